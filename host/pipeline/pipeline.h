// The measured pipeline on one device: construction -> bvh -> trace (-> shade), run W warm-up times
// and then N captures (docs/design.md#the-run-loop). Used by `render`, `sweep` and `tune`; the
// builders and the tracer (and so their compiled programs) live as long as the Pipeline.
#pragma once

#include <optional>
#include <vector>

#include "construct/brick_builder.h"
#include "bvh/bvh_builder.h"
#include "measure/statistics.h"
#include "render/brick_tracer.h"

namespace sdfbrick::pipeline {

struct PipelineRun {
    render::SceneBricks bricks;                   // the last capture's
    std::optional<render::TraceResult> trace;     // the last capture's; empty when not traced
    std::vector<measure::Capture> captures;
    std::vector<measure::StageStats> stages;  // every kernel stage: construction's, "bvh", "tlas", "trace", "shade"
    measure::Spread build_ms, bvh_ms, trace_ms;  // per capture: construction, bvh + tlas, trace
    bool identical = true;  // every capture gave the same bricks count and the same traced image
    std::string trace_digest;  // of the last capture's hit and aux buffers ("" when not traced)
};

class Pipeline {
public:
    explicit Pipeline(ocl::Device& device);
    ocl::Device& device() { return builder_.device(); }

    // trace: empty = construction and BVH only.
    PipelineRun run(const Scene& scene, const construct::BuildSettings& settings,
                    const std::optional<render::TraceSettings>& trace, int warmup = 0, int repeat = 1);

private:
    construct::BrickBuilder builder_;
    bvh::BvhBuilder bvh_;
    render::BrickTracer tracer_;
};

// Digest of a render buffer (hit and aux): equal iff bit-identical.
std::string buffer_digest(const RenderBuffer& b);

}  // namespace sdfbrick::pipeline
