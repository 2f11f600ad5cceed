#include "pipeline/run.h"

#include "core/hash.h"
#include "pipeline/passes.h"
#include "scene/to_device.h"

namespace sdfbrick::pipeline {

namespace {

using detail::Pass;
using detail::timed;

// The trace of a pass: the image read back only for the last one, and only when asked.
void trace_pass(render::BrickTracer& tracer, Pass& p, const Scene& scene, const render::SceneBricks& bricks,
                const SdfCamera& camera, const RunSpec& spec, measure::Scheduler& scheduler, bool last) {
    p.trace = timed(p.trace_wall, [&] {
        return tracer.render(scene, bricks, camera, spec.trace, scheduler, {}, {spec.image && last, spec.trace_digests});
    });
    p.trace_digest = p.trace->digest;
}

// The pass's capture; the device's pooled memory that the pass did not take again is freed.
Pass finish(Pass& p, measure::Scheduler& scheduler) {
    p.capture = scheduler.resolve();
    scheduler.device().memory_pool()->trim();
    return std::move(p);
}

}  // namespace

Lane::Lane(ocl::Device& device) : device_(device) {}

construct::BrickBuilder& Lane::builder() {
    if (!builder_) builder_.emplace(device_);
    return *builder_;
}

bvh::BvhBuilder& Lane::bvh() {
    if (!bvh_) bvh_.emplace(device_);
    return *bvh_;
}

render::BrickTracer& Lane::tracer() {
    if (!tracer_) tracer_.emplace(device_);
    return *tracer_;
}

Lane::~Lane() = default;

ocl::DeviceDigest& Lane::digest() {
    if (!digest_) digest_.emplace(device());
    return *digest_;
}

reference::ReferenceTracer& Lane::reference() {
    if (!reference_) reference_.emplace(device());
    return *reference_;
}

BrickDigests brick_digests(const render::SceneBricks& b, ocl::DeviceDigest& digest) {
    Fnv1a64 bricks, lists;
    for (const auto& [output, list] : construct::build_digests(b.builds, b.settings, digest)) {
        bricks.add_part(output);
        lists.add_part(list);
    }
    return {bricks.hex(), lists.hex()};
}

// The builders and tracer the work needs, made before the first pass (not inside a capture).
double Lane::prepare(Work work) {
    double ms = 0.0;
    timed(ms, [&] {
        builder();
        if (work != Work::construct) bvh();
        if (work == Work::trace) tracer();
    });
    return ms;
}

Run Lane::run(const Scene& scene, const RunSpec& spec) {
    const double setup = prepare(spec.work);
    std::optional<SdfCamera> camera;
    if (spec.work == Work::trace) camera = make_camera(scene.camera, spec.trace.width, spec.trace.height);
    Run run = detail::repeat_passes(spec.warmup, spec.repeat, [&](bool last) {
        measure::Scheduler scheduler(device());
        Pass p;
        p.bricks = timed(p.construct_wall, [&] { return render::build_scene_bricks(builder(), scene, spec.build, scheduler); });
        if (spec.work != Work::construct)
            timed(p.bvh_wall, [&] { render::prepare_tracing(bvh(), scene, p.bricks, scheduler); });
        if (spec.brick_digests) {
            BrickDigests d = timed(p.digest_wall, [&] { return brick_digests(p.bricks, digest()); });
            p.brick_digest = std::move(d.bricks);
            p.list_digest = std::move(d.lists);
        }
        if (camera) trace_pass(tracer(), p, scene, p.bricks, *camera, spec, scheduler, last);
        return finish(p, scheduler);
    });
    run.setup_ms = setup;
    return run;
}

Run Lane::trace(const Scene& scene, const render::SceneBricks& bricks, const RunSpec& spec) {
    const SdfCamera camera = make_camera(scene.camera, spec.trace.width, spec.trace.height);
    double setup = 0.0;
    timed(setup, [&] { tracer(); });
    Run run = detail::repeat_passes(spec.warmup, spec.repeat, [&](bool last) {
        measure::Scheduler scheduler(device());
        Pass p;
        trace_pass(tracer(), p, scene, bricks, camera, spec, scheduler, last);
        return finish(p, scheduler);
    });
    run.setup_ms = setup;
    return run;
}

}  // namespace sdfbrick::pipeline
