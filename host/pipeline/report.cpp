#include "pipeline/report.h"

#include <algorithm>
#include <numeric>

#include <fmt/format.h>

#include "reference/surface_cells.h"

namespace sdfbrick::pipeline {

namespace {

double per_second(double count, double ms) { return ms > 0 ? count / (ms * 1e-3) : 0.0; }

GeometryFigures geometry_figures(const construct::GeometryBuild& b, const measure::Capture& last) {
    GeometryFigures g;
    g.name = b.name;
    g.origin = b.origin;
    g.leaf_size = b.leaf_size;
    g.levels = b.levels;
    g.clamp_c = b.clamp_c;
    g.band = b.band;
    g.level_table = b.level_reports;
    g.tolerance = b.tolerance;
    g.check_error_max = b.check_error_max;
    g.check_error_p99 = b.check_error_p99;
    g.brick_bytes = b.leaf_count > 0 && b.pool ? b.pool->bytes() / b.leaf_count : 0;
    g.bricks = b.leaf_count;
    g.edits_per_leaf_mean = b.edits_per_leaf_mean;
    g.edits_per_leaf_max = b.edits_per_leaf_max;
    g.edit_evaluations = b.edit_evaluations;
    g.dependency_entries = b.dependency_entries;
    g.pool_bytes = b.pool ? b.pool->bytes() : 0;
    g.memory = b.memory;
    g.work = b.work;
    g.device_ms = b.device_ms;
    g.host_ms = b.host_ms;
    if (b.end_launch <= last.size())
        g.launches.assign(last.begin() + static_cast<std::ptrdiff_t>(b.first_launch),
                          last.begin() + static_cast<std::ptrdiff_t>(b.end_launch));
    return g;
}

std::string memory_text(const Memory& memory) {
    std::string s;
    for (const auto& [name, bytes] : memory) s += fmt::format("{}{} {}", s.empty() ? "" : ", ", name, bytes_text(bytes));
    return s;
}

// Bricks kept per reference surface cell (1 when both are 0).
double kept_per_reference(const construct::LevelReport& l) {
    if (*l.reference_cells == 0) return l.bricks == 0 ? 1.0 : static_cast<double>(l.bricks);
    return static_cast<double>(l.bricks) / static_cast<double>(*l.reference_cells);
}

nlohmann::json to_json(const construct::LevelReport& l) {
    nlohmann::json j = {{"level", l.level}, {"cell_size", l.cell_size}, {"bricks", l.bricks}, {"leaves", l.leaves},
                        {"plane_leaves", l.plane_leaves}, {"edit_entries", l.edit_entries}, {"max_edits", l.max_edits},
                        {"count_ms", l.count_ms}, {"scan_ms", l.scan_ms}, {"subdivide_ms", l.subdivide_ms},
                        {"cull_ms", l.cull_ms}};
    if (l.reference_cells) {
        j["reference_cells"] = *l.reference_cells;
        j["kept_per_reference"] = kept_per_reference(l);
    }
    return j;
}

nlohmann::json to_json(const GeometryFigures& g) {
    nlohmann::json levels = nlohmann::json::array();
    for (const auto& l : g.level_table) levels.push_back(to_json(l));
    nlohmann::json launches = nlohmann::json::array();
    for (const auto& l : g.launches) launches.push_back(measure::to_json(l));
    return {{"name", g.name},
            {"bricks", g.bricks},
            {"levels", levels},
            {"origin", {g.origin.x, g.origin.y, g.origin.z}},
            {"leaf_size", g.leaf_size},
            {"clamp_c", g.clamp_c},
            {"band", g.band},
            {"tolerance", g.tolerance},
            {"check_error", {{"max", g.check_error_max}, {"p99", g.check_error_p99}}},
            {"edits_per_leaf", {{"mean", g.edits_per_leaf_mean}, {"max", g.edits_per_leaf_max}}},
            {"edit_evaluations", g.edit_evaluations},
            {"dependency_entries", g.dependency_entries},
            {"memory", g.memory},
            {"device_ms", g.device_ms},
            {"host_ms", g.host_ms},
            {"launches", launches}};
}

std::string to_text(const GeometryFigures& g) {
    std::string s = fmt::format("  geometry {}: {} leaf bricks of {} ({} levels), C = {:.4g}, band +-{:.4g}\n", g.name,
                                g.bricks, g.leaf_size, g.levels, g.clamp_c, g.band);
    if (g.tolerance > 0.0)
        s += fmt::format("    adaptive: tolerance {:.4g}; check points' worst error over the leaves: max {:.4g}, "
                         "p99 {:.4g}\n", g.tolerance, g.check_error_max, g.check_error_p99);
    const bool reference = !g.level_table.empty() && g.level_table.front().reference_cells.has_value();
    s += fmt::format("    level  cell      bricks   edits/brick  max   count ms  scan ms  subdiv ms  cull ms{}{}\n",
                     g.tolerance > 0.0 ? "     leaves     planes   leaf pool" : "", reference ? "  reference  kept/ref" : "");
    for (const auto& l : g.level_table) {
        s += fmt::format("    {:>5}  {:<8.4g} {:>9}  {:>11.2f}  {:>4}  {:>8.3f}  {:>7.3f}  {:>9.3f}  {:>7.3f}", l.level,
                         l.cell_size, l.bricks,
                         l.bricks ? static_cast<double>(l.edit_entries) / static_cast<double>(l.bricks) : 0.0,
                         l.max_edits, l.count_ms, l.scan_ms, l.subdivide_ms, l.cull_ms);
        if (g.tolerance > 0.0)
            s += fmt::format("  {:>9}  {:>9}  {:>10}", l.leaves, l.plane_leaves, bytes_text(l.leaves * g.brick_bytes));
        s += l.reference_cells ? fmt::format("  {:>9}  {:>8.3f}\n", *l.reference_cells, kept_per_reference(l)) : "\n";
    }
    s += fmt::format("    edits per leaf: mean {:.2f}, max {}; edit evaluations {:.4g}\n", g.edits_per_leaf_mean,
                     g.edits_per_leaf_max, static_cast<double>(g.edit_evaluations));
    s += "    memory: " + memory_text(g.memory) + "\n";
    return s;
}

}  // namespace

std::string bytes_text(std::uint64_t b) {
    if (b >= (1ull << 30)) return fmt::format("{:.2f} GiB", static_cast<double>(b) / (1ull << 30));
    if (b >= (1ull << 20)) return fmt::format("{:.2f} MiB", static_cast<double>(b) / (1ull << 20));
    if (b >= (1ull << 10)) return fmt::format("{:.1f} KiB", static_cast<double>(b) / (1ull << 10));
    return fmt::format("{} B", b);
}

// ---- wall time ----

WallBreakdown wall_breakdown(const Run& run) {
    return {run.wall_ms.median, run.construct_wall_ms.median, run.bvh_wall_ms.median, run.trace_wall_ms.median,
            run.digest_wall_ms.median, run.setup_ms};
}

nlohmann::json to_json(const WallBreakdown& w) {
    return {{"total", w.total}, {"construct", w.construct}, {"bvh", w.bvh}, {"trace", w.trace}, {"digests", w.digests},
            {"setup_once", w.setup}};
}

std::string to_text(const WallBreakdown& w) {
    std::string parts;
    for (const auto& [name, ms] : {std::pair{"construct", w.construct}, std::pair{"bvh", w.bvh},
                                   std::pair{"trace", w.trace}, std::pair{"digests", w.digests}})
        if (ms > 0.0) parts += fmt::format("{}{} {:.3f}", parts.empty() ? "" : ", ", name, ms);
    return fmt::format("wall {:.3f} ms a capture ({}){}", w.total, parts,
                       w.setup > 0.0 ? fmt::format(", setup {:.3f} ms once", w.setup) : "");
}

// ---- construction ----

double ConstructionFigures::edits_per_leaf_mean() const {
    return bricks ? static_cast<double>(leaf_edit_entries) / static_cast<double>(bricks) : 0.0;
}

ConstructionFigures construction_figures(const Run& run) {
    static const measure::Capture no_capture;
    const measure::Capture& last = run.captures.empty() ? no_capture : run.captures.back();
    ConstructionFigures c;
    for (const construct::GeometryBuild& b : run.bricks.builds) {
        GeometryFigures g = geometry_figures(b, last);
        c.bricks += g.bricks;
        c.edit_evaluations += g.edit_evaluations;
        c.pool_bytes += g.pool_bytes;
        if (!g.level_table.empty() && g.bricks > 0) c.leaf_edit_entries += g.level_table.back().edit_entries;
        c.edits_per_leaf_max = std::max(c.edits_per_leaf_max, g.edits_per_leaf_max);
        c.levels = std::max(c.levels, g.levels);
        c.host_ms += g.host_ms;
        for (const auto& [k, v] : g.memory) c.memory[k] += v;
        for (const auto& [stage, w] : g.work) {
            construct::StageWork& sum = c.work[stage];
            sum.flop += w.flop;
            sum.bytes += w.bytes;
            sum.evaluations += w.evaluations;
        }
        c.geometries.push_back(std::move(g));
    }
    return c;
}

// ---- build ----

double BuildFigures::bricks_per_second() const {
    return per_second(static_cast<double>(construction.bricks), total_ms.median);
}

double BuildFigures::edit_evaluations_per_second() const {
    return per_second(static_cast<double>(construction.edit_evaluations), total_ms.median);
}

BuildFigures build_figures(const Run& run, const ocl::DeviceInfo& device) {
    BuildFigures f;
    f.construction = construction_figures(run);
    f.stages = run.stages;
    f.total_ms = run.total_ms;
    f.wall_ms = run.wall_ms;
    f.wall = wall_breakdown(run);
    f.captures = run.captures.size();
    f.identical = run.identical;
    f.kernels = measure::kernel_rows(run.captures, device);
    f.digest = run.brick_digest;
    f.list_digest = run.list_digest;
    for (const auto& [stage, w] : f.construction.work)
        f.roofline.push_back({stage, measure::stage_median(f.stages, stage), w.flop, w.bytes});
    f.peaks = measure::cached_peaks(device);
    return f;
}

namespace {

nlohmann::json roofline_json(const BuildFigures& f) {
    nlohmann::json stages = nlohmann::json::array();
    for (const RooflineRow& r : f.roofline) {
        nlohmann::json j = {{"stage", std::string(to_string(r.stage))}, {"ms", r.ms}, {"flop", r.flop}, {"bytes", r.bytes},
                            {"gflops", r.gflops()}, {"gbps", r.gbps()},
                            {"flop_per_byte", r.bytes > 0.0 ? r.flop / r.bytes : 0.0}};
        if (f.peaks) {
            j["fma_peak_fraction"] = r.gflops() / f.peaks->fma_gflops;
            j["bandwidth_fraction"] = r.gbps() / f.peaks->bandwidth_gbps;
        }
        stages.push_back(j);
    }
    return {{"peaks", f.peaks ? measure::to_json(*f.peaks) : nlohmann::json()}, {"stages", stages}};
}

// One line per stage: FP32 throughput and compulsory traffic, and their shares of the device's peaks.
std::string roofline_text(const BuildFigures& f) {
    std::string s = f.peaks ? fmt::format("  roofline (peaks: {:.1f} GFLOP/s FP32 FMA, {:.1f} GB/s):\n", f.peaks->fma_gflops,
                                          f.peaks->bandwidth_gbps)
                            : std::string("  roofline (no cached peaks: run `devices --peaks` for the shares):\n");
    for (const RooflineRow& r : f.roofline) {
        s += fmt::format("    {:<9} {:>10.3f} ms  {:>10.4g} GFLOP  {:>9.3f} GFLOP/s", to_string(r.stage), r.ms, r.flop * 1e-9,
                         r.gflops());
        if (f.peaks) s += fmt::format(" ({:>5.1f}%)", 100.0 * r.gflops() / f.peaks->fma_gflops);
        s += fmt::format("  {:>9.4g} GB  {:>8.3f} GB/s", r.bytes * 1e-9, r.gbps());
        if (f.peaks) s += fmt::format(" ({:>5.2f}%)", 100.0 * r.gbps() / f.peaks->bandwidth_gbps);
        s += "\n";
    }
    return s;
}

}  // namespace

void add_reference_levels(ConstructionFigures& c, const Scene& scene, const construct::BuildSettings& s) {
    for (std::size_t i = 0; i < c.geometries.size() && i < scene.geometries.size(); ++i) {
        GeometryFigures& figures = c.geometries[i];
        const Geometry& g = scene.geometries[i];
        const Aabb box = bounds(g);
        if (box.empty() || figures.level_table.empty()) continue;
        construct::Domain domain = construct::make_domain(box, s.leaf_size, s.branching);
        domain.levels = figures.levels;
        const std::vector<std::uint64_t> cells = reference::count_surface_cells(g, domain);
        for (construct::LevelReport& l : figures.level_table)
            l.reference_cells = static_cast<std::size_t>(l.level) < cells.size() ? cells[l.level] : 0;
    }
}

nlohmann::json to_json(const BuildFigures& f) {
    const ConstructionFigures& c = f.construction;
    nlohmann::json geometries = nlohmann::json::array();
    for (const GeometryFigures& g : c.geometries) geometries.push_back(to_json(g));
    return {{"bricks", c.bricks},
            {"digest", f.digest},
            {"list_digest", f.list_digest},
            {"stages", measure::to_json(f.stages)},
            {"device_ms", f.total_ms.median},
            {"host_ms", c.host_ms},
            {"total_ms", measure::to_json(f.total_ms)},
            {"wall_ms", measure::to_json(f.wall_ms)},
            {"wall_breakdown_ms", to_json(f.wall)},
            {"captures", {{"repeat", f.captures}, {"identical", f.identical}}},
            {"kernels", measure::to_json(f.kernels)},
            {"memory", c.memory},
            {"edits_per_leaf", {{"mean", c.edits_per_leaf_mean()}, {"max", c.edits_per_leaf_max}}},
            {"edit_evaluations", c.edit_evaluations},
            {"bricks_per_second", f.bricks_per_second()},
            {"edit_evaluations_per_second", f.edit_evaluations_per_second()},
            {"geometries", geometries},
            {"roofline", roofline_json(f)}};
}

std::string to_text(const BuildFigures& f, bool kernel_table) {
    std::string s;
    for (const GeometryFigures& g : f.construction.geometries) s += to_text(g);
    std::string stages;
    for (const auto& st : f.stages)
        stages += fmt::format("{}{} {:.3f}", stages.empty() ? "" : ", ", to_string(st.stage), st.ms.median);
    s += fmt::format("  stages (device ms{}): {}; total {:.3f} ms; {}\n", f.captures > 1 ? ", medians" : "", stages,
                     f.total_ms.median, to_text(f.wall));
    if (f.captures > 1) {
        s += fmt::format("  total over {} captures: median {:.3f} ms, min {:.3f}, max {:.3f}, cv {:.2f}%\n", f.captures,
                         f.total_ms.median, f.total_ms.min, f.total_ms.max, 100.0 * f.total_ms.cv);
        s += measure::stage_table_text(f.stages, f.identical);
    }
    if (!f.roofline.empty()) s += roofline_text(f);
    if (kernel_table) s += measure::kernel_table_text(f.kernels);
    s += fmt::format("  digest {} (edit lists {})\n", f.digest, f.list_digest);
    return s;
}

// ---- render ----

Memory RenderFigures::memory() const {
    Memory m = bvh.memory;
    for (const auto& [k, v] : construction.memory) m[k] += v;
    if (combined_pool_bytes) m["combined pool"] = *combined_pool_bytes;
    return m;
}

double RenderFigures::rays_per_second() const {
    return per_second(static_cast<double>(width) * height, trace_ms.median);
}

RenderFigures render_figures(const Run& run, const RunSpec& spec, const ocl::DeviceInfo& device) {
    const render::SceneBricks& bricks = run.bricks;
    RenderFigures f;
    f.construction = construction_figures(run);
    f.bvh = {bricks.bvh.node_count, bricks.bvh.tlas_node_count,
             std::accumulate(bricks.bvh.tree_leaves.begin(), bricks.bvh.tree_leaves.end(), std::uint64_t{0}),
             bricks.bvh.instance_objects.size(), bricks.bvh.device_ms, bricks.bvh.memory};
    if (bricks.combined_pool) f.combined_pool_bytes = bricks.combined_pool->bytes();
    f.voxel_world = bricks.voxel_world;
    f.stages = run.stages;
    f.build_ms = run.build_ms;
    f.bvh_ms = run.bvh_ms;
    f.trace_ms = run.trace_ms;
    f.total_ms = run.total_ms;
    f.wall_ms = run.wall_ms;
    f.wall = wall_breakdown(run);
    f.warmup = spec.warmup;
    f.captures = run.captures.size();
    f.identical = run.identical;
    f.kernels = measure::kernel_rows(run.captures, device);
    f.width = spec.trace.width;
    f.height = spec.trace.height;
    f.group_x = spec.trace.group_x;
    f.group_y = spec.trace.group_y;
    f.shade = spec.trace.shade;
    if (run.trace) {
        f.work = run.trace->work.per_pixel();
        f.warnings = run.trace->warnings;
    }
    f.digest = run.trace_digest;
    return f;
}

nlohmann::json to_json(const RenderFigures& f) {
    nlohmann::json warnings = nlohmann::json::array();
    for (const render::TraceWarning& w : f.warnings) warnings.push_back(render::to_json(w));
    return {{"trace_group", {f.group_x, f.group_y}},
            {"stages", measure::to_json(f.stages)},
            {"build_ms", measure::to_json(f.build_ms)},
            {"bvh_ms", measure::to_json(f.bvh_ms)},
            {"trace_ms", measure::to_json(f.trace_ms)},
            {"total_ms", measure::to_json(f.total_ms)},
            {"wall_ms", measure::to_json(f.wall_ms)},
            {"wall_breakdown_ms", to_json(f.wall)},
            {"captures", {{"warmup", f.warmup}, {"repeat", f.captures}, {"identical", f.identical}}},
            {"bricks", f.construction.bricks},
            {"bvh", {{"nodes", f.bvh.nodes}, {"tlas_nodes", f.bvh.tlas_nodes}, {"leaves", f.bvh.leaves}, {"instances", f.bvh.instances},
                     {"device_ms", f.bvh.device_ms}}},
            {"memory", f.memory()},
            {"rays_per_second", f.rays_per_second()},
            {"work_per_pixel", {{"node_visits", f.work.node_visits}, {"brick_steps", f.work.brick_steps}}},
            {"capped_rays", f.work.capped_rays},
            {"warnings", warnings},
            {"digest", f.digest},
            {"voxel_world", f.voxel_world},
            {"kernels", measure::to_json(f.kernels)}};
}

std::string to_text(const RenderFigures& f, bool kernel_table) {
    const std::string shade =
        f.shade ? fmt::format(", shade {:.3f} ms", measure::stage_median(f.stages, measure::Stage::shade)) : "";
    std::string s = fmt::format("  build {:.3f} ms ({} bricks), bvh {:.3f} ms ({} nodes over {} bricks), trace {:.3f} ms "
                                "({:.3g} rays/s, {:.1f} node visits and {:.1f} brick steps per ray){}; device {:.3f} ms, {}\n",
                                f.build_ms.median, f.construction.bricks, f.bvh_ms.median, f.bvh.nodes, f.bvh.leaves,
                                f.trace_ms.median, f.rays_per_second(), f.work.node_visits, f.work.brick_steps, shade,
                                f.total_ms.median, to_text(f.wall));
    for (const render::TraceWarning& w : f.warnings) s += "  warning: " + w.message + "\n";
    if (f.captures > 1) s += measure::stage_table_text(f.stages, f.identical);
    if (kernel_table) s += measure::kernel_table_text(f.kernels);
    return s;
}

BuildFigures build_figures(const Execution& e) {
    BuildFigures f = build_figures(e.job(), e.home_lane().device);
    if (e.split) {
        f.kernels.clear();
        f.roofline.clear();
    }
    return f;
}

RenderFigures render_figures(const Execution& e) {
    const LaneSettings& s = e.home_lane().settings;
    RenderFigures f = render_figures(e.job(), {Work::trace, s.build, s.trace, e.warmup}, e.home_lane().device);
    if (e.split) f.kernels.clear();
    return f;
}

LaneFigures lane_figures(const Execution& e, std::size_t lane) {
    const LaneRun& l = e.lanes.at(lane);
    LaneFigures f;
    f.stages = l.run.stages;
    f.total_ms = l.run.total_ms;
    f.captures = l.run.captures.size();
    f.kernels = measure::kernel_rows(l.run.captures, l.device);
    if (e.construct_split) f.construct = e.construct_split->devices.at(lane);
    if (e.trace_split) f.trace = e.trace_split->devices.at(lane);
    return f;
}

namespace {

nlohmann::json share_json(const std::optional<DeviceShare>& d) {
    if (!d) return nullptr;
    return {{"planned", d->planned}, {"done", d->done}, {"busy_ms", d->busy_ms}, {"idle_ms", d->idle_ms},
            {"kernels_ms", d->kernels_ms}, {"copies_ms", d->copies_ms}, {"copied_bytes", d->copied_bytes},
            {"rate", d->rate}};
}

}  // namespace

nlohmann::json to_json(const LaneFigures& f) {
    return {{"stages", measure::to_json(f.stages)}, {"total_ms", measure::to_json(f.total_ms)},
            {"captures", f.captures}, {"kernels", measure::to_json(f.kernels)},
            {"construct_share", share_json(f.construct)}, {"trace_share", share_json(f.trace)}};
}

std::string to_text(const LaneFigures& f, bool kernel_table) {
    std::string s = fmt::format("  its launches: device {:.3f} ms a capture over {} captures\n", f.total_ms.median,
                                f.captures);
    if (f.captures > 1) s += measure::stage_table_text(f.stages, true);
    if (kernel_table) s += measure::kernel_table_text(f.kernels);
    return s;
}

nlohmann::json placement_json(const Execution& e) {
    nlohmann::json j = {{"placement", to_string(e.placement)}, {"home", e.home_lane().device.index}};
    if (e.construct_split) j["construct"] = to_json(*e.construct_split);
    if (e.trace_split) j["trace"] = to_json(*e.trace_split);
    return j;
}

std::string placement_text(const Execution& e) {
    std::string s;
    if (e.construct_split) s += to_text(*e.construct_split);
    if (e.trace_split) s += to_text(*e.trace_split);
    return s;
}

}  // namespace sdfbrick::pipeline
