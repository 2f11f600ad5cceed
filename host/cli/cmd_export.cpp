// `sdfbrick export` and `sdfbrick sample`: a scene's brick set built on one device and read back, then
// written as OpenVDB / NanoVDB level sets (export) or sampled at the points of a file beside the
// double-precision reference field (sample).
#include <chrono>
#include <cstdio>
#include <functional>
#include <memory>

#include <fmt/format.h>

#include "cli/build_flags.h"
#include "cli/commands.h"
#include "core/errors.h"
#include "core/files.h"
#include "exchange/sample.h"
#include "exchange/vdb.h"
#include "pipeline/command_report.h"
#include "pipeline/executor.h"
#include "tune/apply.h"
#include "scene/scene_json.h"

namespace sdfbrick::cli {

namespace {

struct SceneOptions {
    std::string file;
    std::optional<double> time;
    BuildFlags flags;
    std::optional<std::string> json;
};

// A scene's bricks on the host: what was built, on which device, and what it cost.
struct HostScene {
    Scene scene;
    std::string device;
    construct::BuildSettings settings;
    std::vector<exchange::HostBricks> bricks;  // per geometry
    std::uint64_t brick_count = 0, pool_bytes = 0;
    double build_ms = 0.0;     // construction device time
    double readback_ms = 0.0;  // host wall time of reading leaves and pools back
};

// The bricks on the first device that --device selects, or shared by the devices with --devices split
// (merged on the home device), then read back to the host. held(layout): the host bytes the command
// holds per leaf brick beyond the copy read back (its grids); a build whose projected leaves would
// not fit in the host's memory is refused before its leaves are made.
HostScene build_on_host(const SceneOptions& o, const GlobalOptions& global,
                        const std::function<double(const construct::BrickLayout&)>& held = {}) {
    apply_global_options(global, true);
    const Scene file_scene = load_scene_warned(o.file);
    HostScene h;
    h.scene = scene_at(file_scene, o.time.value_or(file_scene.time));
    const std::unique_ptr<RunDevices> devices = open_run_devices(global);
    const TuningChoice tuning = open_tuning(global);
    pipeline::Job job;
    job.work = pipeline::Work::construct;
    construct::BuildSettings settings = o.flags.resolve();
    settings.host_bytes_per_leaf =
        exchange::HostBricks::bytes_per_brick(settings.layout()) + (held ? held(settings.layout()) : 0.0);
    job.settings = tune::settings_for(settings, std::nullopt, tuning.get(), o.flags.given());
    job.brick_digests = false;
    job.image = false;
    job.rates = devices->rates ? &*devices->rates : nullptr;
    const bool split = devices->placement == pipeline::Placement::split;
    const pipeline::Execution e =
        devices->executor.run(h.scene, job, split ? pipeline::Placement::split : pipeline::Placement::whole);
    const pipeline::Run& run = e.job();
    h.device = e.home_lane().device.name;
    h.settings = e.home_lane().settings.build;
    const auto start = std::chrono::steady_clock::now();
    for (const construct::GeometryBuild& b : run.bricks.builds) {
        h.bricks.emplace_back(b, h.settings);
        h.brick_count += b.leaf_count;
        h.pool_bytes += b.pool->bytes();
    }
    h.readback_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    h.build_ms = run.bricks.build_ms;
    return h;
}

nlohmann::json host_scene_json(const HostScene& h, const SceneOptions& o) {
    return {{"scene", {{"file", o.file}, {"name", h.scene.name}, {"time", h.scene.time}}},
            {"device", h.device},
            {"settings", pipeline::settings_json(h.settings)},
            {"bricks", h.brick_count},
            {"pool_bytes", h.pool_bytes},
            {"build_ms", h.build_ms},
            {"readback_ms", h.readback_ms}};
}

std::string host_scene_text(const HostScene& h, const SceneOptions& o) {
    return fmt::format("{} ({}), t = {} s on {}: {} bricks ({}, {}^3 samples), pool {} bytes, built in {:.3f} ms, "
                       "read back in {:.3f} ms\n",
                       h.scene.name, o.file, h.scene.time, h.device, h.brick_count, construct::to_string(h.settings.format),
                       h.settings.samples, h.pool_bytes, h.build_ms, h.readback_ms);
}

// ---- export ----

struct ExportOptions : SceneOptions {
    std::optional<std::string> vdb, nvdb;
};

nlohmann::json to_json(const exchange::VdbExport& e) {
    nlohmann::json grids = nlohmann::json::array();
    for (const exchange::VdbGridRecord& g : e.grids)
        grids.push_back({{"name", g.name}, {"geometry", g.geometry}, {"active_voxels", g.active_voxels},
                         {"voxel_size", g.voxel_size}, {"background", g.background}, {"quantum", g.quantum}});
    return {{"format", exchange::to_string(e.format)}, {"path", e.path.string()}, {"file_bytes", e.file_bytes},
            {"ms", e.ms}, {"grids", grids}};
}

std::string to_text(const exchange::VdbExport& e) {
    std::string s = fmt::format("{} {}: {} grids, {} bytes, written in {:.1f} ms\n", exchange::to_string(e.format),
                                e.path.string(), e.grids.size(), e.file_bytes, e.ms);
    for (const exchange::VdbGridRecord& g : e.grids)
        s += fmt::format("  {} (geometry {}): level set, {} active voxels, voxel {:.6g}, background {:.6g}\n", g.name,
                         g.geometry, g.active_voxels, g.voxel_size, g.background);
    return s;
}

void run_export(const ExportOptions& o, const GlobalOptions& global) {
    if (!o.vdb && !o.nvdb) throw InputError("export: give --vdb FILE, --nvdb FILE or both");
    if (o.vdb) exchange::require_vdb(exchange::VdbFormat::openvdb);
    if (o.nvdb) exchange::require_vdb(exchange::VdbFormat::nanovdb);
    std::vector<std::filesystem::path> paths;
    for (const auto* path : {&o.vdb, &o.nvdb, &o.json})
        if (*path) paths.emplace_back(**path);
    check_output_paths(paths);
    const HostScene h = build_on_host(o, global, [&](const construct::BrickLayout& layout) {
        return (o.vdb ? exchange::grid_bytes_per_brick(layout, exchange::VdbFormat::openvdb) : 0.0) +
               (o.nvdb ? exchange::grid_bytes_per_brick(layout, exchange::VdbFormat::nanovdb) : 0.0);
    });
    std::vector<exchange::VdbFile> files;
    if (o.vdb) files.push_back(exchange::make_vdb(h.scene, h.bricks, *o.vdb, exchange::VdbFormat::openvdb));
    if (o.nvdb) files.push_back(exchange::make_vdb(h.scene, h.bricks, *o.nvdb, exchange::VdbFormat::nanovdb));
    std::vector<Output> outputs;
    for (const exchange::VdbFile& f : files) outputs.push_back(f.output);
    if (o.json)  // made when written, after the files it describes (their sizes)
        outputs.push_back({*o.json, [&](std::ostream& os) {
                               nlohmann::json j = host_scene_json(h, o);
                               j["command"] = "export";
                               j["files"] = nlohmann::json::array();
                               for (const exchange::VdbFile& f : files) j["files"].push_back(to_json(f.written()));
                               os << format_json(j);
                           }});
    write_all(outputs);
    std::string text = "export " + host_scene_text(h, o);
    for (const exchange::VdbFile& f : files) text += to_text(f.written());
    if (o.json) text += fmt::format("report: {}\n", *o.json);
    std::fputs(text.c_str(), stdout);
}

// ---- sample ----

struct SampleOptions : SceneOptions {
    std::string points;
    std::string out;
};

void run_sample(const SampleOptions& o, const GlobalOptions& global) {
    const std::vector<glm::dvec3> points = exchange::read_points(o.points);
    std::vector<std::filesystem::path> paths{o.out};
    if (o.json) paths.emplace_back(*o.json);
    check_output_paths(paths);
    const HostScene h = build_on_host(o, global);
    const auto start = std::chrono::steady_clock::now();
    const std::vector<exchange::PointSample> samples = exchange::sample_points(h.scene, h.bricks, points);
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    std::vector<Output> outputs{text_output(o.out, exchange::samples_csv(samples))};
    std::size_t in_band = 0, unsaturated = 0;
    double max_error = 0.0;
    for (const exchange::PointSample& s : samples) {
        if (!s.distance) continue;
        ++in_band;
        if (s.saturated) continue;
        ++unsaturated;
        max_error = std::max(max_error, std::abs(*s.distance - s.reference));
    }
    std::string text = "sample " + host_scene_text(h, o) +
                       fmt::format("{} points from {}: {} inside bricks ({} within the band), sampled with the "
                                   "reference in {:.1f} ms; max |bricks - reference| within the band {:.4g}; "
                                   "written to {}\n",
                                   points.size(), o.points, in_band, unsaturated, ms, max_error, o.out);
    if (o.json) {
        nlohmann::json j = host_scene_json(h, o);
        j["command"] = "sample";
        j["points"] = {{"file", o.points}, {"count", points.size()}, {"inside_bricks", in_band},
                       {"within_band", unsaturated}, {"max_abs_difference", max_error}, {"ms", ms}, {"out", o.out}};
        outputs.push_back(text_output(*o.json, format_json(j)));
        text += fmt::format("report: {}\n", *o.json);
    }
    write_all(outputs);
    std::fputs(text.c_str(), stdout);
}

void add_scene_options(CLI::App* cmd, SceneOptions& o) {
    cmd->add_option("file", o.file, "scene file (JSON)")->required();
    cmd->add_option("--time", o.time, "animation time in seconds (default: the scene's)");
    o.flags.add_to(cmd);
    cmd->add_option("--json", o.json, "write a JSON report here");
}

}  // namespace

void add_export_commands(CLI::App& app, const GlobalOptions& global) {
    auto e = std::make_shared<ExportOptions>();
    auto* exp = app.add_subcommand("export", "Build a scene's bricks on one device and write them as narrow-band "
                                             "level sets, one grid per object in world units (OpenVDB, NanoVDB)");
    add_scene_options(exp, *e);
    exp->add_option("--vdb", e->vdb, "OpenVDB file to write (.vdb)");
    exp->add_option("--nvdb", e->nvdb, "NanoVDB file to write (.nvdb)");
    exp->callback([e, &global] { run_export(*e, global); });

    auto s = std::make_shared<SampleOptions>();
    auto* smp = app.add_subcommand("sample", "Build a scene's bricks on one device and write the distance and gradient "
                                             "they give at the points of a file, with the reference field's value");
    add_scene_options(smp, *s);
    smp->add_option("--points", s->points, "points: .csv (x,y,z a line) or binary float32 x y z triples")->required();
    smp->add_option("-o,--out", s->out, "CSV to write: x,y,z,distance,gx,gy,gz,object,saturated,reference")
        ->required();
    smp->callback([s, &global] { run_sample(*s, global); });
}

}  // namespace sdfbrick::cli
