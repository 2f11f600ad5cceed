#include "pipeline/executor.h"

#include <stdexcept>

#include "scene/to_device.h"

namespace sdfbrick::pipeline {

std::string_view to_string(Placement p) {
    switch (p) {
        case Placement::whole: return "whole";
        case Placement::replicate: return "replicate";
        case Placement::split: return "split";
    }
    return "?";
}

std::optional<Placement> placement_from_string(std::string_view s) {
    for (Placement p : {Placement::whole, Placement::replicate, Placement::split})
        if (s == to_string(p)) return p;
    return std::nullopt;
}

Executor::Executor(std::vector<ocl::Device*> devices) : devices_(std::move(devices)), lanes_(devices_.size()) {
    if (devices_.empty()) throw std::invalid_argument("executor: no device");
}

Executor::~Executor() = default;

Lane& Executor::lane(std::size_t i) {
    if (!lanes_.at(i)) lanes_[i] = std::make_unique<Lane>(*devices_[i]);
    return *lanes_[i];
}

namespace {

void run_split_job(std::vector<std::unique_ptr<Lane>>& lanes, const std::vector<ocl::Device*>& devices,
                   const Scene& scene, const Job& job, Execution& out) {
    SplitSpec spec;
    spec.work = job.work;
    for (const LaneRun& l : out.lanes) {
        spec.build.push_back(l.settings.build);
        spec.trace.push_back(l.settings.trace);
    }
    spec.warmup = job.warmup;
    spec.repeat = job.repeat;
    spec.brick_digests = job.brick_digests;
    spec.trace_digests = job.trace_digests;
    spec.image = job.image;
    spec.rates = job.rates;
    SplitRun r = run_split(lanes, devices, scene, spec);
    for (std::size_t i = 0; i < out.lanes.size(); ++i) out.lanes[i].run = std::move(r.lanes[i]);
    out.split = std::move(r.job);
    out.home = r.home;
    out.construct_split = std::move(r.construct);
    if (!r.tracing.stage.empty()) out.trace_split = std::move(r.tracing);
}

}  // namespace

Execution Executor::run(const Scene& scene, const Job& job, Placement placement) {
    if (!job.settings) throw std::invalid_argument("executor: a job needs its settings");
    Execution out;
    out.placement = placement;
    out.warmup = job.warmup;
    const std::size_t n = placement == Placement::whole ? 1 : devices_.size();
    for (std::size_t i = 0; i < n; ++i) out.lanes.push_back({devices_[i]->info(), job.settings(devices_[i]->info()), {}, {}});
    if (job.bricks && placement == Placement::split) {
        const std::vector<ocl::Device*> devices(devices_.begin(), devices_.begin() + static_cast<std::ptrdiff_t>(n));
        run_split_job(lanes_, devices, scene, job, out);
    } else if (job.bricks) {
        for (std::size_t i = 0; i < n; ++i) {
            const LaneSettings& s = out.lanes[i].settings;
            out.lanes[i].run = lane(i).run(scene, {job.work, s.build, s.trace, job.warmup, job.repeat, job.brick_digests,
                                                   job.trace_digests, job.image});
        }
    }
    if (job.reference) {
        const render::TraceSettings& t = out.lanes.front().settings.trace;
        const SdfCamera camera = make_camera(scene.camera, t.width, t.height);
        for (std::size_t i = 0; i < n; ++i)
            if (placement == Placement::replicate || i == out.home)
                out.lanes[i].reference = lane(i).reference().render(scene, camera);
    }
    return out;
}

Execution Executor::trace(const Scene& scene, const Execution& built, const Job& job) {
    if (!job.settings) throw std::invalid_argument("executor: a job needs its settings");
    Execution out;
    out.placement = built.placement == Placement::replicate ? Placement::replicate : Placement::whole;
    out.warmup = job.warmup;
    for (std::size_t i = 0; i < built.lanes.size(); ++i) {
        if (out.placement != Placement::replicate && i != built.home) continue;
        const ocl::DeviceInfo& device = built.lanes[i].device;
        LaneRun l{device, job.settings(device), {}, {}};
        const RunSpec spec{Work::trace, l.settings.build, l.settings.trace, job.warmup, job.repeat, false,
                           job.trace_digests, job.image};
        const render::SceneBricks& bricks = built.split ? built.split->bricks : built.lanes[i].run.bricks;
        l.run = lane(i).trace(scene, bricks, spec);
        out.lanes.push_back(std::move(l));
    }
    return out;
}

}  // namespace sdfbrick::pipeline
