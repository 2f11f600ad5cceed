#include "cl/kernel_source.h"

#include <cstdlib>
#include <mutex>
#include <regex>
#include <set>
#include <sstream>
#include <stdexcept>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "core/errors.h"
#include "core/files.h"

namespace sdfbrick::ocl {

namespace {

// The largest kernel source file read from a kernel directory.
constexpr std::size_t kMaxKernelSourceBytes = std::size_t{4} << 20;

std::mutex kernel_dir_mutex;
std::optional<std::filesystem::path> kernel_dir_override;
// Sets added by add_kernel_sources (guarded by kernel_dir_mutex); a function so that it exists before
// any static initialiser of another file registers a set.
std::vector<const KernelSources*>& extra_sources() {
    static std::vector<const KernelSources*> sets;
    return sets;
}

std::optional<std::string_view> find_extra(std::string_view file) {
    const std::lock_guard lock(kernel_dir_mutex);
    for (const KernelSources* set : extra_sources())
        for (const auto& [name, text] : *set)
            if (name == file) return text;
    return std::nullopt;
}

struct KernelDir {
    std::filesystem::path path;
    const char* set_by;  // for messages
};

std::optional<KernelDir> current_kernel_dir() {
    {
        const std::lock_guard lock(kernel_dir_mutex);
        if (kernel_dir_override) {
            return KernelDir{*kernel_dir_override, "set_kernel_dir"};
        }
    }
    const char* env = std::getenv(kKernelDirEnv);
    if (env != nullptr && *env != '\0') {
        return KernelDir{env, kKernelDirEnv};
    }
    return std::nullopt;
}

// included_from: "a.cl:3" when the file is named by an #include line, empty for the root file.
std::string read_kernel_file(std::string_view file, std::string_view included_from) {
    const std::string who = included_from.empty() ? std::string() : fmt::format(" (included from {})", included_from);
    if (const std::optional<KernelDir> dir = current_kernel_dir()) {
        const std::filesystem::path path = dir->path / std::filesystem::path(file);
        std::error_code ec;
        if (!std::filesystem::exists(std::filesystem::symlink_status(path, ec))) {
            if (const auto extra = find_extra(file)) return std::string(*extra);
            throw std::runtime_error(fmt::format("kernel source '{}'{} not found: cannot read {} (kernel directory "
                                                 "set by {})",
                                                 file, who, path.string(), dir->set_by));
        }
        // Regular files of a bounded size only, as for every other input: a link to /dev/zero or a
        // FIFO is refused, never read until memory runs out or forever.
        try {
            return read_file(path, kMaxKernelSourceBytes);
        } catch (const InputError& e) {
            throw InputError(fmt::format("kernel source '{}'{}: {} (kernel directory set by {})", file, who, e.what(), dir->set_by));
        }
    }
    std::vector<std::string_view> names;
    for (const auto& [name, text] : embedded_kernel_sources()) {
        if (name == file) {
            return std::string(text);
        }
        names.push_back(name);
    }
    if (const auto extra = find_extra(file)) return std::string(*extra);
    throw std::runtime_error(fmt::format(
        "kernel source '{}'{} not found among the kernels embedded in this build ({}); set {} or call "
        "set_kernel_dir to read kernels from a directory",
        file, who, fmt::join(names, ", "), kKernelDirEnv));
}

// Appends file, expanded, to out.
void expand(std::string_view file, std::string_view included_from, std::set<std::string, std::less<>>& included,
            std::string& out) {
    static const std::regex include_line(R"re(^\s*#\s*include\s*"([^"]+)"\s*(//.*|/\*.*)?\r?$)re");
    const std::string text = read_kernel_file(file, included_from);
    out += fmt::format("#line 1 \"{}\"\n", file);
    std::istringstream lines(text);
    std::size_t line_number = 0;
    for (std::string line; std::getline(lines, line);) {
        ++line_number;
        std::smatch match;
        if (!std::regex_match(line, match, include_line)) {
            out += line;
            out += '\n';
            continue;
        }
        const std::string name = match[1].str();
        if (!included.insert(name).second) {
            out += fmt::format("// #include \"{}\": already included above\n", name);
            continue;
        }
        expand(name, fmt::format("{}:{}", file, line_number), included, out);
        out += fmt::format("#line {} \"{}\"\n", line_number + 1, file);
    }
}

}  // namespace

void add_kernel_sources(const KernelSources& sources) {
    const std::lock_guard lock(kernel_dir_mutex);
    extra_sources().push_back(&sources);
}

void set_kernel_dir(std::optional<std::filesystem::path> dir) {
    const std::lock_guard lock(kernel_dir_mutex);
    kernel_dir_override = std::move(dir);
}

std::optional<std::filesystem::path> kernel_dir() {
    if (std::optional<KernelDir> dir = current_kernel_dir()) {
        return std::move(dir->path);
    }
    return std::nullopt;
}

std::string load_kernel_source(std::string_view file) {
    std::set<std::string, std::less<>> included = {std::string(file)};
    std::string out;
    expand(file, {}, included, out);
    return out;
}

}  // namespace sdfbrick::ocl
