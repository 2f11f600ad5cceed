// Echoing input in messages: one line, printable ASCII only, bounded length.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

namespace sdfbrick {

// The longest piece of input a message echoes, in bytes before escaping.
inline constexpr std::size_t kEchoLimit = 64;

// `text` with every byte outside printable ASCII written as \n, \t, \r, \\ or \xHH (so that
// newlines, terminal escapes, NULs and invalid UTF-8 never reach a message), cut to `limit` bytes
// of input with "..." after the cut.
std::string escaped(std::string_view text, std::size_t limit = kEchoLimit);

// escaped(text) in double quotes (a quote inside is escaped too).
std::string quoted_input(std::string_view text, std::size_t limit = kEchoLimit);

// A long JSON path cut in the middle: its first and last parts with "/..." between, escaped.
std::string shortened_path(std::string_view path, std::size_t limit = 160);

}  // namespace sdfbrick
