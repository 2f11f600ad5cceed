// Accuracy of a traced image against a reference image (the device reference tracer or the host
// double-precision one, reference/device_tracer.h, reference/host_tracer.h), and the pictures that show it.
//
// Conventions of compare():
//   - The two buffers must have the same width and height; `reference` is a reference tracer's output:
//     its aux.y holds flags, and a pixel with SDF_REF_UNCONVERGED set is left out of every figure
//     below except `reference_unconverged`, which counts them (the reference itself does not know the
//     answer there). The test buffer's aux is not read. Do not pass a brick tracer's buffer as the
//     reference: its aux.y is a step count and would be read as flags.
//   - A pixel is a hit when its depth (hit.w) is >= 0 (RenderBuffer::is_hit).
//   - pixels: the pixels compared = width * height - reference_unconverged.
//   - hit_mismatches: pixels that are a hit in one image and a miss in the other (both ways);
//     mismatch_fraction = hit_mismatches / pixels (0 when pixels == 0).
//   - depth errors: |d_test - d_ref| / voxel_world over the both_hit pixels, in voxels (voxel_world =
//     the world size of one voxel of the brick grid, > 0). Mean, 99th percentile and maximum.
//   - normal errors: the angle between the two normals in degrees over the both_hit pixels, computed
//     as atan2(|a x b|, a . b) on the normals normalised in double (accurate for small angles too); a
//     zero or non-finite normal on a hit counts as 180 degrees.
//   - Percentiles are nearest-rank: the p-th percentile of n sorted values v[1..n] is v[ceil(p n / 100)]
//     (v[1] when that rank is 0). Every figure is 0 when there is no both_hit pixel.
//   - psnr_db: PSNR of the normal colour images (normal_image: n * 0.5 + 0.5 clamped to [0, 1] on hits,
//     black on misses), peak 1, MSE over the 3 channels of the compared pixels:
//     10 log10(1 / MSE). +infinity when MSE == 0 (identical images, or no pixel compared); to_json
//     writes that as null.
//   - Sums are accumulated in double in pixel order: the result is deterministic.
#pragma once

#include <cstddef>
#include <optional>
#include <span>

#include <nlohmann/json.hpp>

#include "image/image.h"
#include "image/render_buffer.h"

namespace sdfbrick::reference {

struct AccuracyMetrics {
    std::size_t pixels = 0;          // pixels compared (reference-unconverged ones excluded)
    std::size_t both_hit = 0;        // hit in both images
    std::size_t hit_mismatches = 0;  // hit in one image and not the other (either way)
    double mismatch_fraction = 0;    // hit_mismatches / pixels
    double depth_error_mean = 0, depth_error_p99 = 0, depth_error_max = 0;  // voxels, over both_hit pixels
    double depth_error_p99_world = 0, depth_error_max_world = 0;             // the same in world units
    // The distance between the two surfaces, world units: each depth error times the cosine between
    // its ray and the reference normal (add_surface_error; absent until it runs).
    std::optional<double> surface_error_p99_world, surface_error_max_world;
    double normal_error_mean_deg = 0, normal_error_p99_deg = 0;            // degrees, over both_hit pixels
    double psnr_db = 0;                     // normal images; +infinity when identical
    std::size_t reference_unconverged = 0;  // reference pixels flagged SDF_REF_UNCONVERGED (excluded above)
};

// Throws std::invalid_argument when the sizes differ (or a buffer's arrays do not match its size) or
// voxel_world is not a finite value > 0.
AccuracyMetrics compare(const RenderBuffer& test, const RenderBuffer& reference, double voxel_world);
// The same with pixel i's depth error in units of pixel_voxel[i] (for scenes whose objects' voxels
// differ in world size: each pixel measured in the voxels of the object it shows). Throws as above,
// and for a pixel_voxel of another size or a value that is not finite and > 0.
AccuracyMetrics compare(const RenderBuffer& test, const RenderBuffer& reference, std::span<const double> pixel_voxel);

struct HostCamera;  // host_tracer.h

// Fills m's surface_error_* from the pixels both hit, their rays given by camera (make_host_camera:
// sdf_camera.h's directions in double). Throws as compare() for mismatched buffers or a camera of
// another size.
void add_surface_error(AccuracyMetrics& m, const RenderBuffer& test, const RenderBuffer& reference,
                       const HostCamera& camera);

// Every field under its own name; psnr_db is null when it is infinite.
nlohmann::json to_json(const AccuracyMetrics& m);

// ---- images for people (sdfbrick::Image, row-major, top row first) ----

// Depth error at which the heat ramp of difference_image saturates (white), in voxels.
inline constexpr double kDifferenceSaturationVoxels = 1.0;

// 3 channels, one colour per pixel:
//   both miss                          black   (0, 0, 0)
//   hit in test only (extra surface)   magenta (1, 0, 1)
//   hit in reference only (missing)    cyan    (0, 1, 1)
//   reference unconverged              blue    (0, 0, 1)
//   both hit: heat ramp of e = |d_test - d_ref| / voxel_world / saturation_voxels, clamped to [0, 1],
//     piecewise linear: e = 0 dark grey (0.15, 0.15, 0.15) -> 1/3 red (1, 0, 0) -> 2/3 yellow (1, 1, 0)
//     -> 1 white (1, 1, 1) (so a both-hit pixel without error is still told apart from a miss).
// Throws as compare() does, and std::invalid_argument for saturation_voxels <= 0.
Image difference_image(const RenderBuffer& test, const RenderBuffer& reference, double voxel_world,
                       double saturation_voxels = kDifferenceSaturationVoxels);
// The same with pixel i's depth error in units of pixel_voxel[i] (as compare() with per-pixel voxels).
Image difference_image(const RenderBuffer& test, const RenderBuffer& reference, std::span<const double> pixel_voxel,
                       double saturation_voxels = kDifferenceSaturationVoxels);

}  // namespace sdfbrick::reference
