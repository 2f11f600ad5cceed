// Tests of the accuracy metrics and images (host/reference/accuracy.h) on small hand-made buffers whose
// answers are worked out by hand.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>

#include "reference/accuracy.h"
#include "reference/host_tracer.h"

namespace sdfbrick::reference {
namespace {

// A buffer of misses.
RenderBuffer blank(int w, int h) {
    RenderBuffer b(w, h);
    for (auto& v : b.hit) v = cl_float4{{0.0f, 0.0f, 0.0f, SDF_MISS}};
    for (auto& a : b.aux) a = cl_uint2{{0u, 0u}};
    return b;
}

void set_hit(RenderBuffer& b, std::size_t i, float depth, float nx = 0.0f, float ny = 0.0f, float nz = 1.0f) {
    b.hit[i] = cl_float4{{nx, ny, nz, depth}};
}

TEST(ReferenceAccuracy, DepthErrorsOfATwoByTwoImage) {
    // Reference depth 2 everywhere; test depths 2, 2.25, 2.5, 3; voxel 0.5 -> errors 0, 0.5, 1, 2 voxels.
    RenderBuffer ref = blank(2, 2), test = blank(2, 2);
    const float td[4] = {2.0f, 2.25f, 2.5f, 3.0f};
    for (std::size_t i = 0; i < 4; ++i) {
        set_hit(ref, i, 2.0f);
        set_hit(test, i, td[i]);
    }
    const AccuracyMetrics m = compare(test, ref, 0.5);
    EXPECT_EQ(m.pixels, 4u);
    EXPECT_EQ(m.both_hit, 4u);
    EXPECT_EQ(m.hit_mismatches, 0u);
    EXPECT_EQ(m.mismatch_fraction, 0.0);
    EXPECT_DOUBLE_EQ(m.depth_error_mean, 0.875);
    EXPECT_DOUBLE_EQ(m.depth_error_p99, 2.0);  // rank ceil(0.99 * 4) = 4
    EXPECT_DOUBLE_EQ(m.depth_error_max, 2.0);
    EXPECT_EQ(m.normal_error_mean_deg, 0.0);
    EXPECT_EQ(m.normal_error_p99_deg, 0.0);
    EXPECT_EQ(m.reference_unconverged, 0u);
    // Same normals, depth does not enter the normal image: identical colours.
    EXPECT_TRUE(std::isinf(m.psnr_db));
    // The error is symmetric in test and reference.
    const AccuracyMetrics r = compare(ref, test, 0.5);
    EXPECT_DOUBLE_EQ(r.depth_error_mean, 0.875);
}

// The distance between the surfaces: each depth error times the cosine between its ray and the
// reference normal. A 1 x 1 camera looks down -z; its ray is the forward axis. Normal +z: the error
// itself; normal at 60 degrees from the ray: half of it. The world-unit depth error keeps the whole.
TEST(ReferenceAccuracy, SurfaceErrorIsTheDepthErrorAlongTheNormal) {
    HostCamera camera;  // forward -z
    camera.right = {1.0, 0.0, 0.0};
    camera.up = {0.0, 1.0, 0.0};
    camera.width = camera.height = 1;
    RenderBuffer ref = blank(1, 1), test = blank(1, 1);
    set_hit(ref, 0, 2.0f);
    set_hit(test, 0, 2.5f);
    AccuracyMetrics m = compare(test, ref, 0.25);
    EXPECT_FALSE(m.surface_error_p99_world);
    add_surface_error(m, test, ref, camera);
    EXPECT_DOUBLE_EQ(*m.surface_error_p99_world, 0.5);
    set_hit(ref, 0, 2.0f, 0.0f, std::sqrt(3.0f) / 2.0f, 0.5f);
    m = compare(test, ref, 0.25);
    add_surface_error(m, test, ref, camera);
    EXPECT_NEAR(*m.surface_error_max_world, 0.25, 1e-7);
    EXPECT_DOUBLE_EQ(m.depth_error_max_world, 0.5);
    camera.width = 2;
    EXPECT_THROW(add_surface_error(m, test, ref, camera), std::invalid_argument);
}

// Each pixel's depth error in its own voxel: the same depth error counts 4 voxels where the voxel is
// 0.25 and 0.5 where it is 2; a list of another size, or a voxel <= 0, is refused.
TEST(ReferenceAccuracy, PerPixelVoxels) {
    RenderBuffer ref = blank(2, 1), test = blank(2, 1);
    for (std::size_t i = 0; i < 2; ++i) {
        set_hit(ref, i, 2.0f);
        set_hit(test, i, 3.0f);
    }
    const std::vector<double> voxels{0.25, 2.0};
    const AccuracyMetrics m = compare(test, ref, std::span<const double>(voxels));
    EXPECT_DOUBLE_EQ(m.depth_error_max, 4.0);
    EXPECT_DOUBLE_EQ(m.depth_error_mean, 2.25);
    const AccuracyMetrics same = compare(test, ref, std::span<const double>(std::vector<double>{2.0, 2.0}));
    EXPECT_DOUBLE_EQ(same.depth_error_max, compare(test, ref, 2.0).depth_error_max);
    EXPECT_THROW(compare(test, ref, std::span<const double>(std::vector<double>{1.0})), std::invalid_argument);
    EXPECT_THROW(compare(test, ref, std::span<const double>(std::vector<double>{1.0, 0.0})), std::invalid_argument);
}

TEST(ReferenceAccuracy, NearestRankPercentileIsNotTheMaximum) {
    // 200 both-hit pixels with errors 0, 1, ..., 199 voxels (voxel 1; depths 1 + k are exact floats):
    // p99 = v[ceil(0.99 * 200)] = v[198] = 197, max = 199, mean = 99.5.
    RenderBuffer ref = blank(20, 10), test = blank(20, 10);
    for (std::size_t i = 0; i < 200; ++i) {
        // Scrambled order: the percentile must sort.
        const std::size_t k = (i * 7) % 200;
        set_hit(ref, i, 1.0f);
        set_hit(test, i, 1.0f + static_cast<float>(k));
    }
    const AccuracyMetrics m = compare(test, ref, 1.0);
    EXPECT_EQ(m.both_hit, 200u);
    EXPECT_DOUBLE_EQ(m.depth_error_mean, 99.5);
    EXPECT_DOUBLE_EQ(m.depth_error_p99, 197.0);
    EXPECT_DOUBLE_EQ(m.depth_error_max, 199.0);
}

TEST(ReferenceAccuracy, NormalAngles) {
    // Pixel 0: (0,0,1) vs (1,0,0): 90 degrees. Pixel 1: identical. Pixel 2: 60 degrees apart.
    // Pixel 3: opposite: 180 degrees. Mean (90 + 0 + 60 + 180) / 4 = 82.5, p99 = max = 180.
    RenderBuffer ref = blank(2, 2), test = blank(2, 2);
    set_hit(ref, 0, 1.0f, 0.0f, 0.0f, 1.0f);
    set_hit(test, 0, 1.0f, 1.0f, 0.0f, 0.0f);
    set_hit(ref, 1, 1.0f, 0.0f, 1.0f, 0.0f);
    set_hit(test, 1, 1.0f, 0.0f, 1.0f, 0.0f);
    set_hit(ref, 2, 1.0f, 1.0f, 0.0f, 0.0f);
    set_hit(test, 2, 1.0f, 0.5f, static_cast<float>(std::sqrt(3.0) / 2.0), 0.0f);
    set_hit(ref, 3, 1.0f, 0.0f, 0.0f, 1.0f);
    set_hit(test, 3, 1.0f, 0.0f, 0.0f, -1.0f);
    const AccuracyMetrics m = compare(test, ref, 1.0);
    EXPECT_EQ(m.both_hit, 4u);
    EXPECT_NEAR(m.normal_error_mean_deg, 82.5, 1e-5);
    EXPECT_NEAR(m.normal_error_p99_deg, 180.0, 1e-9);
    EXPECT_EQ(m.depth_error_max, 0.0);

    // A single 90-degree pixel: mean = p99 = 90 exactly (up to atan2's rounding).
    RenderBuffer a = blank(1, 1), b = blank(1, 1);
    set_hit(a, 0, 1.0f, 0.0f, 0.0f, 1.0f);
    set_hit(b, 0, 1.0f, 0.0f, 1.0f, 0.0f);
    const AccuracyMetrics n = compare(a, b, 1.0);
    EXPECT_NEAR(n.normal_error_mean_deg, 90.0, 1e-12);
    EXPECT_NEAR(n.normal_error_p99_deg, 90.0, 1e-12);
    // A small angle: 1e-4 radians, in degrees.
    RenderBuffer c = blank(1, 1), d = blank(1, 1);
    set_hit(c, 0, 1.0f, 0.0f, 0.0f, 1.0f);
    set_hit(d, 0, 1.0f, static_cast<float>(std::sin(1e-4)), 0.0f, static_cast<float>(std::cos(1e-4)));
    EXPECT_NEAR(compare(c, d, 1.0).normal_error_mean_deg, 1e-4 * 180.0 / 3.14159265358979323846, 1e-8);
}

TEST(ReferenceAccuracy, MismatchesAreCountedBothWays) {
    // 2x2: pixel 0 hit in test only, pixel 1 hit in reference only, pixel 2 both hit, pixel 3 both miss.
    RenderBuffer ref = blank(2, 2), test = blank(2, 2);
    set_hit(test, 0, 1.0f);
    set_hit(ref, 1, 1.0f);
    set_hit(test, 2, 1.5f);
    set_hit(ref, 2, 1.0f);
    const AccuracyMetrics m = compare(test, ref, 0.25);
    EXPECT_EQ(m.pixels, 4u);
    EXPECT_EQ(m.hit_mismatches, 2u);
    EXPECT_EQ(m.both_hit, 1u);
    EXPECT_DOUBLE_EQ(m.mismatch_fraction, 0.5);
    // Depth figures only over the both-hit pixel: 0.5 / 0.25 = 2 voxels.
    EXPECT_DOUBLE_EQ(m.depth_error_mean, 2.0);
    EXPECT_DOUBLE_EQ(m.depth_error_max, 2.0);
    // Depth 0 is a hit (a camera inside the solid), only negative depths are misses.
    RenderBuffer z = blank(2, 2);
    set_hit(z, 3, 0.0f);
    EXPECT_EQ(compare(z, blank(2, 2), 1.0).hit_mismatches, 1u);
}

TEST(ReferenceAccuracy, IdenticalImagesHaveNoErrorAndInfinitePsnr) {
    RenderBuffer b = blank(3, 2);
    set_hit(b, 1, 2.5f, 0.6f, 0.0f, 0.8f);
    set_hit(b, 4, 0.75f, 0.0f, -1.0f, 0.0f);
    const AccuracyMetrics m = compare(b, b, 0.01);
    EXPECT_EQ(m.pixels, 6u);
    EXPECT_EQ(m.both_hit, 2u);
    EXPECT_EQ(m.hit_mismatches, 0u);
    EXPECT_EQ(m.depth_error_mean, 0.0);
    EXPECT_EQ(m.depth_error_p99, 0.0);
    EXPECT_EQ(m.depth_error_max, 0.0);
    EXPECT_EQ(m.normal_error_mean_deg, 0.0);
    EXPECT_EQ(m.normal_error_p99_deg, 0.0);
    EXPECT_TRUE(std::isinf(m.psnr_db));
    EXPECT_GT(m.psnr_db, 0.0);
    const nlohmann::json j = to_json(m);
    EXPECT_TRUE(j.at("psnr_db").is_null());
    EXPECT_EQ(j.at("pixels").get<std::size_t>(), 6u);
    EXPECT_EQ(j.at("both_hit").get<std::size_t>(), 2u);
    for (const char* key : {"hit_mismatches", "mismatch_fraction", "depth_error_mean", "depth_error_p99",
                            "depth_error_max", "normal_error_mean_deg", "normal_error_p99_deg", "reference_unconverged"}) {
        ASSERT_TRUE(j.contains(key)) << key;
        EXPECT_EQ(j.at(key).get<double>(), 0.0) << key;
    }
}

TEST(ReferenceAccuracy, PsnrOfAKnownMse) {
    // 2x1: pixel 0 identical hits; pixel 1 a miss (black) in test and a hit with normal (0,0,1)
    // (colour (0.5, 0.5, 1)) in the reference: squared error 0.25 + 0.25 + 1 = 1.5 over 6 channel
    // values -> MSE 0.25 -> PSNR 10 log10(4) dB.
    RenderBuffer ref = blank(2, 1), test = blank(2, 1);
    set_hit(ref, 0, 1.0f, 1.0f, 0.0f, 0.0f);
    set_hit(test, 0, 1.0f, 1.0f, 0.0f, 0.0f);
    set_hit(ref, 1, 1.0f, 0.0f, 0.0f, 1.0f);
    const AccuracyMetrics m = compare(test, ref, 1.0);
    EXPECT_NEAR(m.psnr_db, 10.0 * std::log10(4.0), 1e-12);
    EXPECT_NEAR(to_json(m).at("psnr_db").get<double>(), 6.0206, 1e-4);
    // 1x1, normals (1,0,0) vs (0,1,0): colours (1, .5, .5) vs (.5, 1, .5): MSE = 0.5 / 3 -> 10 log10(6).
    RenderBuffer a = blank(1, 1), b = blank(1, 1);
    set_hit(a, 0, 1.0f, 1.0f, 0.0f, 0.0f);
    set_hit(b, 0, 1.0f, 0.0f, 1.0f, 0.0f);
    EXPECT_NEAR(compare(a, b, 1.0).psnr_db, 10.0 * std::log10(6.0), 1e-12);
}

TEST(ReferenceAccuracy, ReferenceUnconvergedPixelsAreExcluded) {
    // Pixel 0 is flagged in the reference and disagrees wildly; it must not count anywhere but in
    // reference_unconverged. Pixel 1 matches exactly. A flag in the *test* buffer's aux is ignored.
    RenderBuffer ref = blank(2, 1), test = blank(2, 1);
    ref.aux[0] = cl_uint2{{4096u, SDF_REF_UNCONVERGED}};
    set_hit(test, 0, 100.0f, 1.0f, 0.0f, 0.0f);
    set_hit(ref, 1, 1.0f);
    set_hit(test, 1, 1.0f);
    test.aux[1] = cl_uint2{{7u, SDF_REF_UNCONVERGED}};
    const AccuracyMetrics m = compare(test, ref, 1.0);
    EXPECT_EQ(m.reference_unconverged, 1u);
    EXPECT_EQ(m.pixels, 1u);
    EXPECT_EQ(m.both_hit, 1u);
    EXPECT_EQ(m.hit_mismatches, 0u);
    EXPECT_EQ(m.depth_error_max, 0.0);
    EXPECT_TRUE(std::isinf(m.psnr_db));
    EXPECT_EQ(to_json(m).at("reference_unconverged").get<std::size_t>(), 1u);
}

TEST(ReferenceAccuracy, BadInputsThrow) {
    const RenderBuffer a = blank(2, 2), b = blank(2, 3), c = blank(3, 2);
    EXPECT_THROW(compare(a, b, 1.0), std::invalid_argument);
    EXPECT_THROW(compare(a, c, 1.0), std::invalid_argument);
    EXPECT_THROW(difference_image(a, b, 1.0), std::invalid_argument);
    EXPECT_THROW(compare(a, a, 0.0), std::invalid_argument);
    EXPECT_THROW(compare(a, a, -1.0), std::invalid_argument);
    EXPECT_THROW(compare(a, a, std::numeric_limits<double>::quiet_NaN()), std::invalid_argument);
    EXPECT_THROW(difference_image(a, a, 1.0, 0.0), std::invalid_argument);
    RenderBuffer broken = blank(2, 2);
    broken.aux.pop_back();
    EXPECT_THROW(compare(broken, a, 1.0), std::invalid_argument);
    EXPECT_NO_THROW(compare(a, a, 1.0));
}

TEST(ReferenceAccuracy, NormalAndDepthImages) {
    RenderBuffer b = blank(2, 1);
    set_hit(b, 0, 3.5f, 0.6f, -0.8f, 0.0f);
    const Image n = normal_image(b);
    ASSERT_EQ(n.width, 2);
    ASSERT_EQ(n.height, 1);
    ASSERT_EQ(n.channels, 3);
    EXPECT_FLOAT_EQ(n.pixels[0], 0.8f);
    EXPECT_FLOAT_EQ(n.pixels[1], 0.1f);
    EXPECT_FLOAT_EQ(n.pixels[2], 0.5f);
    for (int k = 3; k < 6; ++k) EXPECT_EQ(n.pixels[static_cast<std::size_t>(k)], 0.0f);
    const Image d = depth_image(b);
    ASSERT_EQ(d.channels, 1);
    EXPECT_EQ(d.pixels[0], 3.5f);
    EXPECT_EQ(d.pixels[1], 0.0f);
}

TEST(ReferenceAccuracy, DifferenceImageColours) {
    // 4x2, voxel 0.5: pixel 0 both miss; 1 test only; 2 reference only; 3 reference unconverged;
    // 4..7 both hit with errors 0, 1/3, 2/3 and 5 voxels (saturation 1 voxel): grey, red, yellow, white.
    RenderBuffer ref = blank(4, 2), test = blank(4, 2);
    set_hit(test, 1, 1.0f);
    set_hit(ref, 2, 1.0f);
    ref.aux[3] = cl_uint2{{10u, SDF_REF_UNCONVERGED}};
    set_hit(test, 3, 1.0f);
    const float err_world[4] = {0.0f, 0.5f / 3.0f, 1.0f / 3.0f, 2.5f};
    for (std::size_t i = 4; i < 8; ++i) {
        set_hit(ref, i, 2.0f);
        set_hit(test, i, 2.0f + err_world[i - 4]);
    }
    const Image im = difference_image(test, ref, 0.5);
    ASSERT_EQ(im.channels, 3);
    auto px = [&](std::size_t i, int k) { return im.pixels[i * 3 + static_cast<std::size_t>(k)]; };
    const float expect[8][3] = {{0, 0, 0}, {1, 0, 1}, {0, 1, 1}, {0, 0, 1},
                                {0.15f, 0.15f, 0.15f}, {1, 0, 0}, {1, 1, 0}, {1, 1, 1}};
    for (std::size_t i = 0; i < 8; ++i)
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(px(i, k), expect[i][k], 1e-5) << i << "," << k;
    // A larger saturation moves the ramp: 5 voxels of 15 -> 1/3 -> red.
    const Image wide = difference_image(test, ref, 0.5, 15.0);
    EXPECT_NEAR(wide.pixels[7 * 3 + 0], 1.0f, 1e-5);
    EXPECT_NEAR(wide.pixels[7 * 3 + 1], 0.0f, 1e-5);
    EXPECT_NEAR(wide.pixels[7 * 3 + 2], 0.0f, 1e-5);
}

}  // namespace
}  // namespace sdfbrick::reference
