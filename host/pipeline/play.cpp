#include "pipeline/play.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <optional>

#include <fmt/format.h>

#include "core/errors.h"
#include "core/stats.h"
#include "pipeline/command_report.h"
#include "pipeline/passes.h"
#include "scene/to_device.h"

namespace sdfbrick::pipeline {

namespace {

using detail::Clock;
using detail::ms_since;
using detail::timed;

// A geometry with an animated edit changes every frame: all of it is rebuilt.
bool animated(const Geometry& g) {
    return std::any_of(g.edits.begin(), g.edits.end(), [](const Edit& e) { return e.animation.has_value(); });
}

ocl::MemoryPool::Allocations allocations(Executor& executor, std::size_t lanes) {
    ocl::MemoryPool::Allocations t;
    for (std::size_t i = 0; i < lanes; ++i) {
        const ocl::MemoryPool::Allocations a = executor.device(i).memory_pool()->allocations();
        t.count += a.count;
        t.bytes += a.bytes;
    }
    return t;
}

// The frame's device time per stage group, from its launches (every lane's in a split).
void add_stage_times(FrameRecord& f, const measure::Capture& capture) {
    for (const measure::Launch& l : capture) {
        f.device_ms += l.device_ms;
        switch (l.stage) {
            case measure::Stage::bvh:
            case measure::Stage::tlas: f.bvh_ms += l.device_ms; break;
            case measure::Stage::trace: f.trace_ms += l.device_ms; break;
            case measure::Stage::shade: f.shade_ms += l.device_ms; break;
            default: f.construct_ms += l.device_ms; break;
        }
    }
}

// The edit log's operations of one frame, applied to the scene in order, and per geometry what they
// changed (construct::EditChange: the edits that left or changed, as they were; those that came or
// changed, as they are; the old slots that went).
class FrameEdits {
public:
    FrameEdits(const EditLog* log, std::size_t geometries) : touched(geometries), changes(geometries), log_(log) {}
    // Returns the operations applied.
    std::size_t apply(int frame, Scene& scene) {
        std::fill(touched.begin(), touched.end(), false);
        for (construct::EditChange& c : changes) c = {};
        std::map<std::size_t, Slots> slots;
        std::size_t applied = 0;
        for (; log_ && next_ < log_->ops.size() && log_->ops[next_].frame == frame; ++next_, ++applied) {
            const EditOp& op = log_->ops[next_];
            const std::vector<Edit>& edits = scene.geometries[op.geometry].edits;
            const auto [it, first] = slots.try_emplace(op.geometry);
            Slots& t = it->second;
            if (first) {
                t.original = edits.size();
                t.slot.resize(edits.size());
                std::iota(t.slot.begin(), t.slot.end(), std::int64_t{0});
                t.unchanged.assign(edits.size(), 1);
            }
            touched[op.geometry] = true;
            note(op, edits, t, changes[op.geometry]);
            sdfbrick::apply(scene, op);
            update_device(op);
        }
        for (auto& [g, t] : slots) finish(t, scene.geometries[g].edits, changes[g]);
        return applied;
    }
    // Geometry g's edits in device form (to_device), made on first use and kept up to date with the
    // operations (only for geometries without animation: an animated one changes every frame).
    const std::vector<SdfEdit>& device_edits(std::size_t g, const Geometry& geometry) {
        if (device_.size() <= g) device_.resize(g + 1);
        if (!device_[g]) device_[g] = to_device(geometry);
        return *device_[g];
    }

