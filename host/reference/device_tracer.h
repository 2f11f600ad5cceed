// The device reference tracer (kernels/reference_trace.cl): sphere traces the ANALYTIC edit lists of
// a scene, no bricks, one work-item per pixel. Every brick render's accuracy is measured against its
// output. It shares only the scene, the camera (SdfCamera, kernels/sdf_camera.h) and the instances
// (SdfInstance) with the brick tracer.
//
// Contract (docs/reference.md#device-reference-tracer gives the method, the argument and timings):
//   - The surface is the zero set of F, the exact edit fold of kernels/sdf_edit.h (from SDF_FAR, no
//     clamp). Per point the kernel folds only the edits whose box (reference/edit_bvh.h) holds it,
//     carrying bounds lo <= F <= hi clamped at C = clamp_guard * k_max + clamp_extent * extent (per
//     geometry: k_max its largest blend radius, extent the largest side of its bounds); where they
//     do not decide the sign, it folds every edit. So the sign of F is exact at every sample for any
//     C: clamp_guard and clamp_extent are speed knobs.
//   - Depth: the first sign change along the ray, bisected to adjacent floats (a ray that starts
//     inside the solid hits at its first sample, flag kRefFlagInside). max_steps samples without a
//     hit leave the pixel a miss flagged SDF_REF_UNCONVERGED, unless another instance hit nearer.
//     The nearest hit over the instances wins (ties: the first instance).
//   - Normal: central differences of F with step normal_step_rel (1 + magnitude), mapped to the
//     world as normalize(M^T grad); -d where the gradient vanishes.
//   - Determinism: sdf_edit.h's rules (docs/design.md#determinism); each pixel depends on that pixel
//     only. Same scene and camera: bit-identical output on every run and device.
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
