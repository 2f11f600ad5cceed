#include "pipeline/run.h"

#include <chrono>
#include <span>
#include <stdexcept>

#include "core/hash.h"
#include "scene/to_device.h"

namespace sdfbrick::pipeline {

namespace {

// What one pass produced.
struct Pass {
    render::SceneBricks bricks;
    std::optional<render::TraceResult> trace;
    std::string brick_digest, list_digest, trace_digest;
};

// Runs warmup + repeat passes (each a Pass from a fresh launch recorder) and keeps the captures.
template <class PassFn>
Run repeat_passes(ocl::Device& device, const RunSpec& spec, PassFn&& pass) {
    if (spec.warmup < 0 || spec.repeat < 1) throw std::invalid_argument("pipeline run: warmup >= 0 and repeat >= 1");
    Run out;
    std::vector<double> build_ms, bvh_ms, trace_ms, wall_ms;
    std::uint64_t bricks = 0;
    for (int i = 0; i < spec.warmup + spec.repeat; ++i) {
        const auto start = std::chrono::steady_clock::now();
        // The last pass's bricks and image go first, so that this pass takes their memory again.
        out.bricks = {};
        out.trace.reset();
        measure::Scheduler scheduler(device);
        Pass p = pass(scheduler, i + 1 == spec.warmup + spec.repeat);
        device.memory_pool()->trim();
        if (i < spec.warmup) continue;
        wall_ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
        out.captures.push_back(scheduler.resolve());
        build_ms.push_back(p.bricks.build_ms);
        bvh_ms.push_back(p.bricks.bvh.device_ms);
        trace_ms.push_back(p.trace ? p.trace->trace_ms : 0.0);
        if (out.captures.size() > 1 &&
            (p.bricks.bricks != bricks || p.brick_digest != out.brick_digest || p.list_digest != out.list_digest ||
             p.trace_digest != out.trace_digest))
            out.identical = false;
        bricks = p.bricks.bricks;
        out.brick_digest = std::move(p.brick_digest);
        out.list_digest = std::move(p.list_digest);
        out.trace_digest = std::move(p.trace_digest);
        out.bricks = std::move(p.bricks);
        out.trace = std::move(p.trace);
    }
    out.stages = measure::stage_stats(out.captures);
    out.total_ms = measure::total_stats(out.captures);
    out.build_ms = measure::spread_of(std::move(build_ms));
    out.bvh_ms = measure::spread_of(std::move(bvh_ms));
    out.trace_ms = measure::spread_of(std::move(trace_ms));
    out.wall_ms = measure::spread_of(std::move(wall_ms));
    return out;
}

}  // namespace

Runner::Runner(ocl::Device& device) : builder_(device), bvh_(device), tracer_(device) {}
Runner::~Runner() = default;

ocl::DeviceDigest& Runner::digest() {
    if (!digest_) digest_.emplace(device());
    return *digest_;
}

BrickDigests brick_digests(const render::SceneBricks& b, ocl::DeviceDigest& digest) {
    Fnv1a64 bricks, lists;
    for (const construct::GeometryBuild& g : b.builds) {
        bricks.add_part(construct::output_digest(g, b.settings, digest));
        lists.add_part(construct::list_digest(g, digest));
    }
    return {bricks.hex(), lists.hex()};
}

Run Runner::run(const Scene& scene, const RunSpec& spec) {
    std::optional<SdfCamera> camera;
    if (spec.work == Work::trace) camera = make_camera(scene.camera, spec.trace.width, spec.trace.height);
    return repeat_passes(device(), spec, [&](measure::Scheduler& scheduler, bool last) {
        Pass p;
        p.bricks = spec.work == Work::construct ? render::build_scene_bricks(builder_, scene, spec.build, scheduler)
                                                : render::build_scene_bricks(builder_, bvh_, scene, spec.build, scheduler);
        if (spec.brick_digests) {
            BrickDigests d = brick_digests(p.bricks, digest());
            p.brick_digest = std::move(d.bricks);
            p.list_digest = std::move(d.lists);
        }
        if (camera) {
            p.trace = tracer_.render(scene, p.bricks, *camera, spec.trace, scheduler, {},
                                     {spec.image && last, spec.trace_digests});
            p.trace_digest = p.trace->digest;
        }
        return p;
    });
}

Run Runner::trace(const Scene& scene, const render::SceneBricks& bricks, const RunSpec& spec) {
    const SdfCamera camera = make_camera(scene.camera, spec.trace.width, spec.trace.height);
    return repeat_passes(device(), spec, [&](measure::Scheduler& scheduler, bool last) {
        Pass p;
        p.trace = tracer_.render(scene, bricks, camera, spec.trace, scheduler, {}, {spec.image && last, spec.trace_digests});
        p.trace_digest = p.trace->digest;
        return p;
    });
}

}  // namespace sdfbrick::pipeline