    std::vector<bool> touched;
    std::vector<construct::EditChange> changes;

private:
    struct Slots {  // per edit of the list now: its old slot (-1: appended), and whether it is unchanged
        std::size_t original = 0;  // the list's length before the frame's operations
        std::vector<std::int64_t> slot;
        std::vector<char> unchanged;
    };
    static void note(const EditOp& op, const std::vector<Edit>& edits, Slots& t, construct::EditChange& c) {
        const auto i = static_cast<std::ptrdiff_t>(op.index);
        if (op.kind == EditOp::Kind::append) {
            t.slot.insert(t.slot.end(), op.edits.size(), -1);
            t.unchanged.insert(t.unchanged.end(), op.edits.size(), 0);
            return;
        }
        if (t.unchanged[op.index]) c.before.push_back(edits[op.index]);
        if (op.kind == EditOp::Kind::replace) {
            t.unchanged[op.index] = 0;
        } else {
            t.slot.erase(t.slot.begin() + i);
            t.unchanged.erase(t.unchanged.begin() + i);
        }
    }
    static void finish(const Slots& t, const std::vector<Edit>& edits, construct::EditChange& c) {
        std::vector<char> occupied(t.original, 0);
        for (std::int64_t s : t.slot)
            if (s >= 0) occupied[static_cast<std::size_t>(s)] = 1;
        for (std::size_t j = 0; j < t.slot.size(); ++j)
            if (!t.unchanged[j]) c.after.push_back(edits[j]);
        for (std::size_t s = 0; s < occupied.size(); ++s)
            if (!occupied[s]) c.removed.push_back(static_cast<std::uint32_t>(s));
    }
    void update_device(const EditOp& op) {
        if (op.geometry >= device_.size() || !device_[op.geometry]) return;
        std::vector<SdfEdit>& d = *device_[op.geometry];
        switch (op.kind) {
            case EditOp::Kind::append:
                for (const Edit& e : op.edits) d.push_back(to_device(e));
                break;
            case EditOp::Kind::remove: d.erase(d.begin() + static_cast<std::ptrdiff_t>(op.index)); break;
            case EditOp::Kind::replace: d.at(op.index) = to_device(op.edits.front()); break;
        }
    }
    const EditLog* log_;
    std::size_t next_ = 0;
    std::vector<std::optional<std::vector<SdfEdit>>> device_;
};

// One frame on a whole lane. A geometry without animation keeps its build from the frame before
// (kept); the others are built again, their old memory given back first so that they take it.
class WholeFrames {
public:
    WholeFrames(Lane& lane, const LaneSettings& settings, const PlaySpec& spec, const Scene& scene)
        : lane_(lane), settings_(settings), spec_(spec) {
        for (const Geometry& g : scene.geometries) animated_.push_back(animated(g));
    }

    // edits: what the edit log's operations changed before this frame.
    void frame(const Scene& scene, FrameEdits& edits, FrameRecord& f, std::optional<render::TraceResult>& trace) {
        measure::Scheduler scheduler(lane_.device());
        render::SceneBricks bricks = timed(f.construct_wall_ms, [&] { return build(scene, edits, scheduler, f); });
        if (spec_.work != Work::construct)
            timed(f.bvh_wall_ms, [&] { render::prepare_tracing(lane_.bvh(), scene, bricks, scheduler); });
        if (spec_.digests) {
            const BrickDigests d = timed(f.digest_wall_ms, [&] { return brick_digests(bricks, lane_.digest()); });
            f.brick_digest = d.bricks;
            f.list_digest = d.lists;
        }
        if (spec_.work == Work::trace) {
            const render::TraceSettings& t = settings_.trace;
            const SdfCamera camera = make_camera(scene.camera, t.width, t.height);
            trace = timed(f.trace_wall_ms, [&] {
                return lane_.tracer().render(scene, bricks, camera, t, scheduler, {},
                                             {static_cast<bool>(spec_.on_image), spec_.digests});
            });
            f.trace_digest = trace->digest;
        }
        f.bricks = bricks.bricks;
        add_stage_times(f, scheduler.resolve());
        kept_ = std::move(bricks);
        lane_.device().memory_pool()->trim();
    }

private:
    render::SceneBricks build(const Scene& scene, FrameEdits& edits, measure::Scheduler& scheduler, FrameRecord& f) {
        std::vector<construct::GeometryBuild> old;
        if (kept_) old = std::move(kept_->builds);
        kept_.reset();  // the last frame's BVH and tracing arrays go back to the pool
        records_.resize(scene.geometries.size());
        render::SceneBricks out;
        out.settings = settings_.build;
        for (std::size_t g = 0; g < scene.geometries.size(); ++g) {
            const bool had = g < old.size();
            if (had && !animated_[g] && !edits.touched[g]) {
                out.builds.push_back(std::move(old[g]));
            } else {
                const Geometry& geometry = scene.geometries[g];
                const std::vector<SdfEdit>* prepared = animated_[g] ? nullptr : &edits.device_edits(g, geometry);
                std::optional<construct::GeometryBuild> b;
                if (had && !animated_[g]) b = rebuild(geometry, old[g], edits.changes[g], records_[g], scheduler, prepared);
                if (b) ++f.geometries_spliced;
                if (had) old[g] = {};
                if (!b) {
                    records_[g].reset();
                    b = lane_.builder().build(geometry, settings_.build, scheduler, nullptr, prepared);
                }
                out.builds.push_back(std::move(*b));
                out.build_ms += out.builds.back().device_ms;
                ++f.geometries_rebuilt;
                f.bricks_rebuilt += out.builds.back().leaves_built;
            }
            out.bricks += out.builds.back().leaf_count;
        }
        return out;
    }

