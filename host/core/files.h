// File helpers: whole-file reads, and writes that never leave a partial file behind.
#pragma once

#include <cstddef>
#include <filesystem>
#include <functional>
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

// Writes `content` to a temporary file beside `path`, then renames it into place (see write_via_temp).
void write_file_atomic(const std::filesystem::path& path, std::string_view content);

// Calls write(temp_path) where temp_path sits beside `path` and keeps its extension (so writers
// that pick a format by extension still work), then renames temp_path to `path`. If write throws,
// the temporary file is removed and the exception propagates: no partial output is left behind.
// A path that exists and is not a regular file (/dev/null, a FIFO, a terminal) is written in place,
// never replaced; a directory is refused. Every failure is an InputError naming the path.
void write_via_temp(const std::filesystem::path& path, const std::function<void(const std::filesystem::path&)>& write);

// One output file of a command: its path and what writes it (given the path to write to).
struct Output {
    std::filesystem::path path;
    std::function<void(const std::filesystem::path&)> write;
};

// An output holding `content` (see write_file_atomic).
Output text_output(const std::filesystem::path& path, std::string content);

// Writes several outputs as one: each to a temporary file beside its path first, and only when all
// have been written are they renamed into place (a special file is written in place, last). On any
// failure every temporary file is removed: either all outputs are written or none is.
void write_all(const std::vector<Output>& outputs);

// Refuses (InputError naming the path) an output path that cannot be written: a directory, a missing
// or non-directory parent. Commands check all their outputs with it before doing any work.
void check_output_path(const std::filesystem::path& path);
// check_output_path for each of a command's outputs, and refuses two that name one file (the same
// path, or paths that resolve to one file): the later write would silently replace the earlier.
void check_output_paths(const std::vector<std::filesystem::path>& paths);

// Flushes standard output; throws InputError("standard output: write failed: reason") when any
// write to it failed (closed, full, a broken pipe).
void finish_stdout();

// A user configuration file named `name`: $env when it is set ("off": none), else
// $XDG_CONFIG_HOME/sdfbrick/name, else $HOME/.config/sdfbrick/name; std::nullopt when none applies.
std::optional<std::filesystem::path> config_file(const char* env, std::string_view name);

}  // namespace sdfbrick
