#include "core/hash.h"

#include <bit>
#include <stdexcept>
#include <vector>

#include <sodium.h>

namespace sdfbrick {

std::uint64_t tree_digest(std::span<const std::byte> stream, std::size_t block_bytes) {
    if (block_bytes == 0) block_bytes = kTreeDigestBlock;
    if (stream.size() <= block_bytes) return Fnv1a64().add(stream).value();
    std::vector<std::uint64_t> level;
    level.reserve((stream.size() + block_bytes - 1) / block_bytes);
    for (std::size_t at = 0; at < stream.size(); at += block_bytes)
        level.push_back(Fnv1a64().add(stream.subspan(at, std::min(block_bytes, stream.size() - at))).value());
    // The digests as little-endian bytes: the host and every OpenCL device this runs on are little-endian
    // (cl/digest.cpp refuses a device that is not).
    static_assert(std::endian::native == std::endian::little, "tree_digest assumes a little-endian host");
    return tree_digest(std::as_bytes(std::span<const std::uint64_t>(level)), kTreeDigestBlock);
}

std::uint64_t SipHash24::value() const {
    static const bool ready = sodium_init() >= 0;
    if (!ready) throw std::runtime_error("libsodium cannot be initialised");
    static_assert(crypto_shorthash_KEYBYTES == 16 && crypto_shorthash_BYTES == 8);
    unsigned char key[16], out[8];
    for (int i = 0; i < 16; ++i) key[i] = static_cast<unsigned char>(key_[i / 8] >> (8 * (i % 8)));
    crypto_shorthash(out, reinterpret_cast<const unsigned char*>(message_.data()), message_.size(), key);
    std::uint64_t v = 0;
    for (int i = 7; i >= 0; --i) v = (v << 8) | out[i];
    return v;
}

}  // namespace sdfbrick
