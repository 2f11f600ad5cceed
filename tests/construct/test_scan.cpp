// The device exclusive prefix sum (host/construct/scan.h, kernels/scan.cl) against std::exclusive_scan:
// lengths around the block size (4 * local size values per work-group), a multi-level length, in
// place, and the 2^32 overflow checks.
#include <algorithm>
#include <bit>
#include <cstdint>
#include <numeric>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "construct/scan.h"
#include "core/errors.h"
#include "core/rng.h"
#include "test_support.h"

namespace sdfbrick {
namespace {

using construct::Scan;

std::vector<cl_uint> random_values(std::size_t n, std::uint64_t seed, std::uint32_t below) {
    Rng rng(seed);
    std::vector<cl_uint> v(n);
    for (auto& x : v) x = static_cast<cl_uint>(rng.next() % below);
    return v;
}

std::uint64_t host_total(const std::vector<cl_uint>& v) {
    std::uint64_t t = 0;
    for (cl_uint x : v) t += x;
    return t;
}

std::vector<cl_uint> host_exclusive(const std::vector<cl_uint>& v) {
    std::vector<cl_uint> out(v.size());
    std::exclusive_scan(v.begin(), v.end(), out.begin(), cl_uint{0});
    return out;
}

// Scans n values in a buffer of n + 7 elements (out of place and in place) and checks the result,
// the total, and that the elements beyond n are untouched.
void check_scan(Scan& scan, std::size_t n, std::uint64_t seed) {
    ocl::Device& dev = test::device();
    const std::vector<cl_uint> values = random_values(n, seed, 1000);
    const std::vector<cl_uint> expected = host_exclusive(values);
    std::vector<cl_uint> padded = values;
    for (int i = 0; i < 7; ++i) padded.push_back(0xdead0000u + static_cast<cl_uint>(i));
    measure::Scheduler scheduler(test::device());

    ocl::Buffer<cl_uint> in(dev, std::span<const cl_uint>(padded));
    ocl::Buffer<cl_uint> out(dev, padded.size());
    const std::vector<cl_uint> sentinel(padded.size(), 0xabcdabcdu);
    out.write(sentinel);
    EXPECT_EQ(scan.exclusive(in, out, n, scheduler, measure::Stage::scan, -1), host_total(values)) << "n = " << n;
    std::vector<cl_uint> got = out.read();
    EXPECT_TRUE(std::equal(expected.begin(), expected.end(), got.begin())) << "out of place, n = " << n;
    for (std::size_t i = n; i < got.size(); ++i) EXPECT_EQ(got[i], 0xabcdabcdu) << "n = " << n << ", i = " << i;
    EXPECT_EQ(in.read(), padded) << "the input changed, n = " << n;

    EXPECT_EQ(scan.exclusive(in, in, n, scheduler, measure::Stage::scan, -1), host_total(values)) << "in place, n = " << n;
    got = in.read();
    EXPECT_TRUE(std::equal(expected.begin(), expected.end(), got.begin())) << "in place, n = " << n;
    for (std::size_t i = n; i < got.size(); ++i) EXPECT_EQ(got[i], padded[i]) << "n = " << n << ", i = " << i;
    scheduler.resolve();
    for (const auto& l : scheduler.launches()) EXPECT_EQ(l.stage, measure::Stage::scan);
}

TEST(ConstructScan, Lengths) {
    Scan scan(test::device());
    std::uint64_t seed = 1;
    for (std::size_t n : {0, 1, 2, 1023, 1024, 1025, 4095, 4096, 4097, 100000})
        check_scan(scan, n, seed++);
}

// A fresh Scan whose first use needs two levels of block totals, then three: the block-total
// buffers grow while the scan recurses.
TEST(ConstructScan, FreshScanDeepRecursion) {
    Scan a(test::device());
    check_scan(a, 1025, 21);
    Scan b(test::device());
    check_scan(b, 3000000, 22);  // three levels with 1024-value blocks
    check_scan(b, 5000, 23);
    check_scan(b, 3000001, 24);
}

TEST(ConstructScan, ThreeMillion) {
    Scan scan(test::device());
    check_scan(scan, 3000000, 31);
}

// The bit counts of n - 1 words and a 0, scanned: against popcounts summed on the host; the words are
// left as they were, and the outputs beyond n untouched.
TEST(ConstructScan, PopcountsOfWords) {
    ocl::Device& dev = test::device();
    Scan scan(dev);
    measure::Scheduler scheduler(dev);
    std::uint64_t seed = 51;
    for (std::size_t n : {1, 2, 1024, 1025, 4097, 1500001}) {
        Rng rng(seed++);
        std::vector<cl_uint> words(std::max<std::size_t>(n - 1, 1));
        for (auto& w : words) w = static_cast<cl_uint>(rng.next()) & static_cast<cl_uint>(rng.next());
        std::vector<cl_uint> counts(n, 0);
        for (std::size_t i = 0; i + 1 < n; ++i) counts[i] = static_cast<cl_uint>(std::popcount(words[i]));
        const std::vector<cl_uint> expected = host_exclusive(counts);
        ocl::Buffer<cl_uint> in(dev, std::span<const cl_uint>(words));
        ocl::Buffer<cl_uint> out(dev, n + 3);
        out.write(std::vector<cl_uint>(n + 3, 0xabcdabcdu));
        EXPECT_EQ(scan.exclusive_popcounts(in, out, n, scheduler, measure::Stage::cull, -1), host_total(counts))
            << "n = " << n;
        const std::vector<cl_uint> got = out.read();
        EXPECT_TRUE(std::equal(expected.begin(), expected.end(), got.begin())) << "n = " << n;
        for (std::size_t i = n; i < got.size(); ++i) EXPECT_EQ(got[i], 0xabcdabcdu) << "n = " << n << ", i = " << i;
        EXPECT_EQ(in.read(), words) << "n = " << n;
    }
    ocl::Buffer<cl_uint> both(dev, 4);
    EXPECT_THROW(scan.exclusive_popcounts(both, both, 3, scheduler, measure::Stage::cull, -1), std::invalid_argument);
}

TEST(ConstructScan, SumsBeyond32BitsThrow) {
    ocl::Device& dev = test::device();
    Scan scan(dev);
    measure::Scheduler scheduler(test::device());
    {
        // Exactly 2^32 - 1: fits.
        const std::vector<cl_uint> v{0xfffffffeu, 1u};
        ocl::Buffer<cl_uint> b(dev, std::span<const cl_uint>(v));
        EXPECT_EQ(scan.exclusive(b, b, v.size(), scheduler, measure::Stage::scan, -1), 0xffffffffu);
    }
    {
        // Only the total exceeds 2^32 (every exclusive value fits).
        const std::vector<cl_uint> v{0xffffffffu, 1u};
        ocl::Buffer<cl_uint> b(dev, std::span<const cl_uint>(v));
        EXPECT_THROW(scan.exclusive(b, b, v.size(), scheduler, measure::Stage::scan, -1), InputError);
    }
    {
        // Wraps inside one block.
        const std::vector<cl_uint> v(8, 0x40000000u);
        ocl::Buffer<cl_uint> b(dev, std::span<const cl_uint>(v));
        EXPECT_THROW(scan.exclusive(b, b, v.size(), scheduler, measure::Stage::scan, -1), InputError);
    }
    {
        // Wraps only across blocks and levels (each block's sum fits).
        const std::vector<cl_uint> v(3000000, 2000u);
        ocl::Buffer<cl_uint> b(dev, std::span<const cl_uint>(v));
        EXPECT_THROW(scan.exclusive(b, b, v.size(), scheduler, measure::Stage::scan, -1), InputError);
    }
    // The scan still works after an overflow.
    check_scan(scan, 5000, 41);
}

}  // namespace
}  // namespace sdfbrick