    // Geometry g rebuilt where the change reaches, from its last build; nothing when it cannot be.
    std::optional<construct::GeometryBuild> rebuild(const Geometry& g, const construct::GeometryBuild& before,
                                                    const construct::EditChange& change,
                                                    std::optional<std::vector<SdfBrick>>& records,
                                                    measure::Scheduler& scheduler, const std::vector<SdfEdit>* prepared) {
        if (!records) records = before.leaves->read();  // once after each full build
        std::optional<construct::GeometryBuild> b =
            lane_.builder().rebuild(g, settings_.build, before, *records, change, scheduler, prepared);
        if (!b) records.reset();
        return b;
    }

    Lane& lane_;
    const LaneSettings& settings_;
    const PlaySpec& spec_;
    std::vector<bool> animated_;  // per geometry of the scene as read (scene_at drops the animation)
    std::optional<render::SceneBricks> kept_;
    std::vector<std::optional<std::vector<SdfBrick>>> records_;  // per geometry: its leaf records, once read
};

// One frame split over the executor's devices: every geometry rebuilt (the split builds subtrees of
// each geometry on every lane).
void split_frame(Executor& executor, const Scene& scene, const std::vector<LaneRun>& lanes, const PlaySpec& spec,
                 FrameRecord& f, std::optional<render::TraceResult>& trace) {
    Job job;
    job.work = spec.work;
    job.settings = [&lanes](const ocl::DeviceInfo& d) {
        for (const LaneRun& l : lanes)
            if (l.device.index == d.index) return l.settings;
        throw std::logic_error("play: a device without settings");
    };
    job.brick_digests = spec.digests;
    job.trace_digests = spec.digests;
    job.image = spec.work == Work::trace && spec.on_image;
    Execution e = executor.run(scene, job, Placement::split);
    Run& run = e.job();
    f.construct_wall_ms = run.construct_wall_ms.median;
    f.bvh_wall_ms = run.bvh_wall_ms.median;
    f.trace_wall_ms = run.trace_wall_ms.median;
    f.digest_wall_ms = run.digest_wall_ms.median;
    f.bricks = run.bricks.bricks;
    f.geometries_rebuilt = scene.geometries.size();
    f.bricks_rebuilt = f.bricks;
    f.brick_digest = run.brick_digest;
    f.list_digest = run.list_digest;
    f.trace_digest = run.trace_digest;
    add_stage_times(f, run.captures.front());
    trace = std::move(run.trace);
}

void check_spec(const PlaySpec& spec, Placement placement) {
    if (spec.frames < 1 || spec.frames > kMaxFrames)
        throw InputError(fmt::format("play: frames must lie in 1 .. {}, got {}", kMaxFrames, spec.frames));
    if (!(spec.dt > 0.0) || !std::isfinite(spec.dt) || !std::isfinite(spec.from) || !std::isfinite(spec.budget_ms) ||
        spec.budget_ms < 0.0)
        throw InputError("play: the time step must be finite and > 0, the start time and budget finite");
    if (placement == Placement::replicate) throw InputError("play runs whole or split, not replicate: a frame is one job");
    if (spec.on_image && spec.work != Work::trace) throw InputError("play: frames' pictures need the trace");
    if (spec.edits && !spec.edits->ops.empty() && spec.edits->ops.back().frame >= spec.frames) {
        const EditOp& last = spec.edits->ops.back();
        throw InputError(fmt::format("{}:{}: /frame: frame {} is not played ({} frames, from 0)", spec.edits->origin,
                                     last.line, last.frame, spec.frames));
    }
}

}  // namespace

PlayRun play(Executor& executor, const Scene& scene, const SettingsFor& settings, Placement placement,
             const PlaySpec& spec) {
    check_spec(spec, placement);
    PlayRun out;
    out.placement = placement;
    out.budget_ms = spec.budget_ms > 0.0 ? spec.budget_ms : spec.dt * 1000.0;
    const std::size_t n = placement == Placement::whole ? 1 : executor.size();
    for (std::size_t i = 0; i < n; ++i) {
        const ocl::DeviceInfo& d = executor.device(i).info();
        out.lanes.push_back({d, settings(d), {}, {}});
        out.setup_ms += executor.lane(i).prepare(Work::trace);
    }
    std::optional<WholeFrames> whole;
    if (placement == Placement::whole) whole.emplace(executor.lane(0), out.lanes.front().settings, spec, scene);
    Scene current = scene;  // with the edit log's operations so far
    const bool animated_scene = std::any_of(scene.geometries.begin(), scene.geometries.end(), animated);
    FrameEdits edits(spec.edits, scene.geometries.size());
    for (int i = 0; i < spec.frames; ++i) {
        FrameRecord f;
        f.index = i;
        f.time = spec.from + spec.dt * i;
        const ocl::MemoryPool::Allocations before = allocations(executor, n);
        const auto start = Clock::now();
        f.operations = edits.apply(i, current);
        // A scene without animation is itself at every time (scene_at would copy every edit).
        std::optional<Scene> moved;
        if (animated_scene) moved = scene_at(current, f.time);
        const Scene& at = moved ? *moved : current;
        std::optional<render::TraceResult> trace;
        if (whole)
            whole->frame(at, edits, f, trace);
        else
            split_frame(executor, at, out.lanes, spec, f, trace);
        if (spec.on_image && trace) timed(f.output_wall_ms, [&] { spec.on_image(i, std::move(*trace)); });
        f.wall_ms = ms_since(start);
        const ocl::MemoryPool::Allocations after = allocations(executor, n);
        f.allocations = after.count - before.count;
        f.allocated_bytes = after.bytes - before.bytes;
        out.frames.push_back(std::move(f));
        if (spec.progress) spec.progress(i + 1, spec.frames);
    }
    return out;
}

PlaySummary summarise(const PlayRun& run, std::size_t skip) {
    PlaySummary s;
    s.frames = run.frames.size();
    s.skipped = std::min(skip, s.frames > 1 ? s.frames - 1 : std::size_t{0});
    if (run.frames.empty()) return s;
    s.first_ms = run.frames.front().wall_ms;
    std::vector<double> wall, device, edit_wall, edit_device;
    for (std::size_t i = 0; i < run.frames.size(); ++i) {
        const FrameRecord& f = run.frames[i];
        if (f.allocations > 0) s.last_allocating_frame = f.index;
        if (i < s.skipped) continue;
        wall.push_back(f.wall_ms);
        device.push_back(f.device_ms);
        if (f.operations > 0) {
            edit_wall.push_back(f.wall_ms);
            edit_device.push_back(f.device_ms);
        }
        if (f.wall_ms > run.budget_ms) ++s.over_budget;
        s.allocations += f.allocations;
        s.allocated_bytes += f.allocated_bytes;
    }
    s.p50 = percentile(wall, 50.0);
    s.p95 = percentile(wall, 95.0);
    s.p99 = percentile(wall, 99.0);
    s.max = *std::max_element(wall.begin(), wall.end());
    s.mean = std::accumulate(wall.begin(), wall.end(), 0.0) / static_cast<double>(wall.size());
    s.device_p50 = percentile(device, 50.0);
    s.device_p99 = percentile(device, 99.0);
    s.edit_frames = edit_wall.size();
    s.edit_p50 = percentile(edit_wall, 50.0);
    s.edit_p99 = percentile(edit_wall, 99.0);
    s.edit_device_p50 = percentile(edit_device, 50.0);
    s.edit_device_p99 = percentile(edit_device, 99.0);
    return s;
}

namespace {

std::string_view work_name(Work w) {
    return w == Work::construct ? "construct" : w == Work::bvh ? "bvh" : "trace";
}

nlohmann::json to_json(const FrameRecord& f) {
    nlohmann::json j{{"frame", f.index},
                     {"time", f.time},
                     {"wall_ms", f.wall_ms},
                     {"device_ms",
                      {{"construct", f.construct_ms},
                       {"bvh", f.bvh_ms},
                       {"trace", f.trace_ms},
                       {"shade", f.shade_ms},
                       {"total", f.device_ms}}},
                     {"wall_breakdown_ms",
                      {{"construct", f.construct_wall_ms},
                       {"bvh", f.bvh_wall_ms},
                       {"trace", f.trace_wall_ms},
                       {"digests", f.digest_wall_ms},
                       {"output", f.output_wall_ms}}},
                     {"bricks", f.bricks},
                     {"geometries_rebuilt", f.geometries_rebuilt},
                     {"geometries_spliced", f.geometries_spliced},
                     {"bricks_rebuilt", f.bricks_rebuilt},
                     {"operations", f.operations},
                     {"allocations", f.allocations},
                     {"allocated_bytes", f.allocated_bytes}};
    if (!f.trace_digest.empty()) j["digest"] = f.trace_digest;
    if (!f.brick_digest.empty()) {
        j["brick_digest"] = f.brick_digest;
        j["list_digest"] = f.list_digest;
    }
    return j;
}

nlohmann::json to_json(const PlaySummary& s, double budget_ms) {
    return {{"frames", s.frames},
            {"skipped", s.skipped},
            {"budget_ms", budget_ms},
            {"wall_ms", {{"p50", s.p50}, {"p95", s.p95}, {"p99", s.p99}, {"max", s.max}, {"mean", s.mean}}},
            {"device_ms", {{"p50", s.device_p50}, {"p99", s.device_p99}}},
            {"over_budget", s.over_budget},
            {"first_frame_ms", s.first_ms},
            {"last_allocating_frame", s.last_allocating_frame},
            {"allocations", s.allocations},
            {"allocated_bytes", s.allocated_bytes},
            {"edit_frames",
             {{"frames", s.edit_frames},
              {"wall_ms", {{"p50", s.edit_p50}, {"p99", s.edit_p99}}},
              {"device_ms", {{"p50", s.edit_device_p50}, {"p99", s.edit_device_p99}}}}}};
}

}  // namespace

nlohmann::json to_json(const PlayRequest& request, const PlayRun& run) {
    nlohmann::json devices = nlohmann::json::array();
    for (const LaneRun& l : run.lanes)
        devices.push_back({{"name", l.device.name},
                           {"index", l.device.index},
                           {"settings", settings_json(l.settings.build)},
                           {"tuning", l.settings.tuning}});
    nlohmann::json frames = nlohmann::json::array();
    for (const FrameRecord& f : run.frames) frames.push_back(to_json(f));
    const render::TraceSettings& t = request.trace;
    return {{"command", "play"},
            {"file", request.file},
            {"scene", request.scene},
            {"placement", to_string(run.placement)},
            {"mode", request.mode},
            {"method", render::to_string(t.method)},
            {"normals", render::to_string(t.normals)},
            {"width", t.width},
            {"height", t.height},
            {"fps", request.fps > 0.0 ? nlohmann::json(request.fps) : nlohmann::json(nullptr)},
            {"frames_out", request.out_pattern.empty() ? nlohmann::json(nullptr) : nlohmann::json(request.out_pattern)},
            {"edits", request.edits.empty() ? nlohmann::json(nullptr) : nlohmann::json(request.edits)},
            {"work", work_name(request.work)},
            {"setup_ms", run.setup_ms},
            {"devices", devices},
            {"summary", to_json(summarise(run), run.budget_ms)},
            {"frames", frames}};
}

std::string to_text(const PlayRequest& request, const PlayRun& run) {
    const PlaySummary s = summarise(run);
    std::string out = fmt::format("play {}: {} frames of {}x{} ({}, {} normals, mode {}), {} on", request.scene, s.frames,
                                  request.trace.width, request.trace.height, render::to_string(request.trace.method),
                                  render::to_string(request.trace.normals), request.mode, to_string(run.placement));
    for (const LaneRun& l : run.lanes) out += " " + l.device.name;
    out += fmt::format("\n  setup {:.1f} ms once; first frame {:.2f} ms\n", run.setup_ms, s.first_ms);
    out += fmt::format("  frame wall (after the first {}): p50 {:.2f}  p95 {:.2f}  p99 {:.2f}  max {:.2f}  mean {:.2f} ms\n",
                       s.skipped, s.p50, s.p95, s.p99, s.max, s.mean);
    out += fmt::format("  frame device: p50 {:.2f}  p99 {:.2f} ms\n", s.device_p50, s.device_p99);
    out += fmt::format("  budget {:.2f} ms: {} of {} frames over\n", run.budget_ms, s.over_budget, s.frames - s.skipped);
    if (s.last_allocating_frame < 0)
        out += "  device allocations: none\n";
    else
        out += fmt::format("  device allocations after the first frame: {} ({} bytes); the last in frame {}\n",
                           s.allocations, s.allocated_bytes, s.last_allocating_frame);
    if (s.edit_frames > 0)
        out += fmt::format("  {} frames applied edit-log operations: wall p50 {:.2f}  p99 {:.2f} ms, device p50 {:.2f}  "
                           "p99 {:.2f} ms\n",
                           s.edit_frames, s.edit_p50, s.edit_p99, s.edit_device_p50, s.edit_device_p99);
    if (!request.out_pattern.empty()) out += fmt::format("  frames written to {}\n", request.out_pattern);
    return out;
}

}  // namespace sdfbrick::pipeline
