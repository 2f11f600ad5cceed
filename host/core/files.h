// File helpers: whole-file reads, and writes that never leave a partial file behind.
#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <string_view>

namespace sdfbrick {

// Reads a whole file; throws InputError("PATH: cannot read: reason") when it cannot.
std::string read_file(const std::filesystem::path& path);

// Writes `content` to a temporary file beside `path`, then renames it into place.
void write_file_atomic(const std::filesystem::path& path, std::string_view content);

// Calls write(temp_path) where temp_path sits beside `path` and keeps its extension (so writers
// that pick a format by extension still work), then renames temp_path to `path`. If write throws,
// the temporary file is removed and the exception propagates: no partial output is left behind.
void write_via_temp(const std::filesystem::path& path, const std::function<void(const std::filesystem::path&)>& write);

}  // namespace sdfbrick
