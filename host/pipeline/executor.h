// The executor: a job (a scene, its settings per device, the work, warm-ups and captures) placed on
// lanes, one per device. Placements: whole (one device does the job), replicate (each device does
// the whole job; the results are compared), split (the devices share one job: construction by
// subtrees, the trace by bands of rows, pipeline/split.h). Every verb, the tuner, the sweep and the
// stability atlas run their measured work through an Executor; a lane keeps its device's programs,
// memory, BVH and image from run to run (docs/design.md, "The executor").
#pragma once

#include <cstddef>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "cl/device.h"
#include "pipeline/run.h"
#include "pipeline/split.h"
#include "reference/device_tracer.h"

namespace sdfbrick::pipeline {

enum class Placement { whole, replicate, split };
std::string_view to_string(Placement p);
std::optional<Placement> placement_from_string(std::string_view s);

// One lane's settings, resolved once per run (given values, then tuning, then validation), with the
// record of where the tuned values came from.
struct LaneSettings {
    construct::BuildSettings build;
    render::TraceSettings trace;                        // the image size also gives the camera
    nlohmann::json tuning = nlohmann::json::object();  // per tuned kernel: source, layer, params
    std::string tuning_text;                            // one line for text reports
};
using SettingsFor = std::function<LaneSettings(const ocl::DeviceInfo&)>;

struct Job {
    Work work = Work::trace;
    bool bricks = true;      // false: no brick work (the reference tracer alone)
    bool reference = false;  // also the reference tracer's image from the same camera (trace.width x height)
    SettingsFor settings;    // called once per lane per run
    int warmup = 0;
    int repeat = 1;
    bool brick_digests = true;  // every capture's brick and edit-list digests (on the device)
    bool trace_digests = true;  // every capture's image digest (on the device)
    bool image = true;          // the last capture's image read back
    RateStore* rates = nullptr;  // split: shares from it, measured rates written back
};

struct LaneRun {
    ocl::DeviceInfo device;
    LaneSettings settings;
    // whole, replicate: the lane's run of the job; split: the lane's own launches per capture (its
    // captures, stages and total; the bricks and image are the job's).
    Run run;
    std::optional<reference::ReferenceResult> reference;  // replicate: every lane's; else the home lane's
};

struct Execution {
    Placement placement = Placement::whole;
    int warmup = 0;
    std::vector<LaneRun> lanes;
    std::size_t home = 0;            // the lane whose device holds the job's bricks (and ran the reference)
    std::optional<Run> split;        // split: the job's run (merged bricks and image, every lane's launches)
    std::optional<StageSplit> construct_split, trace_split;  // split: each stage's shares (last capture)

    // The job's run: the split's, else the home lane's.
    const Run& job() const { return split ? *split : lanes.at(home).run; }
    Run& job() { return split ? *split : lanes.at(home).run; }
    const LaneRun& home_lane() const { return lanes.at(home); }
};

class Executor {
public:
    // The devices stay owned by the caller and must outlive the executor.
    explicit Executor(std::vector<ocl::Device*> devices);
    explicit Executor(ocl::Device& device) : Executor(std::vector<ocl::Device*>{&device}) {}
    ~Executor();

    std::size_t size() const { return devices_.size(); }
    ocl::Device& device(std::size_t i) { return *devices_.at(i); }
    // The lane of device i, made on first use and kept.
    Lane& lane(std::size_t i);

    // Runs job with placement: whole uses the first device only. Throws InputError for settings a
    // device refuses, std::invalid_argument for a job without settings or with warmup < 0 or repeat < 1.
    Execution run(const Scene& scene, const Job& job, Placement placement = Placement::whole);

    // Trace passes only, through the bricks of an earlier run of this executor (built: its Work::bvh
    // or Work::trace execution): every lane of a replicate run traces its own bricks; a whole or split
    // run's bricks are traced on their home lane. job.work and the build settings are not used.
    Execution trace(const Scene& scene, const Execution& built, const Job& job);

private:
    std::vector<ocl::Device*> devices_;
    std::vector<std::unique_ptr<Lane>> lanes_;
};

}  // namespace sdfbrick::pipeline
