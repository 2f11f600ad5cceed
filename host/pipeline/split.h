// Split execution (docs/multi-device.md): one job's construction and trace shared among several
// devices, one host thread per device, merged bit-identically. Construction: each device builds the
// descendants of a range of every geometry's split-level bricks (construct::Subtrees), the leaves
// are concatenated in range order. Trace: each device traces a band of image rows against its own
// copy of the merged bricks. Shares come from each device's measured rate for the stage (a
// RateStore), or from a static estimate when a device has none. A device that cannot hold its part
// (out of memory) gets parts of at most half that size, down to kMinPart; a device whose part throws
// otherwise is out of the run; what it had not done is split among the devices left; when none is
// left the run throws.
#pragma once

#include <cstddef>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "cl/device.h"
#include "construct/brick_builder.h"
#include "measure/statistics.h"
#include "pipeline/run.h"
#include "render/brick_tracer.h"

namespace sdfbrick::pipeline {

// Each device's measured rate per workload and stage, kept in one JSON file keyed by device (name,
// driver, compute units), the global index first:
//   {"<device>": {"<workload>": {"construct": rate, "trace": rate}}}.
// A workload is a scene and a brick size ("drops at 0.03125"): the cost of an edit-list entry or a
// pixel differs between scenes, so rates of different workloads are not compared. Construction's
// rate is edit-list entries of the split level per millisecond, the trace's pixels per millisecond.
class RateStore {
public:
    static constexpr const char* kEnv = "SDFBRICK_RATES";
    // $SDFBRICK_RATES ("off": none), else $XDG_CONFIG_HOME/sdfbrick/rates.json, else
    // ~/.config/sdfbrick/rates.json.
    static std::optional<std::filesystem::path> default_path();
    // A missing file is an empty store; without a path nothing is read or saved. Throws InputError
    // naming the file when it is not a store, or when a file stands where its folder would be.
    explicit RateStore(std::optional<std::filesystem::path> path);

    std::optional<double> rate(const ocl::DeviceInfo& device, std::string_view workload, std::string_view stage) const;
    void set(const ocl::DeviceInfo& device, std::string_view workload, std::string_view stage, double rate);
    void save() const;
    const std::optional<std::filesystem::path>& path() const { return path_; }

private:
    std::optional<std::filesystem::path> path_;
    nlohmann::json data_ = nlohmann::json::object();
};

// The basis of a stage split before every device has a measured rate.
inline constexpr const char* kStaticBasis = "static estimate (compute units x clock x FP32 lanes)";

// One device's part of one split stage.
struct DeviceShare {
    std::size_t device = 0;  // global index
    std::string name;
    double planned = 0.0;   // fraction of the stage's work planned for it
    double done = 0.0;      // fraction it did (planned, less what failed, plus what it redid)
    double busy_ms = 0.0;   // wall time of its shares
    double idle_ms = 0.0;   // from the end of its last share to the end of the stage
    // What the busy time went to: device time of its kernels, and host wall time of its copies
    // between host and device (construction: leaves, lists, pool and boxes read back; trace: the
    // merged bricks uploaded) with the bytes they moved. The rest is host work and waiting.
    double kernels_ms = 0.0;
    double copies_ms = 0.0;
    std::uint64_t copied_bytes = 0;
    double rate = 0.0;      // work units per ms it reached (0 when it did nothing)
    std::string failure;    // why it left the run ("" when it did not)
    std::string limit;      // why its parts were made smaller ("" when they were not)
};

// One split stage: "construct" (units: edit-list entries of the split level) or "trace" (pixels).
struct StageSplit {
    std::string stage;
    std::string workload;  // the rate store's key: scene and brick size
    std::string basis;     // "measured rates" or kStaticBasis
    double work = 0.0;  // units in all
    double wall_ms = 0.0;
    std::vector<DeviceShare> devices;
    // The stage's time on the fastest device alone, estimated as work / its measured rate, and the
    // speed-up of the split over it (0 when no device finished a share).
    double fastest_single_ms() const;
    double speedup() const;
};
nlohmann::json to_json(const StageSplit& s);
std::string to_text(const StageSplit& s);

struct SplitSpec {
    Work work = Work::trace;
    // Per device, in the order of the devices given (tuned parameters may differ; the layout, leaf
    // size and image must not).
    std::vector<construct::BuildSettings> build;
    std::vector<render::TraceSettings> trace;
    int warmup = 0;
    int repeat = 1;  // timed passes (captures) after the warm-ups
    bool brick_digests = true;
    bool trace_digests = true;  // the image's digest every pass
    bool image = true;          // the last pass's image read back (SplitRun::job.trace)
    RateStore* rates = nullptr;  // shares from it; the measured rates are written back
};

// A split run: the job's result (pipeline::Run: the merged bricks on the home lane's device, the
// merged image, every lane's launches in each capture) and each lane's own launches.
struct SplitRun {
    Run job;
    std::vector<Run> lanes;  // per device: its captures (the launches of its parts), stages and total
    StageSplit construct, tracing;  // of the last pass; tracing.stage empty when not traced
    std::size_t home = 0;  // the lane whose device holds the job's bricks
};

// Runs one job split over devices (at least one; one host thread each), on the executor's lanes
// (one per device, made on first use and kept). Throws when every device failed: the first failure
// itself when each was an InputError, else one error naming every device's.
SplitRun run_split(std::vector<std::unique_ptr<Lane>>& lanes, const std::vector<ocl::Device*>& devices,
                   const Scene& scene, const SplitSpec& spec);

}  // namespace sdfbrick::pipeline
