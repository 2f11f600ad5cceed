// Device tree digests against the host's tree_digest of the same bytes.
#include <gtest/gtest.h>

#include <cstring>
#include <vector>

#include "cl/digest.h"
#include "cl/memory_pool.h"
#include "core/hash.h"
#include "core/rng.h"
#include "test_support.h"

namespace sdfbrick {
namespace {

std::vector<std::uint8_t> random_bytes(std::size_t n, std::uint64_t seed) {
    Rng rng(seed);
    std::vector<std::uint8_t> v(n);
    for (auto& b : v) b = static_cast<std::uint8_t>(rng.next() >> 56);
    return v;
}

// The stream a Records selection names, gathered on the host.
std::vector<std::byte> gather(const std::vector<std::uint8_t>& data, const ocl::Records& w) {
    std::vector<std::byte> out;
    for (std::size_t r = 0; r < w.records; ++r)
        for (std::size_t k = 0; k < w.take; ++k) out.push_back(static_cast<std::byte>(data[r * w.stride + w.first + k]));
    return out;
}

TEST(ClDigest, HostTwinIsFnvForOneBlockAndChangesWithEveryByte) {
    const std::vector<std::uint8_t> v = random_bytes(3 * kTreeDigestBlock + 11, 1);
    const auto bytes = std::as_bytes(std::span(v));
    EXPECT_EQ(tree_digest(bytes.first(100)), Fnv1a64().add(bytes.first(100)).value());
    EXPECT_EQ(tree_digest({}), Fnv1a64().value());
    const std::uint64_t whole = tree_digest(bytes);
    EXPECT_NE(whole, Fnv1a64().add(bytes).value());  // several blocks: not the serial hash
    std::vector<std::uint8_t> w = v;
    for (std::size_t at : {std::size_t{0}, kTreeDigestBlock - 1, kTreeDigestBlock, w.size() - 1}) {
        w[at] ^= 1;
        EXPECT_NE(tree_digest(std::as_bytes(std::span(w))), whole) << at;
        w[at] ^= 1;
    }
}

TEST(ClDigest, DeviceEqualsHostOverBytesOfEverySize) {
    ocl::Device& d = test::device();
    ocl::DeviceDigest digest(d);
    // Up to three levels: 600 blocks of digests need a second reduction.
    for (std::size_t n : {std::size_t{0}, std::size_t{1}, std::size_t{3}, kTreeDigestBlock - 1, kTreeDigestBlock,
                          kTreeDigestBlock + 1, 5 * kTreeDigestBlock + 7, 600 * kTreeDigestBlock + 5}) {
        const std::vector<std::uint8_t> v = random_bytes(n, n + 3);
        const ocl::Buffer<std::uint8_t> b(d, std::span<const std::uint8_t>(v));
        EXPECT_EQ(digest.bytes(b), tree_digest(std::as_bytes(std::span(v)))) << n << " bytes";
    }
}

TEST(ClDigest, DeviceEqualsHostOverSelectedBytesOfRecords) {
    ocl::Device& d = test::device();
    ocl::DeviceDigest digest(d);
    const std::vector<std::uint8_t> v = random_bytes(32 * 3000, 9);
    const ocl::Buffer<std::uint8_t> b(d, std::span<const std::uint8_t>(v));
    // Words of each record (coordinates: 12 of 32 bytes), bytes at odd offsets, contiguous records
    // of an odd size (blocks that start off a word).
    for (const ocl::Records w : {ocl::Records{3000, 32, 0, 12}, ocl::Records{3000, 32, 0, 16}, ocl::Records{3000, 32, 5, 3},
                                 ocl::Records{32000, 3, 0, 3}, ocl::Records{1, 32, 4, 8}}) {
        const std::vector<std::byte> stream = gather(v, w);
        EXPECT_EQ(digest.digest(b.get(), w), tree_digest(stream, ocl::DeviceDigest::block_bytes(w.take)))
            << w.records << " records of " << w.stride << ", bytes " << w.first << "+" << w.take;
    }
}

TEST(ClDigest, LeafListsEqualHostAndFollowEveryEntry) {
    ocl::Device& d = test::device();
    ocl::DeviceDigest digest(d);
    Rng rng(5);
    std::vector<SdfBrick> leaves(1500);
    std::vector<cl_uint> lists;
    for (std::size_t i = 0; i < leaves.size(); ++i) {
        SdfBrick& b = leaves[i];
        for (int a = 0; a < 3; ++a) b.coord[a] = static_cast<sdf_i32>(rng.next() % 1000) - 500;
        b.edit_offset = static_cast<sdf_u32>(lists.size());
        b.edit_count = static_cast<sdf_u32>(rng.next() % 9);
        for (sdf_u32 k = 0; k < b.edit_count; ++k) lists.push_back(static_cast<cl_uint>(rng.next() % 4096));
    }
    const auto host = [&](const std::vector<cl_uint>& l) {
        std::vector<std::uint64_t> per_leaf;
        for (const SdfBrick& b : leaves) {
            Fnv1a64 h;
            h.add_values(std::span<const sdf_i32>(b.coord, 3));
            h.add_values(std::span<const cl_uint>(l.data() + b.edit_offset, b.edit_count));
            per_leaf.push_back(h.value());
        }
        return tree_digest(std::as_bytes(std::span(per_leaf)));
    };
    const ocl::Buffer<SdfBrick> lb(d, std::span<const SdfBrick>(leaves));
    ocl::Buffer<cl_uint> ll(d, std::span<const cl_uint>(lists));
    EXPECT_EQ(digest.leaf_lists(lb, ll), host(lists));
    std::vector<cl_uint> changed = lists;
    changed.back() ^= 1;
    ll.write(changed);
    EXPECT_EQ(digest.leaf_lists(lb, ll), host(changed));
    EXPECT_NE(host(changed), host(lists));
}

TEST(ClDigest, BatchedDigestsEqualSingleOnes) {
    ocl::Device& d = test::device();
    ocl::DeviceDigest digest(d);
    std::vector<std::uint64_t> singles;
    std::vector<ocl::Buffer<std::uint8_t>> buffers;
    for (std::size_t n : {std::size_t{0}, std::size_t{10}, 70 * kTreeDigestBlock + 3}) {
        const std::vector<std::uint8_t> v = random_bytes(n, n);
        buffers.emplace_back(d, std::span<const std::uint8_t>(v));
        singles.push_back(tree_digest(std::as_bytes(std::span(v))));
    }
    for (int round = 0; round < 20; ++round)  // more slots than the first results buffer holds
        for (const auto& b : buffers) digest.enqueue(b.get(), {b.bytes(), 1, 0, 1});
    const std::vector<std::uint64_t> all = digest.read_all();
    ASSERT_EQ(all.size(), 60u);
    for (std::size_t i = 0; i < all.size(); ++i) EXPECT_EQ(all[i], singles[i % 3]) << i;
    EXPECT_TRUE(digest.read_all().empty());
}

// Kept memory fits requests up to twice smaller, the smallest first; trim frees what was not taken
// again since the last trim.
TEST(ClMemoryPool, TakesTheSmallestFitAndTrimsWhatWasNotReused) {
    ocl::Device& d = test::device();
    ocl::MemoryPool pool;
    std::size_t capacity = 0;
    EXPECT_FALSE(pool.take(100, capacity));
    const auto make = [&](std::size_t bytes) {
        cl_int status = CL_SUCCESS;
        return ocl::MemObject(clCreateBuffer(d.context(), CL_MEM_READ_WRITE, bytes, nullptr, &status));
    };
    pool.give(make(1000), 1000);
    pool.give(make(400), 400);
    EXPECT_FALSE(pool.take(1001, capacity));
    EXPECT_FALSE(pool.take(150, capacity));  // 400 is more than twice 150
    EXPECT_TRUE(pool.take(300, capacity));
    EXPECT_EQ(capacity, 400u);
    pool.trim();  // 1000 was given back before this trim
    EXPECT_EQ(pool.kept_bytes(), 1000u);
    pool.trim();  // and not taken since
    EXPECT_EQ(pool.kept_bytes(), 0u);
    EXPECT_EQ(ocl::pooled_capacity(100000, 1 << 30) % 8192, 0u);
    EXPECT_GE(ocl::pooled_capacity(100000, 1 << 30), 100000u);
    EXPECT_LE(ocl::pooled_capacity(100000, 1 << 30), 100000u + 100000u / 8);
    EXPECT_EQ(ocl::pooled_capacity(100000, 100000), 100000u);
}

}  // namespace
}  // namespace sdfbrick
