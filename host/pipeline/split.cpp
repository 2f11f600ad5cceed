#include "pipeline/split.h"

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <exception>
#include <memory>
#include <mutex>
#include <optional>
#include <numeric>
#include <span>
#include <stdexcept>
#include <thread>
#include <tuple>

#include <fmt/format.h>

#include "cl/cl_error.h"
#include "core/errors.h"
#include "core/files.h"
#include "core/hash.h"
#include "pipeline/passes.h"
#include "scene/to_device.h"

namespace sdfbrick::pipeline {

// ---- the rate store ----

namespace {

std::string device_key(const ocl::DeviceInfo& d) {
    return fmt::format("{}: {} | {} | {} CU", d.index, d.name, d.driver_version, d.compute_units);
}

}  // namespace

std::optional<std::filesystem::path> RateStore::default_path() { return config_file(kEnv, "rates.json"); }

RateStore::RateStore(std::optional<std::filesystem::path> path) : path_(std::move(path)) {
    if (!path_) return;
    // Where the store cannot be written (a file on its way to the folder), say so now, not after the run.
    for (std::filesystem::path p = path_->parent_path(); !p.empty(); p = p.parent_path()) {
        std::error_code ec;
        const std::filesystem::file_status st = std::filesystem::status(p, ec);
        if (std::filesystem::exists(st)) {
            if (!std::filesystem::is_directory(st))
                throw InputError(fmt::format("{}: the device rate store cannot be written: {} is not a folder",
                                             path_->string(), p.string()));
            break;
        }
        if (p == p.parent_path()) break;
    }
    if (!std::filesystem::exists(*path_)) return;
    data_ = nlohmann::json::parse(read_file(*path_), nullptr, false);
    if (!data_.is_object())
        throw InputError(fmt::format("{}: not a device rate store (a JSON object of devices)", path_->string()));
}

std::optional<double> RateStore::rate(const ocl::DeviceInfo& device, std::string_view workload,
                                      std::string_view stage) const {
    const auto d = data_.find(device_key(device));
    if (d == data_.end() || !d->is_object()) return std::nullopt;
    const auto w = d->find(std::string(workload));
    if (w == d->end() || !w->is_object()) return std::nullopt;
    const auto r = w->find(std::string(stage));
    if (r == w->end() || !r->is_number() || !(r->get<double>() > 0.0)) return std::nullopt;
    return r->get<double>();
}

void RateStore::set(const ocl::DeviceInfo& device, std::string_view workload, std::string_view stage, double rate) {
    nlohmann::json& d = data_[device_key(device)];
    if (!d.is_object()) d = nlohmann::json::object();
    d[std::string(workload)][std::string(stage)] = rate;
}

void RateStore::save() const {
    if (!path_) return;
    if (path_->has_parent_path()) std::filesystem::create_directories(path_->parent_path());
    write_file_atomic(*path_, data_.dump(2) + "\n");
}

// ---- reports ----

double StageSplit::fastest_single_ms() const {
    double best = 0.0;
    for (const DeviceShare& d : devices) best = std::max(best, d.rate);
    return best > 0.0 ? work / best : 0.0;
}

double StageSplit::speedup() const { return wall_ms > 0.0 ? fastest_single_ms() / wall_ms : 0.0; }

nlohmann::json to_json(const StageSplit& s) {
    nlohmann::json devices = nlohmann::json::array();
    for (const DeviceShare& d : s.devices)
        devices.push_back({{"device", d.device}, {"name", d.name}, {"planned", d.planned}, {"done", d.done},
                           {"busy_ms", d.busy_ms}, {"idle_ms", d.idle_ms}, {"kernels_ms", d.kernels_ms},
                           {"copies_ms", d.copies_ms}, {"copied_bytes", d.copied_bytes}, {"rate", d.rate},
                           {"failure", d.failure.empty() ? nlohmann::json(nullptr) : nlohmann::json(d.failure)},
                           {"limit", d.limit.empty() ? nlohmann::json(nullptr) : nlohmann::json(d.limit)}});
    return {{"stage", s.stage}, {"workload", s.workload}, {"basis", s.basis}, {"work", s.work}, {"wall_ms", s.wall_ms},
            {"fastest_single_ms_estimated", s.fastest_single_ms()}, {"speedup_estimated", s.speedup()},
            {"devices", devices}};
}

std::string to_text(const StageSplit& s) {
    std::string text = fmt::format("{} split of {} ({}): {:.1f} ms; fastest device alone ~{:.1f} ms (estimated from "
                                   "its rate): speed-up {:.2f}x\n",
                                   s.stage, s.workload, s.basis, s.wall_ms, s.fastest_single_ms(), s.speedup());
    for (const DeviceShare& d : s.devices) {
        text += fmt::format("  device {} [{}]: planned {:.1f}%, done {:.1f}%, busy {:.1f} ms, idle at end {:.1f} ms",
                            d.device, d.name, 100.0 * d.planned, 100.0 * d.done, d.busy_ms, d.idle_ms);
        if (d.busy_ms > 0.0)
            text += fmt::format(" (kernels {:.1f} ms, copies {:.1f} ms for {:.0f} MB)", d.kernels_ms, d.copies_ms,
                                static_cast<double>(d.copied_bytes) / 1e6);
        if (!d.limit.empty()) text += fmt::format("; smaller parts: {}", d.limit);
        text += d.failure.empty() ? "\n" : fmt::format("; FAILED: {}\n", d.failure);
    }
    return text;
}

// ---- the split run ----

namespace {

using detail::Clock;
using detail::ms_since;

// The split level: the first with at least this many bricks (or the leaf level).
constexpr std::uint64_t kSplitBricks = 256;

// A part of a stage's work, as a fraction of it: [f0, f1).
struct Interval {
    double f0 = 0.0, f1 = 1.0;
    double width() const { return f1 - f0; }
};

// The index range of the weights' prefix sums that [f0, f1) covers: boundary(f) is the first index
// whose prefix reaches f * total, so neighbouring intervals share their boundary exactly.
std::pair<std::uint64_t, std::uint64_t> covered(const std::vector<std::uint64_t>& prefix, Interval iv) {
    const auto at = [&](double f) {
        const double target = f * static_cast<double>(prefix.back());
        return static_cast<std::uint64_t>(
            std::lower_bound(prefix.begin(), prefix.end(), target,
                             [](std::uint64_t p, double t) { return static_cast<double>(p) < t; }) -
            prefix.begin());
    };
    return {at(iv.f0), at(iv.f1)};
}

// A part of one geometry's build, read back to the host.
struct HostBuild {
    construct::GeometryBuildInfo meta;
    int split_level = -1;           // -1: the build ended before a split level
    std::uint64_t total_weight = 0;  // of the split level's bricks
    std::vector<SdfBrick> leaves;
    std::vector<cl_uint> lists;
    std::vector<std::uint8_t> pool;
    std::vector<SdfBounds> aabbs;
    std::vector<cl_uint> shifts;

