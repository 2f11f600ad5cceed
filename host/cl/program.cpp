#include "cl/program.h"

#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <regex>
#include <sstream>
#include <stdexcept>
#include <system_error>
#include <vector>

#include <fmt/format.h>

#include "cl/device.h"
#include "cl/kernel_source.h"
#include "core/fault.h"
#include "core/hash.h"

namespace sdfbrick::ocl {

namespace {

// Prepended to every program source; the one place where contraction is switched off.
constexpr std::string_view kSourcePrologue = "#pragma OPENCL FP_CONTRACT OFF\n";

// Part of every key and every cache entry: changing the entry format or the build rules changes it.
constexpr std::string_view kCacheFormat = "sdfbrick program cache 1";

// Options that would make results differ between devices or runs.
constexpr std::array<std::string_view, 7> kRefusedOptions = {
    "-cl-fast-relaxed-math", "-cl-mad-enable",       "-cl-unsafe-math-optimizations", "-cl-finite-math-only",
    "-cl-no-signed-zeros",   "-cl-denorms-are-zero", "-cl-single-precision-constant",
};

std::string checksum(std::string_view log, std::string_view binary) {
    return Fnv1a64().add_part(log).add_part(binary).hex();
}

void refuse_unsafe_options(std::string_view extra_options) {
    std::istringstream words{std::string(extra_options)};
    for (std::string word; words >> word;) {
        const bool refused = word.starts_with("-cl-std") ||
                             std::find(kRefusedOptions.begin(), kRefusedOptions.end(), word) != kRefusedOptions.end();
        if (refused) {
            throw std::invalid_argument(fmt::format(
                "build option '{}' is not allowed: sdfbrick builds every kernel with fixed, deterministic "
                "floating-point options",
                word));
        }
    }
}

double ms_since(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

std::string build_log(cl_program program, cl_device_id device) {
    std::size_t size = 0;
    if (clGetProgramBuildInfo(program, device, CL_PROGRAM_BUILD_LOG, 0, nullptr, &size) != CL_SUCCESS) {
        return {};
    }
    std::string log(size, '\0');
    if (clGetProgramBuildInfo(program, device, CL_PROGRAM_BUILD_LOG, size, log.data(), nullptr) != CL_SUCCESS) {
        return {};
    }
    while (!log.empty() && (log.back() == '\0' || log.back() == '\n' || log.back() == ' ')) {
        log.pop_back();
    }
    return log;
}

std::string building(const BuildRecord& record) {
    return fmt::format("building {} for {} with options '{}'", record.kernel_file, record.device_name, record.options);
}

ProgramHandle compile_from_source(const Device& device, const std::string& source, BuildRecord& record) {
    const char* text = source.c_str();
    const std::size_t length = source.size();
    cl_int status = CL_SUCCESS;
    ProgramHandle program(clCreateProgramWithSource(device.context(), 1, &text, &length, &status));
    check(status, fmt::format("creating a program from the source of {} on {}", record.kernel_file,
                              record.device_name));
    const cl_device_id id = device.id();
    if (fault::should_fail(fault::Point::build, device.info().index)) {
        throw ClError(CL_BUILD_PROGRAM_FAILURE, building(record), fault::describe(fault::Point::build, device.info().index));
    }
    status = clBuildProgram(program.get(), 1, &id, record.options.c_str(), nullptr, nullptr);
    record.log = map_log_locations(build_log(program.get(), id), source);
    if (status != CL_SUCCESS) {
        throw ClError(status, building(record),
                      record.log.empty() ? "the compiler gave no build log" : "build log:\n" + record.log);
    }
    record.origin = ProgramOrigin::compiled;
    return program;
}

std::string read_file(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream bytes;
    bytes << in.rdbuf();
    return std::move(bytes).str();
}

void discard(const std::filesystem::path& file, BuildRecord& record, std::string_view why) {
    std::error_code ignored;
    std::filesystem::remove(file, ignored);
    record.cache_note = fmt::format("discarded cache entry {}: {}; built from source", file.string(), why);
}

// The program from the disk cache entry, or an empty handle (entry missing or damaged: then deleted).
ProgramHandle load_from_disk(const Device& device, const std::filesystem::path& file, BuildRecord& record) {
    std::error_code error;
    if (!std::filesystem::is_regular_file(file, error)) {
        return {};
    }
    const std::optional<CacheEntry> entry = decode_cache_entry(read_file(file));
    if (!entry || entry->key != record.key) {
        discard(file, record, "not a complete entry for this key");
        return {};
    }
    const cl_device_id id = device.id();
    const auto* binary = reinterpret_cast<const unsigned char*>(entry->binary.data());
    const std::size_t size = entry->binary.size();
    cl_int binary_status = CL_SUCCESS;
    cl_int status = CL_SUCCESS;
    ProgramHandle program(clCreateProgramWithBinary(device.context(), 1, &id, &size, &binary, &binary_status, &status));
    if (status == CL_SUCCESS) {
        status = binary_status;
    }
    if (status != CL_SUCCESS) {
        discard(file, record, fmt::format("the driver refused the binary ({})", error_name(status)));
        return {};
    }
    status = clBuildProgram(program.get(), 1, &id, record.options.c_str(), nullptr, nullptr);
    if (status != CL_SUCCESS) {
        discard(file, record, fmt::format("building the binary failed ({})", error_name(status)));
        return {};
    }
    record.log = entry->log;
    record.origin = ProgramOrigin::disk_cache;
    return program;
}

std::string program_binary(cl_program program, const BuildRecord& record) {
    const std::string doing = fmt::format("reading the binary of {} built for {}", record.kernel_file, record.device_name);
    std::size_t size = 0;
    check(clGetProgramInfo(program, CL_PROGRAM_BINARY_SIZES, sizeof(size), &size, nullptr), doing);
    std::string binary(size, '\0');
    unsigned char* destination = reinterpret_cast<unsigned char*>(binary.data());
    check(clGetProgramInfo(program, CL_PROGRAM_BINARIES, sizeof(destination), &destination, nullptr), doing);
    return binary;
}

// Writes the entry to a temporary file and renames it into place, so that readers never see a
// partial entry. Failures are noted in the record, not thrown: the program itself is fine.
void store_on_disk(cl_program program, const std::filesystem::path& file, BuildRecord& record) {
    static std::atomic<unsigned> counter{0};
    const std::string binary = program_binary(program, record);
    if (binary.empty()) {
        record.cache_note = "the driver returned no program binary; nothing cached";
        return;
    }
    const std::string bytes = encode_cache_entry({record.key, record.log, binary});
    const std::filesystem::path temporary =
        file.string() + fmt::format(".tmp-{}-{}", static_cast<long>(getpid()), counter++);
    std::error_code error;
    std::filesystem::create_directories(file.parent_path(), error);
    if (!error) {
        std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
        out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
        out.close();
        if (!out) {
            error = std::make_error_code(std::errc::io_error);
        }
    }
    if (!error) {
        std::filesystem::rename(temporary, file, error);
    }
    if (error) {
        std::error_code ignored;
        std::filesystem::remove(temporary, ignored);
        record.cache_note = fmt::format("could not store the binary in {}: {}", file.string(), error.message());
    }
}

}  // namespace

std::string map_log_locations(std::string_view log, std::string_view assembled_source) {
    static const std::regex directive(R"re(^#line (\d{1,9}) "([^"]*)"\r?$)re");
    static const std::regex location(R"re(<[A-Za-z_]+>:(\d{1,9}))re");
    std::vector<std::string> places(1);  // places[n]: "file:line" of assembled line n (1-based), "" if unknown
    std::string file;
    std::size_t next_line = 0;
    std::istringstream lines{std::string(assembled_source)};
    for (std::string line; std::getline(lines, line);) {
        std::smatch match;
        if (std::regex_match(line, match, directive)) {
            places.emplace_back();
            file = match[2].str();
            next_line = std::stoul(match[1].str());
            continue;
        }
        places.push_back(file.empty() ? std::string() : fmt::format("{}:{}", file, next_line));
        ++next_line;
    }
    const std::string text(log);
    std::string mapped;
    auto copied_to = text.cbegin();
    for (auto it = std::sregex_iterator(text.begin(), text.end(), location); it != std::sregex_iterator(); ++it) {
        const std::size_t n = std::stoul((*it)[1].str());
        if (n < places.size() && !places[n].empty()) {
            mapped.append(copied_to, (*it)[0].first);
            mapped += places[n];
            copied_to = (*it)[0].second;
        }
    }
    mapped.append(copied_to, text.cend());
    return mapped;
}

std::string_view to_string(ProgramOrigin origin) {
    switch (origin) {
    case ProgramOrigin::compiled: return "compiled";
    case ProgramOrigin::disk_cache: return "disk cache";
    case ProgramOrigin::memory_cache: return "memory cache";
    }
    return "unknown";
}

std::optional<std::filesystem::path> program_cache_dir() {
    const auto env = [](const char* name) -> std::string_view {
        const char* value = std::getenv(name);
        return value != nullptr ? value : "";
    };
    if (const std::string_view dir = env(kCacheDirEnv); !dir.empty()) {
        if (dir == "off") {
            return std::nullopt;
        }
        return std::filesystem::path(dir);
    }
    if (const std::string_view xdg = env("XDG_CACHE_HOME"); !xdg.empty()) {
        return std::filesystem::path(xdg) / "sdfbrick" / "programs";
    }
    if (const std::string_view home = env("HOME"); !home.empty()) {
        return std::filesystem::path(home) / ".cache" / "sdfbrick" / "programs";
    }
    return std::nullopt;
}

Program build_program(Device& device, std::string_view kernel_file, std::string_view extra_options) {
    const auto start = std::chrono::steady_clock::now();
    refuse_unsafe_options(extra_options);
    const DeviceInfo& info = device.info();

    BuildRecord record;
    record.kernel_file = kernel_file;
    record.device_name = info.name;
    record.correctly_rounded_divide_sqrt = info.correctly_rounded_divide_sqrt;
    record.options = "-cl-std=CL1.2";
    if (record.correctly_rounded_divide_sqrt) {
        record.options += " -cl-fp32-correctly-rounded-divide-sqrt";
    }
    if (info.has_extension("cl_nv_device_attribute_query")) {
        // ptxas --verbose: the build log then holds each kernel's register count (measure/kernel_attributes.h).
        record.options += " -cl-nv-verbose";
    }
    if (!extra_options.empty()) {
        record.options += ' ';
        record.options += extra_options;
    }
    const std::string source = std::string(kSourcePrologue) + load_kernel_source(kernel_file);

    Fnv1a64 key;
    for (std::string_view part : {kCacheFormat, std::string_view(info.platform_name),
                                  std::string_view(info.platform_version), std::string_view(info.name),
                                  std::string_view(info.driver_version), std::string_view(info.device_version),
                                  std::string_view(source), std::string_view(record.options)}) {
        key.add_part(part);
    }
    record.key = key.hex();

    if (const Program* known = device.find_program(record.key)) {
        BuildRecord reused = known->record();
        reused.origin = ProgramOrigin::memory_cache;
        reused.cache_note.clear();
        reused.build_ms = ms_since(start);
        return Program(known->handle(), std::move(reused));
    }

    if (const std::optional<std::filesystem::path> dir = program_cache_dir()) {
        record.cache_file = *dir / (record.key + ".bin");
    }
    ProgramHandle program;
    if (record.cache_file) {
        program = load_from_disk(device, *record.cache_file, record);
    }
    if (!program) {
        program = compile_from_source(device, source, record);
        if (record.cache_file) {
            store_on_disk(program.get(), *record.cache_file, record);
        }
    }
    record.build_ms = ms_since(start);
    Program built(std::move(program), std::move(record));
    device.remember_program(built);
    return built;
}

Kernel make_kernel(const Program& program, const char* name) {
    cl_int status = CL_SUCCESS;
    Kernel kernel(clCreateKernel(program.get(), name, &status));
    if (status != CL_SUCCESS) {
        std::string defined;
        std::size_t size = 0;
        if (clGetProgramInfo(program.get(), CL_PROGRAM_KERNEL_NAMES, 0, nullptr, &size) == CL_SUCCESS && size > 0) {
            defined.resize(size);
            if (clGetProgramInfo(program.get(), CL_PROGRAM_KERNEL_NAMES, size, defined.data(), nullptr) == CL_SUCCESS) {
                defined.resize(std::min(defined.find('\0'), defined.size()));
                for (std::size_t at = defined.find(';'); at != std::string::npos; at = defined.find(';', at)) {
                    defined.replace(at, 1, ", ");
                }
            } else {
                defined.clear();
            }
        }
        const BuildRecord& record = program.record();
        throw ClError(status,
                      fmt::format("creating kernel '{}' from {} on {}", name, record.kernel_file, record.device_name),
                      defined.empty() ? std::string() : fmt::format("the program defines: {}", defined));
    }
    return kernel;
}

std::string encode_cache_entry(const CacheEntry& entry) {
    std::string bytes = fmt::format("{}\nkey {}\nlog {}\nbinary {}\nchecksum {}\n", kCacheFormat, entry.key,
                                    entry.log.size(), entry.binary.size(), checksum(entry.log, entry.binary));
    bytes += entry.log;
    bytes += entry.binary;
    return bytes;
}

std::optional<CacheEntry> decode_cache_entry(std::string_view bytes) {
    // Reads one header line "<label> <value>\n" (or exactly kCacheFormat for an empty label).
    const auto line = [&bytes](std::string_view label) -> std::optional<std::string_view> {
        const std::size_t end = bytes.find('\n');
        if (end == std::string_view::npos) {
            return std::nullopt;
        }
        std::string_view text = bytes.substr(0, end);
        bytes.remove_prefix(end + 1);
        if (label.empty()) {
            return text;
        }
        if (!text.starts_with(label) || text.size() <= label.size() || text[label.size()] != ' ') {
            return std::nullopt;
        }
        return text.substr(label.size() + 1);
    };
    const auto number = [](std::optional<std::string_view> text) -> std::optional<std::size_t> {
        if (!text || text->empty()) {
            return std::nullopt;
        }
        std::size_t value = 0;
        for (char c : *text) {
            if (c < '0' || c > '9' || value > (SIZE_MAX - 9) / 10) {
                return std::nullopt;
            }
            value = value * 10 + static_cast<std::size_t>(c - '0');
        }
        return value;
    };
    if (line("") != kCacheFormat) {
        return std::nullopt;
    }
    const std::optional<std::string_view> key = line("key");
    const std::optional<std::size_t> log_size = number(line("log"));
    const std::optional<std::size_t> binary_size = number(line("binary"));
    const std::optional<std::string_view> sum = line("checksum");
    if (!key || !log_size || !binary_size || !sum || *log_size > bytes.size() ||
        bytes.size() - *log_size != *binary_size) {
        return std::nullopt;
    }
    CacheEntry entry{std::string(*key), std::string(bytes.substr(0, *log_size)),
                     std::string(bytes.substr(*log_size))};
    if (checksum(entry.log, entry.binary) != *sum) {
        return std::nullopt;
    }
    return entry;
}

}  // namespace sdfbrick::ocl
