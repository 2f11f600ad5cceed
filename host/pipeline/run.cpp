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
    double construct_wall = 0.0, bvh_wall = 0.0, trace_wall = 0.0, digest_wall = 0.0;
};

using Clock = std::chrono::steady_clock;

// Runs fn and adds its wall time to ms.
template <class Fn>
auto timed(double& ms, Fn&& fn) {
    const auto start = Clock::now();
    struct Add {
        double& ms;
        Clock::time_point start;
        ~Add() { ms += std::chrono::duration<double, std::milli>(Clock::now() - start).count(); }
    } add{ms, start};
    return fn();
}

// Runs warmup + repeat passes (each a Pass from a fresh launch recorder) and keeps the captures.
template <class PassFn>
Run repeat_passes(ocl::Device& device, const RunSpec& spec, PassFn&& pass) {
    if (spec.warmup < 0 || spec.repeat < 1) throw std::invalid_argument("pipeline run: warmup >= 0 and repeat >= 1");
    Run out;
    std::vector<double> build_ms, bvh_ms, trace_ms, wall_ms, construct_wall, bvh_wall, trace_wall, digest_wall;
    std::uint64_t bricks = 0;
    for (int i = 0; i < spec.warmup + spec.repeat; ++i) {
        const auto start = Clock::now();
        // The last pass's bricks and image go first, so that this pass takes their memory again.
        out.bricks = {};
        out.trace.reset();
        measure::Scheduler scheduler(device);
        Pass p = pass(scheduler, i + 1 == spec.warmup + spec.repeat);
        device.memory_pool()->trim();
        if (i < spec.warmup) continue;
        wall_ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - start).count());
        out.captures.push_back(scheduler.resolve());
        build_ms.push_back(p.bricks.build_ms);
        bvh_ms.push_back(p.bricks.bvh.device_ms);
        trace_ms.push_back(p.trace ? p.trace->trace_ms : 0.0);
        construct_wall.push_back(p.construct_wall);
        bvh_wall.push_back(p.bvh_wall);
        trace_wall.push_back(p.trace_wall);
        digest_wall.push_back(p.digest_wall);
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
    out.construct_wall_ms = measure::spread_of(std::move(construct_wall));
    out.bvh_wall_ms = measure::spread_of(std::move(bvh_wall));
    out.trace_wall_ms = measure::spread_of(std::move(trace_wall));
    out.digest_wall_ms = measure::spread_of(std::move(digest_wall));
    return out;
}

// The trace of a pass: the image read back only for the last one, and only when asked.
void trace_pass(render::BrickTracer& tracer, Pass& p, const Scene& scene, const render::SceneBricks& bricks,
                const SdfCamera& camera, const RunSpec& spec, measure::Scheduler& scheduler, bool last) {
    p.trace = timed(p.trace_wall, [&] {
        return tracer.render(scene, bricks, camera, spec.trace, scheduler, {}, {spec.image && last, spec.trace_digests});
    });
    p.trace_digest = p.trace->digest;
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
    for (const auto& [output, list] : construct::build_digests(b.builds, b.settings, digest)) {
        bricks.add_part(output);
        lists.add_part(list);
    }
    return {bricks.hex(), lists.hex()};
}

Run Runner::run(const Scene& scene, const RunSpec& spec) {
    std::optional<SdfCamera> camera;
    if (spec.work == Work::trace) camera = make_camera(scene.camera, spec.trace.width, spec.trace.height);
    return repeat_passes(device(), spec, [&](measure::Scheduler& scheduler, bool last) {
        Pass p;
        p.bricks = timed(p.construct_wall, [&] { return render::build_scene_bricks(builder_, scene, spec.build, scheduler); });
        if (spec.work != Work::construct)
            timed(p.bvh_wall, [&] { render::prepare_tracing(bvh_, scene, p.bricks, scheduler); });
        if (spec.brick_digests) {
            BrickDigests d = timed(p.digest_wall, [&] { return brick_digests(p.bricks, digest()); });
            p.brick_digest = std::move(d.bricks);
            p.list_digest = std::move(d.lists);
        }
        if (camera) trace_pass(tracer_, p, scene, p.bricks, *camera, spec, scheduler, last);
        return p;
    });
}

Run Runner::trace(const Scene& scene, const render::SceneBricks& bricks, const RunSpec& spec) {
    const SdfCamera camera = make_camera(scene.camera, spec.trace.width, spec.trace.height);
    return repeat_passes(device(), spec, [&](measure::Scheduler& scheduler, bool last) {
        Pass p;
        trace_pass(tracer_, p, scene, bricks, camera, spec, scheduler, last);
        return p;
    });
}

}  // namespace sdfbrick::pipeline
