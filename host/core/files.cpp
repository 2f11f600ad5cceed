#include "core/files.h"

#include <algorithm>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <cstdlib>
#include <fstream>

#include <fmt/format.h>

#include "core/errors.h"
#include "core/fault.h"

namespace sdfbrick {

namespace {

namespace fs = std::filesystem;

// What a file that is not a regular file is, for messages.
std::string_view kind_of(mode_t mode) {
    if (S_ISDIR(mode)) return "a directory";
    if (S_ISFIFO(mode)) return "a FIFO";
    if (S_ISCHR(mode)) return "a character device";
    if (S_ISBLK(mode)) return "a block device";
    if (S_ISSOCK(mode)) return "a socket";
    return "a special file";
}

// Closes a POSIX file descriptor at scope exit.
struct Fd {
    int fd;
    ~Fd() {
        if (fd >= 0) ::close(fd);
    }
};

}  // namespace

std::string read_file(const fs::path& path, std::size_t max_bytes) {
    const auto fail = [&](std::string_view why) { return InputError(fmt::format("{}: cannot read: {}", path.string(), why)); };
    // O_NONBLOCK: opening a FIFO without a writer must not hang; it is refused below anyway.
    const Fd file{::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC)};
    if (file.fd < 0) throw fail(std::strerror(errno));
    struct stat st{};
    if (::fstat(file.fd, &st) != 0) throw fail(std::strerror(errno));
    if (!S_ISREG(st.st_mode)) throw fail(fmt::format("{}, not a regular file", kind_of(st.st_mode)));
    if (static_cast<std::uint64_t>(st.st_size) > max_bytes)
        throw fail(fmt::format("{} bytes; at most {} are read", st.st_size, max_bytes));
    std::string content;
    content.reserve(static_cast<std::size_t>(st.st_size));
    char chunk[1 << 16];
    while (true) {  // the file may grow while it is read: read to its end, within the limit
        const ssize_t n = ::read(file.fd, chunk, sizeof chunk);
        if (n < 0 && errno == EINTR) continue;
        if (n < 0) throw fail(std::strerror(errno));
        if (n == 0) break;
        if (content.size() + static_cast<std::size_t>(n) > max_bytes) throw fail(fmt::format("more than {} bytes", max_bytes));
        content.append(chunk, static_cast<std::size_t>(n));
    }
    return content;
}

void check_output_path(const fs::path& path) {
    const auto fail = [&](std::string_view why) { return InputError(fmt::format("{}: cannot write: {}", path.string(), why)); };
    std::error_code ec;
    const fs::file_status status = fs::status(path, ec);
    if (status.type() == fs::file_type::directory) throw fail("a directory");
    const fs::path parent = path.has_parent_path() ? path.parent_path() : fs::path(".");
    if (status.type() == fs::file_type::not_found && !fs::is_directory(parent, ec))
        throw fail(fmt::format("{} is not a directory", parent.string()));
    if (::access(status.type() == fs::file_type::not_found ? parent.c_str() : path.c_str(), W_OK) != 0)
        throw fail(std::strerror(errno));
}

namespace {

// Two paths that name one file: the same after resolving what exists of them.
void check_distinct(const std::vector<fs::path>& paths) {
    std::vector<fs::path> seen;
    for (const fs::path& p : paths) {
        std::error_code ec;
        fs::path key = fs::weakly_canonical(p, ec);
        if (ec) key = fs::absolute(p).lexically_normal();
        if (std::find(seen.begin(), seen.end(), key) != seen.end())
            throw InputError(fmt::format("{}: named as two outputs of one command (the second would replace the first)",
                                         p.string()));
        seen.push_back(std::move(key));
    }
}

}  // namespace

void check_output_paths(const std::vector<fs::path>& paths) {
    for (const fs::path& p : paths) check_output_path(p);
    check_distinct(paths);
}

void write_all(const std::vector<Output>& outputs) {
    std::vector<fs::path> paths;
    for (const Output& o : outputs) paths.push_back(o.path);
    check_distinct(paths);
    std::vector<fs::path> temps;  // one per output; empty: a special file, written in place
    try {
        for (const Output& o : outputs) {
            if (fault::should_fail(fault::Point::write))
                throw InputError(o.path.string() + ": cannot write: " + fault::describe(fault::Point::write, std::nullopt));
            std::error_code ec;
            const fs::file_status status = fs::status(o.path, ec);
            if (status.type() == fs::file_type::directory) throw InputError(o.path.string() + ": cannot write: a directory");
            if (fs::exists(status) && status.type() != fs::file_type::regular) {
                temps.emplace_back();  // a device, FIFO or terminal: never replaced by a file
                continue;
            }
            fs::path tmp = o.path;
            tmp.replace_filename(fmt::format(".{}.tmp-{}{}", o.path.stem().string(), ::getpid(), o.path.extension().string()));
            temps.push_back(tmp);
            o.write(tmp);
        }
        for (std::size_t i = 0; i < outputs.size(); ++i) {
            std::error_code ec;
            if (temps[i].empty()) outputs[i].write(outputs[i].path);
            else fs::rename(temps[i], outputs[i].path, ec);
            if (ec) throw InputError(outputs[i].path.string() + ": cannot write: " + ec.message());
        }
    } catch (...) {
        for (const fs::path& tmp : temps) {
            std::error_code ignored;
            if (!tmp.empty()) fs::remove(tmp, ignored);
        }
        throw;
    }
}

void write_via_temp(const fs::path& path, const std::function<void(const fs::path&)>& write) { write_all({{path, write}}); }

Output text_output(const fs::path& path, std::string content) {
    return {path, [path, content = std::move(content)](const fs::path& target) {
                std::ofstream out(target, std::ios::binary | std::ios::trunc);
                if (!out) throw InputError(path.string() + ": cannot write: " + std::strerror(errno));
                out.write(content.data(), static_cast<std::streamsize>(content.size()));
                out.flush();
                if (!out) throw InputError(path.string() + ": write failed: " + std::strerror(errno));
                out.close();
                if (!out) throw InputError(path.string() + ": write failed: " + std::strerror(errno));
            }};
}

void write_file_atomic(const fs::path& path, std::string_view content) { write_all({text_output(path, std::string(content))}); }

void finish_stdout() {
    errno = 0;
    if (std::fflush(stdout) != 0 || std::ferror(stdout)) {
        const int error = errno;
        std::clearerr(stdout);
        throw InputError(fmt::format("standard output: write failed: {}", error ? std::strerror(error) : "I/O error"));
    }
}

std::optional<std::filesystem::path> config_file(const char* env, std::string_view name) {
    if (const char* value = std::getenv(env); value != nullptr && *value != '\0') {
        if (std::string_view(value) == "off") return std::nullopt;
        return std::filesystem::path(value);
    }
    if (const char* xdg = std::getenv("XDG_CONFIG_HOME"); xdg != nullptr && *xdg != '\0')
        return std::filesystem::path(xdg) / "sdfbrick" / name;
    if (const char* home = std::getenv("HOME"); home != nullptr && *home != '\0')
        return std::filesystem::path(home) / ".config" / "sdfbrick" / name;
    return std::nullopt;
}

}  // namespace sdfbrick
