// What every fuzz target demands of a refusal: an InputError whose message is one printable line of
// bounded length. Anything else (another exception, a crash, a sanitizer report) is a finding.
#pragma once

#include <cstdlib>
#include <string_view>

namespace sdfbrick::fuzz {

inline void check_refusal(std::string_view message) {
    for (const char c : message)
        if (static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) >= 0x7f) std::abort();
    if (message.size() > 4096) std::abort();
}

}  // namespace sdfbrick::fuzz
