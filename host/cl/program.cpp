#include "cl/program.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cerrno>
#include <charconv>
#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <cstdio>
#include <fstream>
#include <functional>
#include <memory>
#include <mutex>
#include <regex>
#include <sstream>
#include <stdexcept>
#include <system_error>
#include <vector>

#include <fmt/format.h>
#include <sodium.h>

#include "cl/device.h"
#include "cl/kernel_source.h"
#include "core/fault.h"
#include "core/hash.h"

namespace sdfbrick::ocl {

namespace {

// Prepended to every program source; the one place where contraction is switched off.
constexpr std::string_view kSourcePrologue = "#pragma OPENCL FP_CONTRACT OFF\n";

// PoCL's CPU drivers keep one process-wide cache of loaded kernel binaries, keyed by the program's
// hash, and (PoCL 3) release an entry found by hash and work-group size alone: when two PoCL devices
// run the same kernel at once with different launch specialisations (global offset zero or not, a
// small grid or not), one device's release can hit the other's entry and PoCL aborts. An empty
// kernel named after the device makes every PoCL device's program (and so its hash) its own; the
// kernels themselves are unchanged.
std::string device_marker(const DeviceInfo& info) {
    if (info.platform_name != "Portable Computing Language") return "";
    return fmt::format("\n__kernel void sdfbrick_device_{}(void) {{}}\n", info.index);
}

// Part of every key and every cache entry: changing the entry format or the build rules changes it.
constexpr std::string_view kCacheFormat = "sdfbrick program cache 2";

// The file in the cache directory that holds the secret key of the entries' MACs.
constexpr std::string_view kSecretFile = "secret";

// Options that would make results differ between devices or runs.
constexpr std::array<std::string_view, 7> kRefusedOptions = {
    "-cl-fast-relaxed-math", "-cl-mad-enable",       "-cl-unsafe-math-optimizations", "-cl-finite-math-only",
    "-cl-no-signed-zeros",   "-cl-denorms-are-zero", "-cl-single-precision-constant",
};

std::string mac(const CacheSeal& seal, const CacheEntry& entry) {
    return SipHash24(seal.k0, seal.k1)
        .add_part(kCacheFormat)
        .add_part(seal.identity)
        .add_part(entry.key)
        .add_part(entry.log)
        .add_part(entry.binary)
        .hex();
}

// The kernel names a built program reports (CL_PROGRAM_KERNEL_NAMES: "a;b;c"), empty if it cannot say.
std::string kernel_names(cl_program program) {
    std::size_t size = 0;
    if (clGetProgramInfo(program, CL_PROGRAM_KERNEL_NAMES, 0, nullptr, &size) != CL_SUCCESS || size == 0) return {};
    std::string names(size, '\0');
    if (clGetProgramInfo(program, CL_PROGRAM_KERNEL_NAMES, size, names.data(), nullptr) != CL_SUCCESS) return {};
    names.resize(std::min(names.find('\0'), names.size()));
    return names;
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

// Runs build() with the process's standard error sent to a temporary file, and returns what was
// printed there (trailing newlines removed): some compilers (PoCL's) print diagnostics such as
// "3 errors generated." on standard error, where they would come before the one-line error message.
// Builds are serialised while standard error is redirected.
std::string capturing_stderr(const std::function<void()>& build) {
    static std::mutex mutex;
    const std::lock_guard lock(mutex);
    std::fflush(stderr);
    const std::unique_ptr<FILE, int (*)(FILE*)> capture(std::tmpfile(), &std::fclose);
    const int saved = capture ? ::dup(STDERR_FILENO) : -1;
    if (saved < 0 || ::dup2(::fileno(capture.get()), STDERR_FILENO) < 0) {
        if (saved >= 0) ::close(saved);
        build();
        return {};
    }
    const auto restore = [&] {
        std::fflush(stderr);
        ::dup2(saved, STDERR_FILENO);
        ::close(saved);
    };
    try {
        build();
    } catch (...) {
        restore();
        throw;
    }
    restore();
    std::string printed;
    std::rewind(capture.get());
    for (int c; (c = std::fgetc(capture.get())) != EOF;) printed += static_cast<char>(c);
    while (!printed.empty() && (printed.back() == '\n' || printed.back() == ' ')) printed.pop_back();
    return printed;
}

// One line for a failed build: how many errors the log holds and the first of them.
std::string build_failure_summary(std::string_view log) {
    std::size_t errors = 0;
    std::string first;
    std::istringstream lines{std::string(log)};
    for (std::string line; std::getline(lines, line);) {
        if (line.find("error:") == std::string::npos) continue;
        if (errors++ == 0) first = line;
    }
    if (errors == 0) return "the build failed (see the log below)";
    return fmt::format("{} error{}, the first: {}", errors, errors == 1 ? "" : "s", first);
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
    const std::string printed =
        capturing_stderr([&] { status = clBuildProgram(program.get(), 1, &id, record.options.c_str(), nullptr, nullptr); });
    record.log = map_log_locations(build_log(program.get(), id), source);
    if (status != CL_SUCCESS) {
        std::string log = record.log;
        if (!printed.empty() && log.find(printed) == std::string::npos) log += (log.empty() ? "" : "\n") + printed;
        throw ClError(status, building(record),
                      log.empty() ? "the compiler gave no build log" : build_failure_summary(log) + "\nbuild log:\n" + log);
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
    record.cache_note += fmt::format("{}discarded cache entry {}: {}; built from source", record.cache_note.empty() ? "" : "; ",
                                     file.string(), why);
}

// Whether `names` (a program's "a;b;c") is a non-empty list of kernels that `source` declares
// ("__kernel void a(", attributes allowed between): a binary of another program is refused.
bool declares_all(std::string_view source, std::string_view names) {
    static const std::regex declared(R"re(\b(?:__)?kernel\s+(?:__attribute__\s*\(\([^;{]*?\)\)\s*)*void\s+([A-Za-z_]\w*)\s*\()re");
    std::vector<std::string> known;
    const std::string text(source);
    for (auto it = std::sregex_iterator(text.begin(), text.end(), declared); it != std::sregex_iterator(); ++it) {
        known.push_back((*it)[1].str());
    }
    std::istringstream list{std::string(names)};
    std::size_t count = 0;
    for (std::string name; std::getline(list, name, ';'); ++count) {
        if (std::find(known.begin(), known.end(), name) == known.end()) return false;
    }
    return count > 0;
}

// The program from the disk cache entry, or an empty handle (entry missing, damaged, forged, or for
// another program: then deleted). Nothing reaches the driver unless its MAC verifies.
ProgramHandle load_from_disk(const Device& device, const std::filesystem::path& file, const CacheSeal& seal,
                             std::string_view source, BuildRecord& record) {
    std::error_code error;
    if (!std::filesystem::is_regular_file(file, error)) {
        return {};
    }
    const std::optional<CacheEntry> entry = decode_cache_entry(read_file(file), seal);
    if (!entry || entry->key != record.key) {
        discard(file, record, "not an entry made by this user for this program");
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
    if (const std::string names = kernel_names(program.get()); !declares_all(source, names)) {
        discard(file, record, fmt::format("the binary defines kernels '{}', which the source does not declare", names));
        return {};
    }
    record.log = entry->log;
    record.origin = ProgramOrigin::disk_cache;
    return program;
}

// The binary of a program of one device (every context holds one device: cl/device.h).
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
void store_on_disk(cl_program program, const std::filesystem::path& file, const CacheSeal& seal, BuildRecord& record) {
    static std::atomic<unsigned> counter{0};
    std::string binary;
    try {
        binary = program_binary(program, record);
    } catch (const ClError& e) {
        record.cache_note = fmt::format("the program binary could not be read ({}); nothing cached", e.what());
        return;
    }
    if (binary.empty()) {
        record.cache_note = "the driver returned no program binary; nothing cached";
        return;
    }
    const std::string bytes = encode_cache_entry({record.key, record.log, binary}, seal);
    const std::filesystem::path temporary =
        file.string() + fmt::format(".tmp-{}-{}", static_cast<long>(getpid()), counter++);
    std::error_code error;
    {
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

using SecretKey = std::pair<std::uint64_t, std::uint64_t>;

// The folder that holds the cache's entries and the key that seals them.
struct CacheDir {
    std::filesystem::path folder;
    SecretKey key;
};

// The key in a secret file: a regular file of this user, private, 32 hex digits and a newline.
std::optional<SecretKey> read_secret(const std::filesystem::path& secret) {
    struct stat sst{};
    if (::lstat(secret.c_str(), &sst) != 0 || !S_ISREG(sst.st_mode) || sst.st_uid != ::geteuid() ||
        (sst.st_mode & 077) != 0)
        return std::nullopt;
    const std::string text = read_file(secret);
    std::uint64_t k[2] = {0, 0};
    const bool valid = text.size() == 33 && text[32] == '\n' &&
                       std::from_chars(text.data(), text.data() + 16, k[0], 16).ptr == text.data() + 16 &&
                       std::from_chars(text.data() + 16, text.data() + 32, k[1], 16).ptr == text.data() + 32;
    if (!valid) return std::nullopt;
    return SecretKey{k[0], k[1]};
}

// Makes a new secret from random bytes. Where there is none yet, the first writer wins (a hard link
// fails when the file exists) and the others read its key: threads and processes that start on an
// empty cache at once agree on one key. A file at the secret's name that is not such a key is never
// replaced (it may be someone's own file): the cache is not used.
std::optional<SecretKey> create_secret(const std::filesystem::path& secret) {
    static std::atomic<unsigned> counter{0};
    static const bool sodium_ready = sodium_init() >= 0;
    if (!sodium_ready) return std::nullopt;
    SecretKey k;
    randombytes_buf(&k, sizeof k);
    const std::filesystem::path temporary =
        secret.string() + fmt::format(".tmp-{}-{}", static_cast<long>(getpid()), counter++);
    const int fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0600);
    const std::string line = fmt::format("{:016x}{:016x}\n", k.first, k.second);
    const bool written = fd >= 0 && ::write(fd, line.data(), line.size()) == static_cast<ssize_t>(line.size());
    if (fd >= 0) ::close(fd);
    const bool placed = written && ::link(temporary.c_str(), secret.c_str()) == 0;
    const bool taken = written && !placed && errno == EEXIST;
    std::error_code ignored;
    if (fd >= 0) std::filesystem::remove(temporary, ignored);
    if (taken) return read_secret(secret);  // another writer's key, or not a key at all
    return placed ? std::optional<SecretKey>(k) : std::nullopt;
}

// A folder this user owns and nobody else may enter: mode 0700, not a symbolic link.
bool private_folder(const std::filesystem::path& dir) {
    struct stat st{};
    return ::lstat(dir.c_str(), &st) == 0 && S_ISDIR(st.st_mode) && st.st_uid == ::geteuid() && (st.st_mode & 077) == 0;
}

// Where the cache's entries go: `dir` itself when it is a private folder of this user (made so when
// it does not exist), else a private subfolder "sdfbrick-UID" made inside it (a shared folder such as
// /tmp). An existing folder is never changed (no chmod) and no file in it is replaced or removed.
// The seal key is held in FOLDER/secret (mode 0600, made with random bytes on first use).
// std::nullopt, with the reason in `note`, when no such folder can be had.
std::optional<CacheDir> open_cache_dir(const std::filesystem::path& dir, std::string& note) {
    std::error_code ignored;
    if (!std::filesystem::exists(dir, ignored)) {
        std::filesystem::create_directories(dir.parent_path(), ignored);
        ::mkdir(dir.c_str(), 0700);
    }
    std::filesystem::path folder = std::filesystem::is_symlink(dir, ignored) ? std::filesystem::canonical(dir, ignored) : dir;
    if (!private_folder(folder)) {
        folder = dir / fmt::format("sdfbrick-{}", static_cast<long>(::geteuid()));
        ::mkdir(folder.c_str(), 0700);
        if (!private_folder(folder)) {
            note = fmt::format("cache directory {} is not a private folder of this user, nor is {}: disk cache not used",
                               dir.string(), folder.string());
            return std::nullopt;
        }
    }
    const std::filesystem::path secret = folder / kSecretFile;
    if (auto key = read_secret(secret)) return CacheDir{folder, *key};
    if (auto key = create_secret(secret)) return CacheDir{folder, *key};
    note = fmt::format("{} is not a cache key this program made (or cannot be written): disk cache not used", secret.string());
    return std::nullopt;
}

// What build_program builds: the record's options and key, the source, and the program's identity
// (everything the key hashes).
struct ProgramInputs {
    BuildRecord record;
    std::string source;
    std::string identity;
};

ProgramInputs program_inputs(const Device& device, std::string_view kernel_file, std::string_view extra_options) {
    refuse_unsafe_options(extra_options);
    const DeviceInfo& info = device.info();
    ProgramInputs in;
    BuildRecord& record = in.record;
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
    in.source = std::string(kSourcePrologue) + load_kernel_source(kernel_file) + device_marker(info);
    for (std::string_view part : {kCacheFormat, std::string_view(info.platform_name),
                                  std::string_view(info.platform_version), std::string_view(info.name),
                                  std::string_view(info.driver_version), std::string_view(info.device_version),
                                  std::string_view(in.source), std::string_view(record.options)}) {
        const std::uint64_t length = part.size();
        in.identity.append(reinterpret_cast<const char*>(&length), sizeof length);
        in.identity.append(part);
    }
    record.key = Fnv1a64().add(in.identity).hex();
    return in;
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

std::optional<CacheSeal> cache_seal(const Device& device, std::string_view kernel_file, std::string_view extra_options) {
    const std::optional<std::filesystem::path> dir = program_cache_dir();
    std::string note;
    const auto cache = dir ? open_cache_dir(*dir, note) : std::nullopt;
    if (!cache) return std::nullopt;
    return CacheSeal{cache->key.first, cache->key.second, program_inputs(device, kernel_file, extra_options).identity};
}

std::string register_cap_option(const DeviceInfo& device, int registers) {
    if (registers <= 0 || !device.has_extension("cl_nv_compiler_options")) return "";
    return fmt::format(" -cl-nv-maxrregcount={}", registers);
}

Program build_program(Device& device, std::string_view kernel_file, std::string_view extra_options) {
    const auto start = std::chrono::steady_clock::now();
    const auto reuse = [&](const Program& known) {
        BuildRecord reused = known.record();
        reused.origin = ProgramOrigin::memory_cache;
        reused.cache_note.clear();
        reused.build_ms = ms_since(start);
        return Program(known.handle(), std::move(reused));
    };
    // Embedded sources do not change: a request made before names its program without the source.
    const bool embedded = !kernel_dir().has_value();
    const std::string request = fmt::format("{}\n{}", kernel_file, extra_options);
    if (const std::string* key = embedded ? device.program_key(request) : nullptr)
        if (const Program* known = device.find_program(*key)) return reuse(*known);

    ProgramInputs in = program_inputs(device, kernel_file, extra_options);
    BuildRecord& record = in.record;
    if (embedded) device.remember_program_key(request, record.key);
    if (const Program* known = device.find_program(record.key)) return reuse(*known);

    std::optional<CacheSeal> seal;
    if (const std::optional<std::filesystem::path> dir = program_cache_dir()) {
        if (const auto cache = open_cache_dir(*dir, record.cache_note)) {
            record.cache_file = cache->folder / (record.key + ".bin");
            seal = CacheSeal{cache->key.first, cache->key.second, in.identity};
        }
    }
    ProgramHandle program;
    if (seal) {
        program = load_from_disk(device, *record.cache_file, *seal, in.source, record);
    }
    if (!program) {
        program = compile_from_source(device, in.source, record);
        if (seal) {
            store_on_disk(program.get(), *record.cache_file, *seal, record);
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
        std::string defined = kernel_names(program.get());
        for (std::size_t at = defined.find(';'); at != std::string::npos; at = defined.find(';', at)) {
            defined.replace(at, 1, ", ");
        }
        const BuildRecord& record = program.record();
        throw ClError(status,
                      fmt::format("creating kernel '{}' from {} on {}", name, record.kernel_file, record.device_name),
                      defined.empty() ? std::string() : fmt::format("the program defines: {}", defined));
    }
    return kernel;
}

std::size_t kernel_work_group_limit(const Device& device, cl_kernel kernel, std::string_view name) {
    std::size_t limit = 0;
    check(clGetKernelWorkGroupInfo(kernel, device.id(), CL_KERNEL_WORK_GROUP_SIZE, sizeof(limit), &limit, nullptr),
          fmt::format("querying the work-group size limit of {}", name));
    return limit;
}

std::uint64_t kernel_local_bytes(const Device& device, cl_kernel kernel, std::string_view name) {
    cl_ulong bytes = 0;
    check(clGetKernelWorkGroupInfo(kernel, device.id(), CL_KERNEL_LOCAL_MEM_SIZE, sizeof(bytes), &bytes, nullptr),
          fmt::format("querying the local memory of {}", name));
    return bytes;
}

std::string encode_cache_entry(const CacheEntry& entry, const CacheSeal& seal) {
    std::string bytes = fmt::format("{}\nkey {}\nlog {}\nbinary {}\nmac {}\n", kCacheFormat, entry.key,
                                    entry.log.size(), entry.binary.size(), mac(seal, entry));
    bytes += entry.log;
    bytes += entry.binary;
    return bytes;
}

std::optional<CacheEntry> decode_cache_entry(std::string_view bytes, const CacheSeal& seal) {
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
        if (!text.starts_with(label) || text.size() < label.size() + 1 || text[label.size()] != ' ') {
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
    const std::optional<std::string_view> sum = line("mac");
    if (!key || !log_size || !binary_size || !sum || *log_size > bytes.size() ||
        bytes.size() - *log_size != *binary_size) {
        return std::nullopt;
    }
    CacheEntry entry{std::string(*key), std::string(bytes.substr(0, *log_size)),
                     std::string(bytes.substr(*log_size))};
    if (mac(seal, entry) != *sum) {
        return std::nullopt;
    }
    return entry;
}

}  // namespace sdfbrick::ocl