    std::uint64_t bytes() const {
        return sizeof(SdfBrick) * leaves.size() + sizeof(cl_uint) * (lists.size() + shifts.size()) + pool.size() +
               sizeof(SdfBounds) * aabbs.size();
    }
};

// One device in the run: its builders (made on first use, so that a failing program build is its
// failure) and, for tracing, its copy of the merged bricks.
struct SplitLane {
    ocl::Device* device = nullptr;
    std::size_t slot = 0;  // index into the spec's per-device settings
    std::unique_ptr<Lane>* slots = nullptr;  // the executor's lane of this device, made on first use
    std::optional<render::SceneBricks> traced;
    std::string failure;
    std::exception_ptr error;
    double cap = 1.0;  // the widest part it may take: less after it could not hold one
    // This stage's kernel device time and host-device copies so far (DeviceShare's fields).
    double kernels_ms = 0.0, copies_ms = 0.0;
    std::uint64_t copied_bytes = 0;

    // The parts it read back in the last pass, one per geometry: their memory is read into again,
    // so that a pass does not fault in fresh pages for every brick it reads back.
    std::vector<HostBuild> spare;

    // Runs fn() as one of the lane's host-device copies of `bytes`.
    template <class Fn>
    auto copy(std::uint64_t bytes, Fn&& fn) {
        struct Count {
            SplitLane& lane;
            std::uint64_t bytes;
            Clock::time_point t0 = Clock::now();
            ~Count() {
                lane.copies_ms += ms_since(t0);
                lane.copied_bytes += bytes;
            }
        } count{*this, bytes};
        return fn();
    }

