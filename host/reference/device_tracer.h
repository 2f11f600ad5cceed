// The device reference tracer (kernels/reference_trace.cl): sphere traces the ANALYTIC edit lists of
// a scene, no bricks, one work-item per pixel. Every brick render's accuracy is measured against its
// output, so it is built for accuracy first; it shares only the scene, the camera (SdfCamera, the
// rays of kernels/sdf_camera.h) and the instances (SdfInstance) with the brick tracer.
//
// ---- The field it traces ----
// F, the exact edit fold of kernels/sdf_edit.h (all edits in order from SDF_FAR, no clamp: the field
// of eval_points.cl and of the double host reference). Per geometry, with k_max its largest blend
// radius and extent the largest side of bounds(g):
//     C = clamp_guard * k_max + clamp_extent * extent       (at least 2^-12 (1 + |bounds|), rounded up to float)
// Edit i's box is level_bounds(edit_i, C + k_i + margin_i) rounded outward to float, margin_i =
// 2^-14 (magnitude + C + k_max + reach_i) for float rounding (as the construction's cull test: the
// evaluated points lie within C + k_max of bounds(g), reach_i = |t_i|max + s_i |params_i|max). Outside its box
// an edit's value is >= C + k_i. At a point p the kernel folds only the edits whose box holds p
// (found through an EditBvh, render/edit_bvh.h), in index order, carrying two values
//     lo = min(combine(lo, v), C) from C          hi = max(combine(hi, v), -C) from SDF_FAR
// Every combine is monotone in the field, so lo <= F(p) <= hi through the folded edits. Skipping an
// edit outside its box keeps both bounds valid: an add / subtract edit there (value >= C + k) is an
// exact no-op on a value in [-C, C] (|F - v| >= k: the blend term is exactly 0, min / max return F),
// and lo <= C, hi >= -C make it one for lo (add) and hi (subtract), or leave the other a looser but
// valid bound; an intersect edit there makes F >= C + k, so the fold restarts after the last such
// edit at (C, SDF_FAR). Where the sign is not decided (lo <= 0 < hi), and for the normal's taps
// where lo != hi, the point takes the exact fold of all the geometry's edits (fallback_points; it
// skips, bit for bit, far add edits while the running value is <= C and far subtract edits while it
// is >= -C). So the sign of F is exact at every sample, and near the surface lo == hi == F (the first
// edit whose value is <= C - k collapses both to it).
//
// Why not the plain band-limited F_C (sdf_fold of sdf_build.h, clamped to [-C, C]) with a "large
// enough" C? Measured on an H100, drops (1024 smooth spheres, k_max 0.3, domain 7.5 wide) at
// 1920 x 1080 against the exact fold of every edit (exact_field):
//     plain F_C, C = 2 k_max + extent/64 = 0.72:  14,753 of 487,202 hit pixels move by > 1e-6 (max
//         6.7% of the depth), normals up to 1.55 rad off (smooth-blend chains carry the saturation
//         at C down to the surface);
//     plain F_C, C = 8 k_max + extent/64 = 2.52:  identical to exact, but 1,611 ms: 3.2 x slower
//         than folding all 1,024 edits at every sample (498 ms): ~320 boxes hold every point, 11.7
//         million samples overflow the 256-entry list;
//     these bounds, C = 0.72 (default):  same hit mask, 16 pixels move by > 1e-6 (max 6.8e-6,
//         grazing rays sampled at other points), 172 ms, 1.6% of samples fall back.
// With the two bounds C is a speed knob only (tests: ReferenceRender.CulledFoldMatchesTheExactField*
// render with three C and compare with exact_field).
//
// ---- The march (per pixel, per instance) ----
// The world ray e + t d (|d| = 1) maps to the geometry frame as o_g + t d_g, o_g = M (e - T),
// d_g = M d, |d_g| = 1 / scale: t is the same parameter in both frames and is the world depth. F is
// in geometry units, so a safe step of F along the ray is F / |d_g| in t (|d_g| computed in the
// kernel, not 1 / scale, so that the step matches the parametrisation the points are computed with).
// The ray is clipped to the geometry's clip box (the add edits' level-k boxes: they hold the solid),
// then, from t0 = max(0, entry):
//   - sample (lo, hi) at p_g(t); inside (hi <= 0): if it is the first sample, hit at t (the ray starts
//     inside the solid; aux flag kRefFlagInside), else bisect [t_prev, t] (F(t_prev) > 0 >= F(t)) until
//     the two ends are adjacent floats (at most 64 halvings, a fixed rule: deterministic); depth = the
//     inside end. So the depth is the first sign change found, within one float step of t.
//   - past the clip box: no hit on this instance;
//   - else step by max(min(lo, C), min_step) / |d_g| (lo <= F <= distance to the surface: never past
//     a surface; min_step = min_step_rel (1 + magnitude) lets a ray that runs within float noise of a
//     surface move on, and crosses into the solid where lo is that small: the bisection finds the
//     crossing. Only a sliver thinner than min_step along the ray can be stepped over).
//   A hit is a sign change, not "F <= eps": F <= eps would put the depth anywhere within eps / cos
//   of the surface (and at grazing incidence far from it), while the sign change pins it to one
//   float step of t; a ray that passes within eps of a surface without entering it is a miss.
// max_steps samples per instance; reaching it at t leaves the pixel a miss with SDF_REF_UNCONVERGED
// unless another instance has a hit nearer than t. The nearest hit over instances wins (ties: the
// first instance).
// Normal: central differences of F (exact values, the same lo == hi / fallback rule) at the hit point
// in the geometry frame with step h = normal_step_rel (1 + magnitude) on each axis, mapped to the
// world as normalize(M^T grad) (-d where the gradient vanishes). magnitude = largest |coordinate| of
// bounds(g) (not of C: the steps must not change with C). With the defaults: float noise of F
// (~1e-7 magnitude) over 2h gives < 1e-3 rad, and the truncation error (h / feature radius)^2 is
// < 1e-3 rad for features >= 30 h.
//
// ---- Speed (H100, 3840 x 2160, scene camera, defaults) ----
// spheres 4.6 ms, cubes 19 ms, fractal 28 ms, rain 119 ms, drops 515 ms (7.7 samples per pixel);
// the host adds ~150 ms (read-back of 200 MB, sums). The per-sample BVH query and sort are divergent
// on a GPU: drops with no culling at all (exact_field) takes only ~3 x longer.
//
// ---- Determinism ----
// The kernel follows sdf_edit.h's rules (written-out sums, no fast math, FP_CONTRACT OFF, correctly
// rounded divide/sqrt); each pixel's output depends on that pixel only; per-pixel counters, summed on
// the host. Same scene and camera: bit-identical output on every run and (same ops) on every device.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "cl/device.h"
#include "cl/program.h"
#include "scene/to_device.h"
#include "scene/scene.h"
#include "sdf_types.h"
#include "image/render_buffer.h"

