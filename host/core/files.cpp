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
#include <atomic>
#include <csignal>
#include <memory>
#include <sstream>
#include <streambuf>
#include <utility>

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

bool lies_within(const fs::path& path, const fs::path& folder) {
    std::error_code ec;
    const fs::path p = fs::weakly_canonical(fs::absolute(path, ec), ec);
    if (ec) return false;
    const fs::path f = fs::weakly_canonical(fs::absolute(folder, ec), ec);
    if (ec) return false;
    auto pi = p.begin();
    for (auto fi = f.begin(); fi != f.end(); ++fi, ++pi) {
        if (fi->empty() && std::next(fi) == f.end()) break;  // a folder written with a trailing slash
        if (pi == p.end() || *pi != *fi) return false;
    }
    return true;
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

void check_output_folder(const fs::path& folder) {
    const auto fail = [&](std::string_view why) { return InputError(fmt::format("{}: cannot write pictures here: {}", folder.string(), why)); };
    std::error_code ec;
    fs::path existing = folder.empty() ? fs::path(".") : folder;
    while (!fs::exists(fs::symlink_status(existing, ec)) && existing.has_relative_path() && existing.has_parent_path())
        existing = existing.parent_path();
    if (!fs::exists(existing, ec)) existing = ".";
    if (!fs::is_directory(existing, ec))
        throw fail(existing == folder ? std::string("not a directory") : fmt::format("{} is not a directory", existing.string()));
    if (::access(existing.c_str(), W_OK | X_OK) != 0)
        throw fail(existing == folder ? std::string(std::strerror(errno)) : fmt::format("{}: {}", existing.string(), std::strerror(errno)));
}

bool make_output_folder(const fs::path& folder) {
    check_output_folder(folder);
    std::error_code ec;
    if (fs::is_directory(folder, ec)) return false;
    if (!fs::create_directories(folder, ec) && ec)
        throw InputError(fmt::format("{}: cannot make the folder: {}", folder.string(), ec.message()));
    return true;
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

namespace {

// The process's umask, read once before any thread runs: new outputs get 0666 less it, as a plain
// open() would give them (the exclusive temporary file starts at 0600).
const mode_t process_umask = [] {
    const mode_t mask = ::umask(0);
    ::umask(mask);
    return mask;
}();

// Paths of temporary outputs being written, for the signal handler to remove. Fixed storage: the
// handler may only read plain memory and call async-signal-safe functions (unlink).
struct TempSlot {
    std::atomic<bool> claimed{false};  // owned by a registration
    std::atomic<bool> ready{false};    // path holds a whole path the handler may remove
    char path[4096]{};
};
TempSlot temp_slots[64];

// Registers a temporary file for removal on a signal (when a slot is free); unregisters at scope exit.
class TempRegistration {
public:
    explicit TempRegistration(const fs::path& path) {
        const std::string& p = path.native();
        if (p.size() >= sizeof temp_slots[0].path) return;
        for (TempSlot& slot : temp_slots) {
            bool expected = false;
            if (!slot.claimed.compare_exchange_strong(expected, true)) continue;
            std::memcpy(slot.path, p.c_str(), p.size() + 1);
            slot.ready.store(true);
            slot_ = &slot;
            return;
        }
    }
    ~TempRegistration() {
        if (!slot_) return;
        slot_->ready.store(false);
        slot_->claimed.store(false);
    }
    TempRegistration(const TempRegistration&) = delete;
    TempRegistration& operator=(const TempRegistration&) = delete;

private:
    TempSlot* slot_ = nullptr;
};

extern "C" void remove_temps_and_die(int sig) {
    for (TempSlot& slot : temp_slots)
        if (slot.ready.load()) ::unlink(slot.path);
    ::signal(sig, SIG_DFL);
    ::raise(sig);
}

// A stream buffer over a file descriptor whose every write is checked: the first failure is kept
// (errno) and every later operation fails. Seeks flush first, so formats that patch offsets work.
class FdBuf : public std::streambuf {
public:
    explicit FdBuf(int fd) : fd_(fd) { setp(buffer_, buffer_ + sizeof buffer_); }
    int error() const { return error_; }

protected:
    int_type overflow(int_type c) override {
        if (!flush()) return traits_type::eof();
        if (traits_type::eq_int_type(c, traits_type::eof())) return traits_type::not_eof(c);
        *pptr() = traits_type::to_char_type(c);
        pbump(1);
        return c;
    }
    std::streamsize xsputn(const char* s, std::streamsize n) override {
        if (n <= epptr() - pptr()) {
            std::memcpy(pptr(), s, static_cast<std::size_t>(n));
            pbump(static_cast<int>(n));
            return n;
        }
        return flush() && put(s, static_cast<std::size_t>(n)) ? n : 0;
    }
    int sync() override { return flush() ? 0 : -1; }
    pos_type seekoff(off_type off, std::ios_base::seekdir dir, std::ios_base::openmode) override {
        if (!flush()) return pos_type(off_type(-1));
        const int whence = dir == std::ios_base::beg ? SEEK_SET : dir == std::ios_base::cur ? SEEK_CUR : SEEK_END;
        const off_t at = ::lseek(fd_, static_cast<off_t>(off), whence);
        if (at < 0) error_ = errno;
        return pos_type(off_type(at < 0 ? -1 : at));
    }
    pos_type seekpos(pos_type pos, std::ios_base::openmode which) override {
        return seekoff(off_type(pos), std::ios_base::beg, which);
    }

private:
    bool put(const char* data, std::size_t size) {
        if (error_) return false;
        while (size > 0) {
            const ssize_t n = ::write(fd_, data, size);
            if (n < 0 && errno == EINTR) continue;
            if (n <= 0) {
                error_ = n < 0 ? errno : EIO;
                return false;
            }
            data += n;
            size -= static_cast<std::size_t>(n);
        }
        return true;
    }
    bool flush() {
        const bool ok = put(pbase(), static_cast<std::size_t>(pptr() - pbase()));
        setp(buffer_, buffer_ + sizeof buffer_);
        return ok;
    }

    int fd_;
    int error_ = 0;
    char buffer_[1 << 16];
};

[[noreturn]] void fail_write(const fs::path& path, int error) {
    throw InputError(fmt::format("{}: write failed: {}", path.string(), std::strerror(error ? error : EIO)));
}

// Streams `output` to fd through checked writes; throws naming the output when any write failed.
void stream_to(const Output& output, int fd) {
    FdBuf buffer(fd);
    std::ostream stream(&buffer);
    output.write(stream);
    stream.flush();
    if (buffer.error() || !stream) fail_write(output.path, buffer.error());
}

// A new temporary file beside `target`, created exclusively under an unpredictable name that keeps
// the target's extension, registered for removal on a signal.
struct TempFile {
    fs::path path;
    Fd file{-1};
    std::unique_ptr<TempRegistration> registration;
};

std::unique_ptr<TempFile> create_temp_beside(const fs::path& target) {
    const std::string extension = target.extension().string();
    std::string name = (target.parent_path() / fmt::format(".{}.tmp-XXXXXX{}", target.stem().string(), extension)).string();
    auto temp = std::make_unique<TempFile>();
    temp->file.fd = ::mkostemps(name.data(), static_cast<int>(extension.size()), O_CLOEXEC);
    if (temp->file.fd < 0)
        throw InputError(fmt::format("{}: cannot write: {}", target.string(), std::strerror(errno)));
    temp->path = name;
    temp->registration = std::make_unique<TempRegistration>(temp->path);
    ::fchmod(temp->file.fd, 0666 & ~process_umask);
    return temp;
}

// Writes a regular-file output to its temporary file, through to the disk.
void write_temp(const Output& output, TempFile& temp) {
    stream_to(output, temp.file.fd);
    if (fault::should_fail(fault::Point::signal)) ::raise(SIGTERM);
    if (::fsync(temp.file.fd) != 0) fail_write(output.path, errno);
    const int fd = std::exchange(temp.file.fd, -1);
    if (::close(fd) != 0) fail_write(output.path, errno);
}

// Writes an output into an existing special file in place. A FIFO is opened without blocking: with
// no reader it is refused. The bytes are made in memory first, since the stream cannot seek there.
void write_special(const Output& output) {
    const Fd file{::open(output.path.c_str(), O_WRONLY | O_NONBLOCK | O_CLOEXEC)};
    if (file.fd < 0 && errno == ENXIO)
        throw InputError(fmt::format("{}: cannot write: a FIFO with no reader (nothing would ever read it)",
                                     output.path.string()));
    if (file.fd < 0) throw InputError(fmt::format("{}: cannot write: {}", output.path.string(), std::strerror(errno)));
    ::fcntl(file.fd, F_SETFL, ::fcntl(file.fd, F_GETFL) & ~O_NONBLOCK);
    std::stringstream bytes;
    output.write(bytes);
    if (!bytes) fail_write(output.path, EIO);
    stream_to({output.path, [&](std::ostream& os) { os << bytes.rdbuf(); }}, file.fd);
}

}  // namespace

void write_all(const std::vector<Output>& outputs) {
    std::vector<fs::path> paths;
    for (const Output& o : outputs) paths.push_back(o.path);
    check_distinct(paths);
    std::vector<std::unique_ptr<TempFile>> temps;  // one per output; null: a special file, written in place
    try {
        for (const Output& o : outputs) {
            if (fault::should_fail(fault::Point::write))
                throw InputError(o.path.string() + ": cannot write: " + fault::describe(fault::Point::write, std::nullopt));
            std::error_code ec;
            const fs::file_status status = fs::status(o.path, ec);
            if (status.type() == fs::file_type::directory) throw InputError(o.path.string() + ": cannot write: a directory");
            if (fs::exists(status) && status.type() != fs::file_type::regular) {
                temps.emplace_back();
                continue;
            }
            temps.push_back(create_temp_beside(o.path));
            write_temp(o, *temps.back());
        }
        for (std::size_t i = 0; i < outputs.size(); ++i) {
            if (!temps[i]) continue;
            if (::rename(temps[i]->path.c_str(), outputs[i].path.c_str()) != 0) fail_write(outputs[i].path, errno);
            temps[i]->path.clear();
        }
        for (std::size_t i = 0; i < outputs.size(); ++i)
            if (!temps[i]) write_special(outputs[i]);
    } catch (...) {
        for (const auto& temp : temps)
            if (temp && !temp->path.empty()) ::unlink(temp->path.c_str());
        throw;
    }
}

void install_output_cleanup() {
    struct sigaction action{};
    action.sa_handler = remove_temps_and_die;
    sigemptyset(&action.sa_mask);
    for (const int sig : {SIGINT, SIGTERM, SIGHUP, SIGQUIT}) ::sigaction(sig, &action, nullptr);
}

int open_journal(const fs::path& path) {
    const int fd = ::open(path.c_str(), O_WRONLY | O_APPEND | O_CREAT | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC, 0666);
    if (fd < 0 && errno == ELOOP)
        throw InputError(fmt::format("{}: cannot write: a symbolic link (nothing is written through a link here)", path.string()));
    if (fd < 0) throw InputError(fmt::format("{}: cannot write: {}", path.string(), std::strerror(errno)));
    struct stat st{};
    if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
        const std::string what = S_ISREG(st.st_mode) ? std::strerror(errno) : fmt::format("{}, not a regular file", kind_of(st.st_mode));
        ::close(fd);
        throw InputError(fmt::format("{}: cannot write: {}", path.string(), what));
    }
    ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) & ~O_NONBLOCK);
    return fd;
}

Output text_output(const fs::path& path, std::string content) {
    return {path, [content = std::move(content)](std::ostream& out) { out.write(content.data(), static_cast<std::streamsize>(content.size())); }};
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
