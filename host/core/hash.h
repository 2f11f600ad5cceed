// FNV-1a 64: a small, stable hash for cache keys and output digests (equal iff bytes are equal,
// up to the usual 64-bit collision odds). SipHash-2-4: a keyed hash (a MAC) for what must not be
// forged by someone who does not hold the key (program cache entries).
#pragma once

#include <array>
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

// The tree digest: a stream of bytes cut into blocks of block_bytes (the last may be shorter), each
// block's FNV-1a 64, and the same again over those digests (8 bytes each, little-endian, blocks of
// kTreeDigestBlock bytes) until one value is left. A stream of one block is its FNV-1a 64; an empty
// stream is FNV-1a 64's offset basis. The blocks can be hashed in parallel, so a device computes
// the same value over bytes it keeps (cl/digest.h, kernels/digest.cl): equal iff the streams are
// equal (up to the usual 64-bit collision odds).
inline constexpr std::size_t kTreeDigestBlock = 4096;
std::uint64_t tree_digest(std::span<const std::byte> stream, std::size_t block_bytes = kTreeDigestBlock);

// SipHash-2-4 (Aumasson and Bernstein) with a 128-bit key, fed incrementally: libsodium's
// crypto_shorthash over the bytes added (k0 and k1 as the key's little-endian halves).
class SipHash24 {
public:
    SipHash24(std::uint64_t k0, std::uint64_t k1) : key_{k0, k1} {}

    SipHash24& add(std::string_view s) {
        message_.append(s);
        return *this;
    }
    // One part of a multi-part message: its length first, so that part boundaries are unambiguous.
    SipHash24& add_part(std::string_view s) {
        std::uint64_t length = s.size();
        char bytes[8];
        for (char& b : bytes) {
            b = static_cast<char>(length & 0xff);
            length >>= 8;
        }
        return add(std::string_view(bytes, 8)).add(s);
    }
    std::uint64_t value() const;
    std::string hex() const { return fmt::format("{:016x}", value()); }

private:
    std::array<std::uint64_t, 2> key_;
    std::string message_;
};

}  // namespace sdfbrick
