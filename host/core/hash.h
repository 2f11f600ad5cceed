// FNV-1a 64: a small, stable hash for cache keys and output digests (equal iff bytes are equal,
// up to the usual 64-bit collision odds).
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <string_view>

#include <fmt/format.h>

namespace sdfbrick {

class Fnv1a64 {
public:
    Fnv1a64& add(std::span<const std::byte> bytes) {
        for (std::byte b : bytes) state_ = (state_ ^ static_cast<std::uint8_t>(b)) * 0x100000001B3ull;
        return *this;
    }
    Fnv1a64& add(std::string_view s) { return add(std::as_bytes(std::span(s.data(), s.size()))); }
    // One part of a multi-part key: its length first, so that part boundaries are unambiguous.
    Fnv1a64& add_part(std::string_view s) {
        const std::uint64_t length = s.size();
        return add(std::as_bytes(std::span(&length, 1))).add(s);
    }
    template <class T>
    Fnv1a64& add_values(std::span<const T> values) { return add(std::as_bytes(values)); }
    std::uint64_t value() const { return state_; }
    std::string hex() const { return fmt::format("{:016x}", state_); }

private:
    std::uint64_t state_ = 0xCBF29CE484222325ull;
};

}  // namespace sdfbrick
