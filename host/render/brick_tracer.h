// Stages "trace" and "shade" (docs/tracing.md): the scene's bricks and BVH ready to trace, and the
// brick ray tracer (kernels/trace.cl, kernels/shade.cl over kernels/sdf_trace.h).
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "construct/brick_builder.h"
#include "measure/scheduler.h"
#include "bvh/bvh_builder.h"
#include "cl/buffer.h"
#include "cl/device.h"
#include "image/image.h"
#include "scene/to_device.h"
#include "scene/scene.h"
#include "sdf_types.h"
#include "image/render_buffer.h"
#include "render/methods.h"
#include "render/pictures.h"
#include "render/warnings.h"

namespace sdfbrick::render {

// Every geometry's bricks (construction), their trees and the top level (bvh), and the arrays the
// tracer reads: one pool for all geometries and a table of SdfBrickGeometry.
struct SceneBricks {
    construct::BuildSettings settings;
    std::vector<construct::GeometryBuild> builds;
    bvh::SceneBvh bvh;
    std::unique_ptr<ocl::Buffer<std::uint8_t>> combined_pool;  // several geometries: their pools, in order
    std::unique_ptr<ocl::Buffer<cl_uint>> combined_shifts;     // ... and their bricks' shifts
    std::unique_ptr<ocl::Buffer<SdfBrickGeometry>> geometries;  // one per geometry, then the empty one
    std::uint64_t bricks = 0;
    double voxel_world = 0.0;  // the smallest voxel of any object, in world units
    double build_ms = 0.0;     // construction device time (all geometries)

    const ocl::Buffer<std::uint8_t>& pool() const { return combined_pool ? *combined_pool : *builds.front().pool; }
    const ocl::Buffer<cl_uint>& shifts() const { return combined_shifts ? *combined_shifts : *builds.front().shifts; }
};

// Builds the bricks of every geometry of scene (already at its time): construction only (no BVH, no
// pools for tracing).
SceneBricks build_scene_bricks(construct::BrickBuilder& bricks, const Scene& scene,
                               const construct::BuildSettings& settings, measure::Scheduler& scheduler);
// Builds the bricks of every geometry of scene (already at its time), then the BVH and the arrays the
// tracer reads.
SceneBricks build_scene_bricks(construct::BrickBuilder& bricks, bvh::BvhBuilder& bvh, const Scene& scene,
                               const construct::BuildSettings& settings, measure::Scheduler& scheduler);
// The BVH and the arrays the tracer reads, for constructed bricks on bvh's device.
void prepare_tracing(bvh::BvhBuilder& bvh, const Scene& scene, SceneBricks& bricks, measure::Scheduler& scheduler);

struct TraceSettings {
    int width = 1280;
    int height = 720;
    Method method = Method::sphere;  // docs/tracing.md: the one method within the 4 ms target; hybrid has analytic's accuracy at 1.76x its time
    NormalMethod normals = NormalMethod::continuous;
    bool shade = false;  // also run the shading kernel (shaded mode)
    int group_x = 16;    // work-group of the trace and shade kernels
    int group_y = 8;
    int shadow_rays = 4;
    int ao_rays = 8;
    // Registers per work-item the trace and shade kernels may use, 0 for the compiler's choice. Only
    // NVIDIA's compiler takes a cap (cl_nv_compiler_options); other devices ignore it. A cap trades
    // spills for occupancy; it changes no result.
    int max_registers = 0;
};

// A band of image rows [first, end); end 0 means every row.
struct Rows {
    int first = 0, end = 0;
};

// What a trace brings to the host besides its times, counters and warnings (which always come).
struct TraceOutputs {
    bool image = true;    // the pixel buffers (and the colour in shaded mode) read back
    bool digest = false;  // the digest of the hit and aux buffers, computed on the device (whole images)
};

struct TraceResult {
    RenderBuffer buffer;     // with TraceOutputs::image (else empty)
    Image colour;            // shaded mode, with TraceOutputs::image
    double trace_ms = 0.0;   // device time of the primary rays
    double shade_ms = 0.0;   // device time of shading and its secondary rays
    WorkTotals work;         // the traced rows' counters, reduced on the device
    std::string digest;      // with TraceOutputs::digest: equals buffer_digest of the image read back
    std::vector<TraceWarning> warnings;  // render/warnings.h: defined output that may be wrong
};

// Digest of a render buffer: FNV-1a 64 over the tree digests (core/hash.h) of the hit and of the aux
// bytes. Equal iff bit-identical; the tracer computes the same on the device.
std::string buffer_digest(const RenderBuffer& b);

// Light, penumbra and occlusion radius for the shaded mode, from the scene's light and size.
SdfShading make_shading(const Scene& scene, const SceneBricks& bricks, const TraceSettings& settings);

class BrickTracer {
public:
    explicit BrickTracer(ocl::Device& device);
    ~BrickTracer();
    // Traces bricks (built on this tracer's device) with camera. Every launch is recorded in scheduler
    // (the run's launch recorder). With rows, only those rows are traced and filled (first a multiple
    // of settings.group_y); every pixel's value is the same as in a whole-image trace. The pixel
    // buffers stay on the device (kept and grown across calls) unless outputs asks for them.
    TraceResult render(const Scene& scene, const SceneBricks& bricks, const SdfCamera& camera,
                       const TraceSettings& settings, measure::Scheduler& scheduler, Rows rows = {},
                       TraceOutputs outputs = {});

private:
    struct Kernels;
    struct Frame;  // the buffers kept across calls
    Kernels& kernels(const construct::BuildSettings& b, const TraceSettings& t);
    std::size_t enqueue_counts(std::size_t first, std::size_t count);
    WorkTotals read_counts(std::size_t groups, std::size_t pixels);
    ocl::Device& device_;
    std::map<std::string, std::unique_ptr<Kernels>> cache_;
    std::unique_ptr<Frame> frame_;
};

}  // namespace sdfbrick::render
