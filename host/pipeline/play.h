// The frame loop (`sdfbrick play`): a scene's animation played frame by frame on the executor's
// lanes. Each frame evaluates the animation at its time, rebuilds the geometries whose edits change
// (all of a geometry with an animated edit), builds the BVH and traces. On a whole placement a
// geometry without animation keeps its bricks from the frame before; a split frame rebuilds every
// geometry. Per frame: wall time and what it went to, device time per stage, bricks, geometries
// rebuilt and device buffers allocated; per run: percentiles of the frame wall and the frames over
// the budget (docs/frames.md).
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "pipeline/executor.h"
#include "scene/edit_log.h"

namespace sdfbrick::pipeline {

inline constexpr int kMaxFrames = 100000;

struct PlaySpec {
    int frames = 1;          // 1 .. kMaxFrames
    double from = 0.0;       // the first frame's time (seconds)
    double dt = 1.0 / 60.0;  // time from one frame to the next (> 0)
    double budget_ms = 0.0;  // a frame's wall budget; 0: dt
    bool digests = false;    // each frame's brick and image digests, computed on the device
    Work work = Work::trace;  // how far a frame goes: construction, + BVH, + trace
    // Operations applied before the frames they name (parsed against the scene); a geometry they
    // change is rebuilt in that frame. Every operation's frame must be below `frames`.
    const EditLog* edits = nullptr;
    // With Work::trace: called on the loop's thread with each frame's trace (its image read back) when set; its time
    // counts in the frame's wall time as output. The CLI queues the picture for a writer thread.
    std::function<void(int frame, render::TraceResult&& trace)> on_image;
    std::function<void(int done, int total)> progress;  // after each frame
};

struct FrameRecord {
    int index = 0;
    double time = 0.0;
    double wall_ms = 0.0;
    // Device time of the frame's launches per stage group, and the total.
    double construct_ms = 0.0, bvh_ms = 0.0, trace_ms = 0.0, shade_ms = 0.0, device_ms = 0.0;
    // What the wall time went to: construction, BVH and tracing arrays, the trace (with any
    // read-back), the digests, the image handed to on_image. The rest is the frame's bookkeeping.
    double construct_wall_ms = 0.0, bvh_wall_ms = 0.0, trace_wall_ms = 0.0, digest_wall_ms = 0.0,
           output_wall_ms = 0.0;
    std::uint64_t bricks = 0;
    std::size_t geometries_rebuilt = 0;
    std::size_t geometries_spliced = 0;  // of those, rebuilt only where the edit log's changes reach
    std::uint64_t bricks_rebuilt = 0;    // the leaves evaluated (a spliced geometry's: those built again)
    std::size_t operations = 0;        // edit-log operations applied before the frame
    // Device buffers allocated during the frame (on every lane): none once capacities settle, apart
    // from what the stages allocate each time (docs/frames.md says which).
    std::uint64_t allocations = 0, allocated_bytes = 0;
    std::string brick_digest, list_digest, trace_digest;  // with PlaySpec::digests
};

struct PlayRun {
    Placement placement = Placement::whole;
    std::vector<LaneRun> lanes;  // each lane's device and settings (their runs are empty)
    double budget_ms = 0.0;
    double setup_ms = 0.0;       // the lanes' builders and tracer made before the first frame
    std::vector<FrameRecord> frames;
};

// Plays spec.frames frames of scene (as read: its animation is evaluated per frame) on the
// executor's devices with placement whole or split (replicate is refused: a frame is one job).
// Throws InputError for a spec out of range or settings a device refuses.
PlayRun play(Executor& executor, const Scene& scene, const SettingsFor& settings, Placement placement,
             const PlaySpec& spec);

// Over the frames after the first `skip` (the first frames pay for capacities and caches).
struct PlaySummary {
    std::size_t frames = 0, skipped = 0;
    double p50 = 0.0, p95 = 0.0, p99 = 0.0, max = 0.0, mean = 0.0;  // frame wall, ms
    double device_p50 = 0.0, device_p99 = 0.0;                      // frame device time, ms
    std::size_t over_budget = 0;                                    // frames whose wall exceeded the budget
    double first_ms = 0.0;                                          // the first frame's wall
    // The frames (after the skipped ones) that applied edit-log operations: their wall and device time.
    std::size_t edit_frames = 0;
    double edit_p50 = 0.0, edit_p99 = 0.0, edit_device_p50 = 0.0, edit_device_p99 = 0.0;
    // The last frame that allocated device memory (-1: none did), and what the frames after the
    // skipped ones allocated in all.
    int last_allocating_frame = -1;
    std::uint64_t allocations = 0, allocated_bytes = 0;
};
PlaySummary summarise(const PlayRun& run, std::size_t skip = 1);

// What a play was asked for, as its report records it.
struct PlayRequest {
    std::string file, scene;
    std::string mode = "normals";
    render::TraceSettings trace;
    double fps = 0.0;  // 0 when the step was given as dt
    std::string out_pattern;  // "" when no frames were written
    std::string edits;        // the edit log's file ("" when none)
    Work work = Work::trace;
};

// {"command": "play", "file", "scene", "placement", "devices": [{name, settings}], "frames": [...],
//  "summary": {...}} (docs/frames.md)
nlohmann::json to_json(const PlayRequest& request, const PlayRun& run);
std::string to_text(const PlayRequest& request, const PlayRun& run);

}  // namespace sdfbrick::pipeline
