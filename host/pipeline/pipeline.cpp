#include "pipeline/pipeline.h"

#include <span>
#include <stdexcept>

#include "core/hash.h"
#include "scene/to_device.h"

namespace sdfbrick::pipeline {

Pipeline::Pipeline(ocl::Device& device) : builder_(device), bvh_(device), tracer_(device) {}

std::string buffer_digest(const RenderBuffer& b) {
    return Fnv1a64().add_values(std::span<const cl_float4>(b.hit)).add_values(std::span<const cl_uint2>(b.aux)).hex();
}

PipelineRun Pipeline::run(const Scene& scene, const construct::BuildSettings& settings,
                          const std::optional<render::TraceSettings>& trace, int warmup, int repeat) {
    if (warmup < 0 || repeat < 1) throw std::invalid_argument("Pipeline::run: warmup >= 0 and repeat >= 1");
    std::optional<SdfCamera> camera;
    if (trace) camera = make_camera(scene.camera, trace->width, trace->height);
    PipelineRun out;
    std::vector<double> build_ms, bvh_ms, trace_ms;
    for (int i = 0; i < warmup + repeat; ++i) {
        render::SceneBricks bricks = render::build_scene_bricks(builder_, bvh_, scene, settings);
        std::optional<render::TraceResult> traced;
        if (trace) traced = tracer_.render(scene, bricks, *camera, *trace);
        if (i < warmup) continue;
        measure::Capture capture;
        for (const construct::GeometryBuild& b : bricks.builds) capture.insert(capture.end(), b.launches.begin(), b.launches.end());
        capture.insert(capture.end(), bricks.bvh.launches.begin(), bricks.bvh.launches.end());
        if (traced) capture.insert(capture.end(), traced->launches.begin(), traced->launches.end());
        out.captures.push_back(std::move(capture));
        build_ms.push_back(bricks.build_ms);
        bvh_ms.push_back(bricks.bvh.device_ms);
        trace_ms.push_back(traced ? traced->trace_ms : 0.0);
        const std::string digest = traced ? buffer_digest(traced->buffer) : "";
        if (i > warmup && (digest != out.trace_digest || bricks.bricks != out.bricks.bricks)) out.identical = false;
        out.trace_digest = digest;
        out.bricks = std::move(bricks);
        out.trace = std::move(traced);
    }
    out.stages = measure::stage_stats(out.captures);
    out.build_ms = measure::spread_of(std::move(build_ms));
    out.bvh_ms = measure::spread_of(std::move(bvh_ms));
    out.trace_ms = measure::spread_of(std::move(trace_ms));
    return out;
}

}  // namespace sdfbrick::pipeline