namespace sdfbrick::reference {

// aux.y flags of the reference tracer (SDF_REF_UNCONVERGED = 1 is in sdf_types.h).
inline constexpr std::uint32_t kRefFlagUnconverged = SDF_REF_UNCONVERGED;
inline constexpr std::uint32_t kRefFlagInside = 2;    // the hit is the ray's first sample (starts inside)
inline constexpr std::uint32_t kRefFlagFallback = 4;  // a sample of this ray took the exact fold of all edits
inline constexpr std::uint32_t kRefFlagOverflow = 8;  // a sample of this ray had > kRefListCapacity boxes

// Candidate edits per point the kernel sorts in private memory; more -> every edit's box is tested in
// order instead (same result, slower; counted as overflow_points).
inline constexpr int kRefListCapacity = 256;

struct ReferenceSettings {
    int max_steps = 2048;              // march samples per ray and instance (1 .. 2^24)
    double clamp_guard = 2.0;          // C = clamp_guard * k_max + clamp_extent * extent (see above);
    double clamp_extent = 1.0 / 64.0;  //   a speed knob only: the traced surface is F's for any C
    double min_step_rel = 0x1p-18;     // smallest step = min_step_rel * (1 + magnitude), geometry units
    double normal_step_rel = 0x1p-13;  // normal's central-difference step = normal_step_rel * (1 + magnitude)
    bool exact_field = false;          // no culling, no bounds: fold every edit at every sample (slow; tests)
};

// What the tracer derived for one geometry (in the geometry frame and units).
struct ReferenceGeometryInfo {
    std::string name;
    std::size_t edits = 0;
    double k_max = 0.0;
    double clamp_c = 0.0;     // C
    double magnitude = 0.0;   // largest |coordinate| of bounds(g): the scale of min_step and normal_step
    double min_step = 0.0;
    double normal_step = 0.0;
    std::size_t bvh_nodes = 0;
    int bvh_depth = 0;
    bool traceable = false;   // false: no add edit, so no surface (the clip box is empty)
};

struct ReferenceResult {
    RenderBuffer image;   // hit = (world normal, depth) or (0, 0, 0, SDF_MISS); aux = (samples, flags)
    double device_ms = 0.0;  // kernel start -> end (profiling events)
    double queue_ms = 0.0;   // kernel queued -> start
    double host_ms = 0.0;    // the whole render() call: preparation, BVHs, uploads, launch, read-back
    std::uint64_t march_steps = 0;        // sum of aux.x: march samples (not bisection or normal taps)
    std::uint64_t overflow_points = 0;    // samples whose box list exceeded kRefListCapacity
    std::uint64_t fallback_points = 0;    // samples that needed the exact fold of all edits
    std::uint64_t hit_pixels = 0;
    std::uint64_t unconverged_pixels = 0;
    std::vector<ReferenceGeometryInfo> geometries;
    std::map<std::string, std::uint64_t> memory;  // device bytes per resource
};

class ReferenceTracer {
public:
    explicit ReferenceTracer(ocl::Device& device);

    // scene: already at its time (scene_at applied); camera: from make_camera(scene.camera, w, h).
    // Throws InputError for a scene that cannot be traced (an object naming a missing geometry, a
    // geometry of more than SDF_MAX_EDITS edits, a non-finite or non-positive scale, non-finite edit
    // bounds), an image size outside 1..kMax*, or settings out of range. A scene without objects
    // renders every pixel as a miss.
    ReferenceResult render(const Scene& scene, const SdfCamera& camera, const ReferenceSettings& settings = {});

    const ocl::BuildRecord& build() const { return program_.record(); }

private:
    ocl::Device& device_;
    ocl::Program program_;
    ocl::Kernel kernel_;
};

// The per-geometry quantities render() uses (C, magnitude, steps, ...), without the device.
ReferenceGeometryInfo reference_geometry_info(const Geometry& g, const ReferenceSettings& settings = {});

}  // namespace sdfbrick::reference