    bool alive() const { return failure.empty(); }
    Lane& tools() {
        if (!*slots) *slots = std::make_unique<Lane>(*device);
        return **slots;
    }
    // A part's launches, once it finished: its device time, and into this pass's capture of the lane.
    void record(measure::Scheduler& scheduler) {
        const measure::Capture& launches = scheduler.resolve();
        kernels_ms += scheduler.total_ms();
        capture.insert(capture.end(), launches.begin(), launches.end());
    }
    measure::Capture capture;  // this pass's launches on the lane (the parts that finished)
};

// A part's result with the fraction it covers.
template <class Result>
struct Part {
    Interval span;
    Result result;
    std::size_t lane = 0;  // which lane made it
};

[[noreturn]] void throw_all_failed(const std::vector<SplitLane>& lanes) {
    bool all_input = true;
    std::string what;
    std::exception_ptr first;
    for (const SplitLane& l : lanes) {
        if (!l.error) continue;
        if (!first) first = l.error;
        try {
            std::rethrow_exception(l.error);
        } catch (const InputError&) {
        } catch (...) {
            all_input = false;
        }
        what += fmt::format("{}device {} ({}): {}", what.empty() ? "" : "; ", l.device->info().index,
                            l.device->info().name, l.failure);
    }
    if (all_input && first) std::rethrow_exception(first);
    throw std::runtime_error("split run: every device failed: " + what);
}

// A device whose weight is below this fraction of the live devices' gets no share: its fixed costs
// (upper levels, uploads, its BVH, the host merge) exceed what it saves the others. Measured on an
// H200 with PoCL beside it: shares of 4-6% made the split 30-48% slower than the GPU alone.
constexpr double kMinShare = 0.10;

// The narrowest part a device out of memory is given before it leaves the run.
constexpr double kMinPart = 1.0 / 64;

// Splits iv among the live lanes in proportion to their weights.
std::vector<std::pair<std::size_t, Interval>> divide(Interval iv, const std::vector<SplitLane>& lanes,
                                                     const std::vector<double>& weights) {
    std::vector<std::size_t> live;
    double all = 0.0, best = 0.0;
    for (std::size_t i = 0; i < lanes.size(); ++i)
        if (lanes[i].alive()) {
            all += weights[i];
            best = std::max(best, weights[i]);
        }
    for (std::size_t i = 0; i < lanes.size(); ++i)
        if (lanes[i].alive() && (weights[i] >= kMinShare * all || weights[i] == best)) live.push_back(i);
    double total = 0.0;
    for (std::size_t i : live) total += weights[i];
    std::vector<std::pair<std::size_t, Interval>> out;
    double sum = 0.0, at = iv.f0;
    for (std::size_t k = 0; k < live.size(); ++k) {
        sum += weights[live[k]];
        const double end = k + 1 == live.size() ? iv.f1 : iv.f0 + iv.width() * (sum / total);
        out.push_back({live[k], {at, end}});
        at = end;
    }
    return out;
}

// Whether e says that a device could not hold what it was given: a smaller part may fit.
bool out_of_memory(const std::exception& e) {
    const auto* cl = dynamic_cast<const ocl::ClError*>(&e);
    return cl && (cl->code() == CL_MEM_OBJECT_ALLOCATION_FAILURE || cl->code() == CL_INVALID_BUFFER_SIZE ||
                  cl->code() == CL_OUT_OF_HOST_MEMORY);
}

// A lane's part iv threw e: a lane out of memory takes parts of at most half the width from now on
// (down to kMinPart), any other failure takes the lane out of the run.
void could_not_run(SplitLane& lane, DeviceShare& share, Interval iv, const std::exception& e) {
    if (out_of_memory(e) && iv.width() / 2 >= kMinPart) {
        lane.cap = iv.width() / 2;
        share.limit = fmt::format("could not hold {:.1f}% of the stage ({}); parts of at most {:.1f}% since",
                                  100.0 * iv.width(), e.what(), 100.0 * lane.cap);
        return;
    }
    lane.failure = out_of_memory(e) ? fmt::format("could not hold even {:.1f}% of the stage: {}", 100.0 * iv.width(),
                                                  e.what())
                                    : e.what();
    lane.error = std::current_exception();
}

// Runs the whole stage [0, 1) over the lanes, one thread each, in proportion to weights: fn(lane,
// interval) does one part. A lane whose part throws leaves the run; what it had not done is divided
// among the lanes left, until everything is done. Returns the parts in order of their fractions.
template <class Result, class Fn>
std::vector<Part<Result>> run_shared(std::vector<SplitLane>& lanes, const std::vector<double>& weights, StageSplit& report,
                                     Fn&& fn) {
    const auto start = Clock::now();
    std::vector<Part<Result>> done;
    std::vector<Interval> pending{{0.0, 1.0}};
    std::vector<double> last_end(lanes.size(), 0.0);
    for (SplitLane& l : lanes) {
        l.cap = 1.0;  // what a device could not hold in another stage may fit in this one
        l.kernels_ms = l.copies_ms = 0.0;
        l.copied_bytes = 0;
    }
    bool first_round = true;
    while (!pending.empty()) {
        if (std::none_of(lanes.begin(), lanes.end(), [](const SplitLane& l) { return l.alive(); })) throw_all_failed(lanes);
        std::vector<std::vector<Interval>> assigned(lanes.size()), lost(lanes.size());
        for (const Interval& iv : pending)
            for (const auto& [lane, part] : divide(iv, lanes, weights)) {
                assigned[lane].push_back(part);
                if (first_round) report.devices[lane].planned += part.width();
            }
        first_round = false;
        pending.clear();
        std::vector<std::vector<Part<Result>>> got(lanes.size());
        const auto work = [&](std::size_t i) {
            for (Interval iv : assigned[i]) {
                if (!lanes[i].alive()) {
                    lost[i].push_back(iv);
                    continue;
                }
                if (iv.width() > lanes[i].cap) {  // the rest goes to the next round
                    lost[i].push_back({iv.f0 + lanes[i].cap, iv.f1});
                    iv.f1 = iv.f0 + lanes[i].cap;
                }
                const auto t0 = Clock::now();
                try {
                    got[i].push_back({iv, fn(lanes[i], iv), i});
                    report.devices[i].done += iv.width();
                } catch (const std::exception& e) {
                    could_not_run(lanes[i], report.devices[i], iv, e);
                    lost[i].push_back(iv);
                }
                report.devices[i].busy_ms += ms_since(t0);
                last_end[i] = ms_since(start);
            }
        };
        // One thread per lane with work; the first of them runs on the calling thread (a lane alone
        // with the stage starts no thread: a new thread's first driver call costs time on some
        // platforms).
        std::vector<std::thread> threads;
        std::optional<std::size_t> inline_lane;
        for (std::size_t i = 0; i < lanes.size(); ++i) {
            if (assigned[i].empty()) continue;
            if (!inline_lane)
                inline_lane = i;
            else
                threads.emplace_back(work, i);
        }
        if (inline_lane) work(*inline_lane);
        for (std::thread& t : threads) t.join();
        for (std::size_t i = 0; i < lanes.size(); ++i) {
            for (Part<Result>& p : got[i]) done.push_back(std::move(p));
            pending.insert(pending.end(), lost[i].begin(), lost[i].end());
        }
    }
    report.wall_ms = ms_since(start);
    for (std::size_t i = 0; i < lanes.size(); ++i) {
        DeviceShare& d = report.devices[i];
        d.failure = lanes[i].failure;
        d.idle_ms = report.wall_ms - last_end[i];  // the whole stage for a device without a part
        d.kernels_ms = lanes[i].kernels_ms;
        d.copies_ms = lanes[i].copies_ms;
        d.copied_bytes = lanes[i].copied_bytes;
    }
    std::sort(done.begin(), done.end(), [](const Part<Result>& a, const Part<Result>& b) { return a.span.f0 < b.span.f0; });
    return done;
}

// FP32 lanes per compute unit, roughly: a CPU core's SIMD width; a GPU compute unit's by vendor
// (four 32-wide warp schedulers per NVIDIA multiprocessor, 16-lane SIMDs on AMD), else 32.
double lanes_per_unit(const ocl::DeviceInfo& d) {
    if (d.type != "gpu") return std::max(1u, d.native_float_width);
    if (d.nv_warp_size) return 4.0 * *d.nv_warp_size;
    if (d.amd_simd_per_compute_unit) return 16.0 * *d.amd_simd_per_compute_unit;
    return 32.0;
}

double static_estimate(const ocl::DeviceInfo& d) {
    return std::max(1.0, double(d.compute_units) * std::max(1u, d.max_clock_mhz) * lanes_per_unit(d));
}

// The stage's weights per lane: measured rates when the store has one for every device, else
// compute units x clock.
std::vector<double> stage_weights(const std::vector<SplitLane>& lanes, const RateStore* rates, StageSplit& report) {
    std::vector<double> w;
    for (const SplitLane& l : lanes) {
        const std::optional<double> r =
            rates ? rates->rate(l.device->info(), report.workload, report.stage) : std::nullopt;
        if (!r) break;
        w.push_back(*r);
    }
    report.basis = "measured rates";
    if (w.size() == lanes.size()) return w;
    report.basis = kStaticBasis;
    w.clear();
    for (const SplitLane& l : lanes) w.push_back(static_estimate(l.device->info()));
    return w;
}

StageSplit start_report(const std::vector<SplitLane>& lanes, std::string stage, const Scene& scene, const SplitSpec& spec) {
    StageSplit r;
    r.stage = std::move(stage);
    r.workload = fmt::format("{} at {}", scene.name, spec.build.front().leaf_size);
    for (const SplitLane& l : lanes) {
        DeviceShare d;
        d.device = l.device->info().index;
        d.name = l.device->info().name;
        r.devices.push_back(d);
    }
    return r;
}

void finish_report(StageSplit& r, RateStore* rates, const std::vector<SplitLane>& lanes) {
    for (std::size_t i = 0; i < lanes.size(); ++i) {
        DeviceShare& d = r.devices[i];
        if (d.done <= 0.0 || d.busy_ms <= 0.0) continue;
        d.rate = d.done * r.work / d.busy_ms;
        if (rates) rates->set(lanes[i].device->info(), r.workload, r.stage, d.rate);
    }
}

// ---- construction ----

// One geometry's part (or merged whole) on the host.

// Reads b's arrays back into h's (memory from an earlier pass, or none), as copies of lane's.
HostBuild to_host(const construct::GeometryBuild& b, SplitLane& lane, HostBuild h) {
    const auto read = [&](const auto& buffer, auto& out) {
        out.resize(buffer.size());
        lane.copy(buffer.bytes(), [&] { buffer.read_into(std::span(out)); });
    };
    read(*b.leaves, h.leaves);
    read(*b.leaf_edit_indices, h.lists);
    read(*b.pool, h.pool);
    read(*b.aabbs, h.aabbs);
    read(*b.shifts, h.shifts);
    h.meta = b.info();
    return h;
}

// A lane's part of the construction: read back to the host, or, when the part is all of the stage
// (one lane did everything), left where it is: nothing is merged, nothing crosses.
struct BuiltPart {
    std::vector<HostBuild> host;  // per geometry; with resident, only the split level and its weight
    std::optional<std::vector<construct::GeometryBuild>> resident;
};

// The split level of a whole build and its weight, from its level table: the level subtrees would
// pick and its list entries (each brick's list counts at least 1).
std::pair<int, std::uint64_t> split_of(const construct::GeometryBuildInfo& b, const construct::Subtrees& subtrees) {
    const std::vector<construct::LevelReport>& t = b.level_reports;
    for (std::size_t l = 0; l < t.size(); ++l)
        if (subtrees.splits_at(static_cast<int>(l), t[l].bricks, b.coarsest_leaf_level))
            return {static_cast<int>(l), std::max(t[l].edit_entries, t[l].bricks)};
    return {-1, 0};
}

// Builds the part iv of every geometry on lane's device.
BuiltPart build_part(SplitLane& lane, const Scene& scene, const construct::BuildSettings& s, Interval iv) {
    BuiltPart out;
    const bool whole = iv.f0 == 0.0 && iv.f1 == 1.0;
    if (whole) out.resident.emplace();
    measure::Scheduler scheduler(*lane.device);
    for (std::size_t gi = 0; gi < scene.geometries.size(); ++gi) {
        const Geometry& g = scene.geometries[gi];
        int split_level = -1;
        std::uint64_t total = 0;
        const construct::Subtrees subtrees{kSplitBricks, [&](const std::vector<SdfBrick>& records) {
            std::vector<std::uint64_t> prefix{0};
            for (const SdfBrick& r : records) prefix.push_back(prefix.back() + std::max<std::uint64_t>(1, r.edit_count));
            const auto range = covered(prefix, iv);
            split_level = records.empty() ? -1 : static_cast<int>(records.front().level);
            total = prefix.back();
            return range;
        }};
        // A lane with all of the stage picks nothing: it builds without reading the split level back.
        construct::GeometryBuild b = lane.tools().builder().build(g, s, scheduler, whole ? nullptr : &subtrees);
        HostBuild h;
        if (whole) {
            std::tie(split_level, total) = split_of(b, subtrees);
            out.resident->push_back(std::move(b));
        } else {
            HostBuild recycled = gi < lane.spare.size() ? std::move(lane.spare[gi]) : HostBuild{};
            h = to_host(b, lane, std::move(recycled));
        }
        h.split_level = split_level;
        h.total_weight = total;
        out.host.push_back(std::move(h));
    }
    lane.record(scheduler);
    return out;
}

// Sums level l of the parts' tables at and below the split level (above it every part built the same).
construct::LevelReport merged_level(const std::vector<const HostBuild*>& parts, std::size_t l) {
    const int split = parts.front()->split_level;
    construct::LevelReport r;
    for (const HostBuild* p : parts) {
        if (l >= p->meta.level_reports.size()) continue;
        if (split < 0 || static_cast<int>(l) < split) return p->meta.level_reports[l];
        if (l >= p->meta.level_reports.size()) continue;
        const construct::LevelReport& q = p->meta.level_reports[l];
        r.level = q.level;
        r.cell_size = q.cell_size;
        r.bricks += q.bricks;
        r.edit_entries += q.edit_entries;
        r.max_edits = std::max(r.max_edits, q.max_edits);
        r.count_ms += q.count_ms;
        r.scan_ms += q.scan_ms;
        r.subdivide_ms += q.subdivide_ms;
        r.cull_ms += q.cull_ms;
        r.leaves += q.leaves;
        r.plane_leaves += q.plane_leaves;
    }
    return r;
}

// The parts of one geometry, in order, as one build: leaves concatenated, each part's edit-list
// offsets moved past the lists before it.
HostBuild merge(const std::vector<const HostBuild*>& parts) {
    HostBuild m;
    // Domain, layout and settings as every part has them; the sums below start from zero.
    m.meta = parts.front()->meta;
    m.meta.level_reports.clear();
    m.meta.leaf_count = 0;
    m.meta.edits_per_leaf_mean = 0.0;
    m.meta.edits_per_leaf_max = 0;
    m.meta.edit_evaluations = 0;
    m.meta.work.clear();
    m.meta.memory.clear();
    m.meta.device_ms = m.meta.host_ms = 0.0;
    m.meta.check_error_max = m.meta.check_error_p99 = 0.0;
    m.meta.first_launch = m.meta.end_launch = 0;  // the parts' launches are in their lanes' recorders
    m.split_level = parts.front()->split_level;
    std::size_t levels = 0;
    for (const HostBuild* p : parts) levels = std::max(levels, p->meta.level_reports.size());
    for (std::size_t l = 0; l < levels; ++l) m.meta.level_reports.push_back(merged_level(parts, l));
    double entries = 0.0;
    for (const HostBuild* p : parts) {
        const auto base = static_cast<cl_uint>(m.lists.size());
        for (SdfBrick b : p->leaves) {
            b.edit_offset += base;
            m.leaves.push_back(b);
        }
        m.lists.insert(m.lists.end(), p->lists.begin(), p->lists.end());
        m.pool.insert(m.pool.end(), p->pool.begin(), p->pool.end());
        m.aabbs.insert(m.aabbs.end(), p->aabbs.begin(), p->aabbs.end());
        m.shifts.insert(m.shifts.end(), p->shifts.begin(), p->shifts.end());
        m.meta.leaf_count += p->meta.leaf_count;
        entries += p->meta.edits_per_leaf_mean * static_cast<double>(p->meta.leaf_count);
        m.meta.edits_per_leaf_max = std::max(m.meta.edits_per_leaf_max, p->meta.edits_per_leaf_max);
        m.meta.edit_evaluations += p->meta.edit_evaluations;
        // The check's worst error is the parts' worst; its 99th percentile is bounded by the parts'
        // largest (the per-leaf errors stay on the devices).
        m.meta.check_error_max = std::max(m.meta.check_error_max, p->meta.check_error_max);
        m.meta.check_error_p99 = std::max(m.meta.check_error_p99, p->meta.check_error_p99);
        m.meta.device_ms += p->meta.device_ms;
        m.meta.host_ms = std::max(m.meta.host_ms, p->meta.host_ms);
        for (const auto& [what, bytes] : p->meta.memory) m.meta.memory[what] += bytes;
        for (const auto& [stage, w] : p->meta.work) {
            construct::StageWork& sum = m.meta.work[stage];
            sum.flop += w.flop;
            sum.bytes += w.bytes;
            sum.evaluations += w.evaluations;
        }
    }
    if (m.meta.leaf_count > 0) m.meta.edits_per_leaf_mean = entries / static_cast<double>(m.meta.leaf_count);
    return m;
}

// A merged build on a device (its figures copied, its arrays uploaded).
construct::GeometryBuild upload(const HostBuild& h, ocl::Device& d) {
    construct::GeometryBuild b;
    b.info() = h.meta;
    b.leaves = std::make_unique<ocl::Buffer<SdfBrick>>(d, std::span<const SdfBrick>(h.leaves));
    b.leaf_edit_indices = std::make_unique<ocl::Buffer<cl_uint>>(d, std::span<const cl_uint>(h.lists));
    b.pool = std::make_unique<ocl::Buffer<std::uint8_t>>(d, std::span<const std::uint8_t>(h.pool));
    b.aabbs = std::make_unique<ocl::Buffer<SdfBounds>>(d, std::span<const SdfBounds>(h.aabbs));
    b.shifts = std::make_unique<ocl::Buffer<cl_uint>>(d, std::span<const cl_uint>(h.shifts));
    return b;
}

render::SceneBricks upload_scene(const std::vector<HostBuild>& merged, const construct::BuildSettings& s,
                                 ocl::Device& d) {
    render::SceneBricks out;
    out.settings = s;
    for (const HostBuild& h : merged) {
        out.builds.push_back(upload(h, d));
        out.bricks += h.meta.leaf_count;
        out.build_ms += h.meta.device_ms;
    }
    return out;
}

// The construction of a pass: on the device of the one lane that built all of it (resident), or
// merged on the host from the parts. A lane that traces without holding it gets a host copy, read
// back once (host_copy) where the construction is resident.
struct Merged {
    std::optional<std::size_t> lane;  // the lane whose device holds resident
    render::SceneBricks resident;
    std::vector<HostBuild> host;
    bool host_ready = false;
    std::mutex mutex;
    bool prepared = false;  // resident has its BVH and tracing arrays
};

// The merged arrays on the host: the host merge, or the resident build read back once (its copies
// counted on the lane that reads).
const std::vector<HostBuild>& host_copy(Merged& m, std::vector<SplitLane>& lanes) {
    std::lock_guard lock(m.mutex);
    if (!m.host_ready) {
        SplitLane& home = lanes[*m.lane];
        m.host.clear();
        for (const construct::GeometryBuild& b : m.resident.builds) m.host.push_back(to_host(b, home, {}));
        m.host_ready = true;
    }
    return m.host;
}

// The split construction: every geometry's parts, merged on the host unless one lane built all.
void split_construct(std::vector<SplitLane>& lanes, const Scene& scene, const SplitSpec& spec, const RateStore* basis,
                     StageSplit& report, Merged& merged) {
    report = start_report(lanes, "construct", scene, spec);
    const std::vector<double> weights = stage_weights(lanes, basis, report);
    auto parts = run_shared<BuiltPart>(lanes, weights, report, [&](SplitLane& lane, Interval iv) {
        return build_part(lane, scene, spec.build[lane.slot], iv);
    });
    for (std::size_t g = 0; g < scene.geometries.size(); ++g)
        report.work += static_cast<double>(parts.front().result.host[g].total_weight);
    if (parts.size() == 1 && parts.front().result.resident) {
        merged.lane = parts.front().lane;
        merged.resident.settings = spec.build[lanes[parts.front().lane].slot];
        for (construct::GeometryBuild& b : *parts.front().result.resident) {
            merged.resident.bricks += b.leaf_count;
            merged.resident.build_ms += b.device_ms;
            merged.resident.builds.push_back(std::move(b));
        }
    } else {
        for (std::size_t g = 0; g < scene.geometries.size(); ++g) {
            std::vector<const HostBuild*> of_g;
            for (const auto& p : parts) of_g.push_back(&p.result.host[g]);
            merged.host.push_back(merge(of_g));
        }
        merged.host_ready = true;
        for (auto& p : parts) lanes[p.lane].spare = std::move(p.result.host);
    }
    finish_report(report, spec.rates, lanes);
}

// ---- tracing ----

// The lane's own copy of the merged bricks, ready to trace. Every band needs all of it, so a device
// that cannot hold it leaves the run instead of taking smaller bands.
render::SceneBricks traced_copy(SplitLane& lane, const Scene& scene, const std::vector<HostBuild>& merged,
                                const construct::BuildSettings& settings, measure::Scheduler& scheduler) {
    try {
        std::uint64_t bytes = 0;
        for (const HostBuild& h : merged) bytes += h.bytes();
        render::SceneBricks b = lane.copy(bytes, [&] { return upload_scene(merged, settings, *lane.device); });
        render::prepare_tracing(lane.tools().bvh(), scene, b, scheduler);
        return b;
    } catch (const std::exception& e) {
        if (!out_of_memory(e)) throw;
        throw std::runtime_error(fmt::format("cannot hold the merged bricks and their BVH: {}", e.what()));
    }
}

// The split trace: bands of rows (in units of every device's work-group rows), merged into one image.
// A lane that traces every row keeps the image on its device: its digest is computed there and the
// image crosses only when `image` asks for it. Bands are read back and merged on the host.
render::TraceResult split_trace(std::vector<SplitLane>& lanes, const Scene& scene, Merged& merged, const SplitSpec& spec,
                                const RateStore* basis, StageSplit& report, bool image) {
    report = start_report(lanes, "trace", scene, spec);
    const std::vector<double> weights = stage_weights(lanes, basis, report);
    const render::TraceSettings& first = spec.trace.front();
    int unit = 1;
    for (const render::TraceSettings& t : spec.trace) {
        if (t.group_y < 1) throw SettingError("group_y", fmt::format("group_y must be positive, got {}", t.group_y));
        unit = std::lcm(unit, t.group_y);
    }
    std::vector<std::uint64_t> prefix;  // rows at each band boundary
    for (int r = 0; r < first.height; r += unit) prefix.push_back(static_cast<std::uint64_t>(r));
    prefix.push_back(static_cast<std::uint64_t>(first.height));
    const SdfCamera camera = make_camera(scene.camera, first.width, first.height);
    auto parts = run_shared<render::TraceResult>(lanes, weights, report, [&](SplitLane& lane, Interval iv) {
        measure::Scheduler scheduler(*lane.device);
        const bool home = merged.lane == lane.slot;
        if (home && !merged.prepared) {  // the lane that holds the construction traces it where it is
            render::prepare_tracing(lane.tools().bvh(), scene, merged.resident, scheduler);
            merged.prepared = true;
        }
        if (!home && !lane.traced)
            lane.traced = traced_copy(lane, scene, host_copy(merged, lanes), spec.build[lane.slot], scheduler);
        const auto [a, b] = covered(prefix, iv);
        const render::Rows rows{static_cast<int>(prefix[a]), static_cast<int>(prefix[b])};
        const bool whole = iv.f0 == 0.0 && iv.f1 == 1.0;
        render::TraceResult r =
            lane.tools().tracer().render(scene, home ? merged.resident : *lane.traced, camera, spec.trace[lane.slot],
                                        scheduler, rows, {!whole || image, whole && spec.trace_digests});
        lane.record(scheduler);
        return r;
    });
    report.work = static_cast<double>(first.width) * first.height;
    if (parts.size() == 1 && parts.front().span.f0 == 0.0 && parts.front().span.f1 == 1.0) {
        finish_report(report, spec.rates, lanes);
        return std::move(parts.front().result);
    }
    render::TraceResult out;
    out.work.pixels = static_cast<std::uint64_t>(first.width) * first.height;
    out.buffer = RenderBuffer(first.width, first.height);
    if (first.shade) out.colour = Image(first.width, first.height, 3);
    for (const auto& p : parts) {
        const auto [a, b] = covered(prefix, p.span);
        const std::size_t from = prefix[a] * first.width, to = prefix[b] * first.width;
        std::copy(p.result.buffer.hit.begin() + from, p.result.buffer.hit.begin() + to, out.buffer.hit.begin() + from);
        std::copy(p.result.buffer.aux.begin() + from, p.result.buffer.aux.begin() + to, out.buffer.aux.begin() + from);
        if (first.shade)
            std::copy(p.result.colour.pixels.begin() + 3 * from, p.result.colour.pixels.begin() + 3 * to,
                      out.colour.pixels.begin() + 3 * from);
        out.trace_ms += p.result.trace_ms;
        out.shade_ms += p.result.shade_ms;
        out.work += p.result.work;
    }
    if (spec.trace_digests) out.digest = buffer_digest(out.buffer);
    finish_report(report, spec.rates, lanes);
    return out;
}

// The merged bricks on the first live device that takes them (for digests and what follows): where
// they are when one lane holds the construction. The BVH and tracing arrays are made for them when
// the work needs them and the lane has not made them.
render::SceneBricks home_bricks(std::vector<SplitLane>& lanes, Merged& merged, const Scene& scene,
                                const SplitSpec& spec, std::size_t& home, double& bvh_wall) {
    const auto prepare = [&](SplitLane& l, render::SceneBricks b, bool prepared) {
        if (spec.work != Work::construct && !prepared) {
            measure::Scheduler scheduler(*l.device);
            detail::timed(bvh_wall, [&] { render::prepare_tracing(l.tools().bvh(), scene, b, scheduler); });
            l.record(scheduler);
        }
        return b;
    };
    if (merged.lane && lanes[*merged.lane].alive()) {
        home = *merged.lane;
        return prepare(lanes[home], std::move(merged.resident), merged.prepared);
    }
    for (SplitLane& l : lanes) {
        if (!l.alive()) continue;
        home = l.slot;
        if (l.traced) return std::move(*l.traced);
        try {
            return prepare(l, upload_scene(host_copy(merged, lanes), spec.build[l.slot], *l.device), false);
        } catch (const std::exception& e) {
            l.failure = e.what();
            l.error = std::current_exception();
        }
    }
    throw_all_failed(lanes);
}

// One pass: the construction split, the trace split (Work::trace), the merged bricks on their home
// lane, digests there. The pass's capture is every lane's launches, lane by lane.
detail::Pass split_pass(std::vector<SplitLane>& lanes, const Scene& scene, const SplitSpec& spec,
                        const RateStore* basis, bool last, SplitRun& out) {
    detail::Pass p;
    Merged merged;
    for (SplitLane& l : lanes) l.capture.clear();
    detail::timed(p.construct_wall, [&] { split_construct(lanes, scene, spec, basis, out.construct, merged); });
    if (spec.work == Work::trace) {
        for (SplitLane& l : lanes) l.traced.reset();
        p.trace = detail::timed(p.trace_wall, [&] {
            return split_trace(lanes, scene, merged, spec, basis, out.tracing, spec.image && last);
        });
        p.trace_digest = p.trace->digest;
    }
    p.bricks = home_bricks(lanes, merged, scene, spec, out.home, p.bvh_wall);
    if (spec.brick_digests) {
        BrickDigests d = detail::timed(p.digest_wall, [&] { return brick_digests(p.bricks, lanes[out.home].tools().digest()); });
        p.brick_digest = std::move(d.bricks);
        p.list_digest = std::move(d.lists);
    }
    for (SplitLane& l : lanes) {
        p.capture.insert(p.capture.end(), l.capture.begin(), l.capture.end());
        if (*l.slots) l.device->memory_pool()->trim();
    }
    return p;
}

// A lane's own figures over the captured passes: its launches (no bricks or image of its own).
Run lane_run(std::vector<measure::Capture> captures) {
    Run r;
    r.captures = std::move(captures);
    r.stages = measure::stage_stats(r.captures);
    r.total_ms = measure::total_stats(r.captures);
    return r;
}

}  // namespace

SplitRun run_split(std::vector<std::unique_ptr<Lane>>& slots, const std::vector<ocl::Device*>& devices,
                   const Scene& scene, const SplitSpec& spec) {
    if (devices.empty() || slots.size() != devices.size()) throw std::invalid_argument("run_split: one lane per device");
    if (spec.build.size() != devices.size() || (spec.work == Work::trace && spec.trace.size() != devices.size()))
        throw std::invalid_argument("run_split: one build (and trace) setting per device");
    std::vector<SplitLane> lanes(devices.size());
    for (std::size_t i = 0; i < devices.size(); ++i) {
        lanes[i].device = devices[i];
        lanes[i].slot = i;
        lanes[i].slots = &slots[i];
    }
    // Every pass splits by the rates stored before the run: a warm-up pass's rates include program
    // builds. The last pass's rates are stored.
    const std::optional<RateStore> basis = spec.rates ? std::optional<RateStore>(*spec.rates) : std::nullopt;
    SplitRun out;
    std::vector<std::vector<measure::Capture>> captures(devices.size());
    int pass = 0;
    out.job = detail::repeat_passes(spec.warmup, spec.repeat, [&](bool last) {
        detail::Pass p = split_pass(lanes, scene, spec, basis ? &*basis : nullptr, last, out);
        if (pass++ >= spec.warmup)
            for (std::size_t i = 0; i < lanes.size(); ++i) captures[i].push_back(lanes[i].capture);
        return p;
    });
    for (auto& c : captures) out.lanes.push_back(lane_run(std::move(c)));
    if (spec.rates) spec.rates->save();
    return out;
}

}  // namespace sdfbrick::pipeline
