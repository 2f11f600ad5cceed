#include "core/quote.h"

#include <fmt/format.h>

namespace sdfbrick {

namespace {

void append_escaped(std::string& out, std::string_view text, bool in_quotes) {
    for (const char c : text) {
        const auto byte = static_cast<unsigned char>(c);
        switch (c) {
            case '\n': out += "\\n"; break;
            case '\t': out += "\\t"; break;
            case '\r': out += "\\r"; break;
            case '\\': out += "\\\\"; break;
            case '"': out += in_quotes ? "\\\"" : "\""; break;
            default:
                if (byte < 0x20 || byte >= 0x7f) out += fmt::format("\\x{:02x}", byte);
                else out += c;
        }
    }
}

std::string escape(std::string_view text, std::size_t limit, bool in_quotes) {
    std::string out;
    append_escaped(out, text.substr(0, limit), in_quotes);
    if (text.size() > limit) out += "...";
    return out;
}

}  // namespace

std::string escaped(std::string_view text, std::size_t limit) { return escape(text, limit, false); }

std::string quoted_input(std::string_view text, std::size_t limit) { return '"' + escape(text, limit, true) + '"'; }

std::string shortened_path(std::string_view path, std::size_t limit) {
    if (path.size() <= limit) return escaped(path, limit);
    const std::size_t head_end = path.rfind('/', limit / 2);
    const std::size_t tail_start = path.find('/', path.size() - limit / 2);
    const std::string_view head = path.substr(0, head_end == 0 || head_end == std::string_view::npos ? limit / 2 : head_end);
    const std::string_view tail = tail_start == std::string_view::npos ? path.substr(path.size() - limit / 2) : path.substr(tail_start);
    return escaped(head, limit) + "/..." + escaped(tail, limit);
}

}  // namespace sdfbrick
