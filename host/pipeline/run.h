// A lane: one device's state kept from pass to pass (its builders, tracer and digest programs, its
// pooled memory, its image), and the run loop on it. A pass is construction (every geometry of the
// scene), optionally the BVH, optionally the trace; a run is `warmup` uncaptured passes and then
// `repeat` captured ones. Each pass has one launch recorder (measure::Scheduler) that the brick
// builder, the BVH builder and the tracer record into; its launches are the pass's capture. The
// executor (pipeline/executor.h) places a job's work on lanes (docs/design.md, "The executor").
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "bvh/bvh_builder.h"
#include "construct/brick_builder.h"
#include "measure/statistics.h"
#include "reference/device_tracer.h"
#include "render/brick_tracer.h"

namespace sdfbrick::pipeline {

// How far a pass goes.
enum class Work { construct, bvh, trace };

struct RunSpec {
    Work work = Work::trace;
    construct::BuildSettings build;
    render::TraceSettings trace;  // with Work::trace (the image size also gives the camera)
    int warmup = 0;
    int repeat = 1;
    bool brick_digests = false;  // digest every capture's bricks, pools and edit lists (on the device)
    bool trace_digests = true;   // digest every capture's traced image (on the device)
    bool image = true;           // read the last capture's image back (Run::trace->buffer, colour)
};

struct Run {
    render::SceneBricks bricks;                // the last capture's (bvh and pools for tracing from Work::bvh on)
    std::optional<render::TraceResult> trace;  // the last capture's, with Work::trace
    std::vector<measure::Capture> captures;
    std::vector<measure::StageStats> stages;
    measure::Spread total_ms;                    // all launches, per capture
    measure::Spread build_ms, bvh_ms, trace_ms;  // construction, bvh + tlas, trace; per capture
    // Wall time of each captured pass: everything it did on the host and waited for (launches, the
    // waits between levels, digests, read-backs), what a user waits for beside total_ms.
    measure::Spread wall_ms;
    // What that wall time went to, per capture: construction (build()), the BVH and tracing arrays,
    // the trace (with its counters and any read-back), and the digests; the rest of wall_ms is the
    // pass's own bookkeeping.
    measure::Spread construct_wall_ms, bvh_wall_ms, trace_wall_ms, digest_wall_ms;
    // Wall time of making the lane's builders and tracer before the first pass (their programs built
    // or loaded from the cache), once per lane: 0 when the lane had them from an earlier run.
    double setup_ms = 0.0;
    std::string brick_digest, list_digest;       // with brick_digests: output_digest / list_digest over the geometries
    std::string trace_digest;                    // of the traced hit and aux buffers ("" when not traced)
    bool identical = true;  // every capture gave the same brick count, digests and traced image
};

class Lane {
public:
    explicit Lane(ocl::Device& device);
    ~Lane();
    Lane(const Lane&) = delete;
    Lane& operator=(const Lane&) = delete;
    ocl::Device& device() { return device_; }
    // Each made on first use (a lane that only runs the reference tracer compiles nothing else).
    construct::BrickBuilder& builder();
    bvh::BvhBuilder& bvh();
    render::BrickTracer& tracer();
    ocl::DeviceDigest& digest();                 // made on first use
    reference::ReferenceTracer& reference();    // made on first use
    // Makes what `work` needs (builder; + BVH builder; + tracer) if not made yet; returns its wall ms.
    double prepare(Work work);

    // Throws InputError for settings the device refuses, std::invalid_argument for warmup < 0 or
    // repeat < 1.
    Run run(const Scene& scene, const RunSpec& spec);
    // The same loop over trace passes only, through bricks this lane's device built (spec.work and
    // spec.build are not used): the trace tuner measures work-group shapes without rebuilding.
    Run trace(const Scene& scene, const render::SceneBricks& bricks, const RunSpec& spec);

private:
    ocl::Device& device_;
    std::optional<construct::BrickBuilder> builder_;
    std::optional<bvh::BvhBuilder> bvh_;
    std::optional<render::BrickTracer> tracer_;
    std::optional<ocl::DeviceDigest> digest_;  // the brick digests' program and scratch, made on first use
    std::optional<reference::ReferenceTracer> reference_;
};

using render::buffer_digest;

// The brick digest (output_digest) and edit-list digest (list_digest) over every geometry of bricks,
// computed on their device by digest.
struct BrickDigests {
    std::string bricks, lists;
};
BrickDigests brick_digests(const render::SceneBricks& bricks, ocl::DeviceDigest& digest);

}  // namespace sdfbrick::pipeline
