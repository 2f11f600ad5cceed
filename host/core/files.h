// File helpers: whole-file reads, and writes that never leave a partial file behind.
#pragma once

#include <cstddef>
#include <filesystem>
#include <functional>
#include <iosfwd>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace sdfbrick {

// The largest file read_file reads unless told otherwise (scene files, reports, databases).
inline constexpr std::size_t kMaxInputBytes = std::size_t{256} << 20;

// Reads a whole regular file of at most max_bytes; throws InputError("PATH: cannot read: reason")
// when it cannot, naming what the path is when it is not a regular file (a directory, a FIFO, a
// device). Never blocks on a FIFO.
std::string read_file(const std::filesystem::path& path, std::size_t max_bytes = kMaxInputBytes);

// Whether `path` lies in `folder` or below it once both are absolute with every symbolic link and
// `..` resolved (as far as the path exists: a file not made yet resolves through its folder).
bool lies_within(const std::filesystem::path& path, const std::filesystem::path& folder);

// Writes `content` to `path` as write_all does.
void write_file_atomic(const std::filesystem::path& path, std::string_view content);

// One output file of a command: its path and what writes its bytes. `write` streams the whole file
// to the stream it is given (seekable, so that formats that patch offsets work); every write to it
// is checked, so a full file system or a size limit is an error, never a short file.
struct Output {
    std::filesystem::path path;
    std::function<void(std::ostream&)> write;
};

// An output holding `content`.
Output text_output(const std::filesystem::path& path, std::string content);

// Writes several outputs as one. Each regular-file output goes to a new temporary file beside its
// path, created exclusively (O_EXCL: a link or file planted at any name is never followed or
// reused) under an unpredictable name, written through checked writes, flushed to disk (fsync), and
// only when all have been written are they renamed into place. An existing special file (a device,
// a terminal, a FIFO with a reader) is written in place, last, never replaced; a FIFO without a
// reader is refused, never waited on; a directory is refused. On any failure every temporary file
// is removed and an InputError names the output: either all outputs are written or none is. While
// a temporary file exists, the signal handlers that install_output_cleanup sets remove it.
void write_all(const std::vector<Output>& outputs);

// Makes SIGINT, SIGTERM, SIGHUP and SIGQUIT remove the temporary files of writes in progress before
// the process ends as the signal would end it. The CLI installs it; a library user that handles
// these signals itself need not.
void install_output_cleanup();

// Opens `path` to append lines (a journal such as the sweep cache), creating it when absent:
// refuses a symbolic link at the path itself and anything but a regular file (InputError naming
// the path), so nothing is ever written through a link planted there. Returns the descriptor.
int open_journal(const std::filesystem::path& path);

// Refuses (InputError naming the path) an output path that cannot be written: a directory, a missing
// or non-directory parent. Commands check all their outputs with it before doing any work.
void check_output_path(const std::filesystem::path& path);
// check_output_path for each of a command's outputs, and refuses two that name one file (the same
// path, or paths that resolve to one file): the later write would silently replace the earlier.
void check_output_paths(const std::vector<std::filesystem::path>& paths);

// Refuses (InputError naming the path) a folder for outputs that cannot be used: an existing path
// that is not a directory or cannot be written, or a missing one whose nearest existing parent is
// not a writable directory. Commands check it before any work.
void check_output_folder(const std::filesystem::path& folder);
// Makes the folder (and missing parents) for outputs; InputError naming it when it cannot. Returns
// whether it made the folder itself (so that a failing write can take it away again).
bool make_output_folder(const std::filesystem::path& folder);

// Flushes standard output; throws InputError("standard output: write failed: reason") when any
// write to it failed (closed, full, a broken pipe).
void finish_stdout();

// A user configuration file named `name`: $env when it is set ("off": none), else
// $XDG_CONFIG_HOME/sdfbrick/name, else $HOME/.config/sdfbrick/name; std::nullopt when none applies.
std::optional<std::filesystem::path> config_file(const char* env, std::string_view name);

}  // namespace sdfbrick
