// `sdfbrick build`: sparse brick construction of every geometry of a scene on each selected device,
// with a per-stage and per-level report, memory per resource, and digests that are equal iff the
// outputs are bit-identical (across repeats, culling modes and devices).
#include <algorithm>
#include <cstdio>
#include <memory>

#include <fmt/format.h>

#include "pipeline/run.h"
#include "cli/build_flags.h"
#include "cli/commands.h"
#include "core/errors.h"
#include "core/files.h"
#include "core/hash.h"
#include "measure/statistics.h"
#include "scene/scene_json.h"

namespace sdfbrick::cli {

namespace {

struct BuildOptions {
    std::string file;
    std::optional<double> time;
    BuildFlags flags;
    MeasureFlags measure;
    std::optional<std::string> json;
};

std::string bytes_text(std::uint64_t b) {
    if (b >= (1ull << 30)) return fmt::format("{:.2f} GiB", static_cast<double>(b) / (1ull << 30));
    if (b >= (1ull << 20)) return fmt::format("{:.2f} MiB", static_cast<double>(b) / (1ull << 20));
    if (b >= (1ull << 10)) return fmt::format("{:.1f} KiB", static_cast<double>(b) / (1ull << 10));
    return fmt::format("{} B", b);
}

struct DeviceRun {
    construct::BuildSettings settings;  // with the tuning applied
    tune::Applied tuning;
    pipeline::Run run;
    std::vector<measure::KernelRow> kernels;
    const std::vector<construct::GeometryBuild>& builds() const { return run.bricks.builds; }
};

DeviceRun run_device(ocl::Device& device, const Scene& scene, const BuildOptions& o, const tune::TuningDb* db) {
    DeviceRun d;
    d.settings = o.flags.resolve();
    d.tuning = tune::apply_tuning(db, device.info(), o.flags.given(), d.settings, nullptr);
    d.settings.validate(device.info());
    pipeline::Runner runner(device);
    d.run = runner.run(scene, {pipeline::Work::construct, d.settings, {}, o.measure.warmups(), o.measure.repeat, true});
    d.kernels = measure::kernel_rows(d.run.captures, device.info());
    return d;
}

std::string report_text(const ocl::Device& device, const DeviceRun& run, const BuildOptions& o) {
    std::string s = fmt::format("device {} [{}]\n  {}\n", device.info().index, device.info().name, run.tuning.text);
    for (const auto& b : run.builds()) {
        s += fmt::format("  geometry {}: {} leaf bricks of {} ({} levels), C = {:.4g}, band +-{:.4g}\n", b.name,
                         b.leaf_count, b.leaf_size, b.levels, b.clamp_c, b.band);
        s += "    level  cell      bricks   edits/brick  max   count ms  scan ms  subdiv ms  cull ms\n";
        for (const auto& l : b.level_reports)
            s += fmt::format("    {:>5}  {:<8.4g} {:>9}  {:>11.2f}  {:>4}  {:>8.3f}  {:>7.3f}  {:>9.3f}  {:>7.3f}\n", l.level,
                             l.cell_size, l.bricks,
                             l.bricks ? static_cast<double>(l.edit_entries) / static_cast<double>(l.bricks) : 0.0,
                             l.max_edits, l.count_ms, l.scan_ms, l.subdivide_ms, l.cull_ms);
        s += fmt::format("    edits per leaf: mean {:.2f}, max {}; edit evaluations {:.4g}\n", b.edits_per_leaf_mean,
                         b.edits_per_leaf_max, static_cast<double>(b.edit_evaluations));
        std::string mem;
        for (const auto& [name, bytes] : b.memory) mem += fmt::format("{}{} {}", mem.empty() ? "" : ", ", name, bytes_text(bytes));
        s += "    memory: " + mem + "\n";
    }
    std::string stages;
    for (const auto& st : run.run.stages) stages += fmt::format("{}{} {:.3f}", stages.empty() ? "" : ", ", to_string(st.stage), st.ms.median);
    s += fmt::format("  stages (device ms{}): {}; total {:.3f} ms\n", run.run.captures.size() > 1 ? ", medians" : "", stages,
                     run.run.total_ms.median);
    if (run.run.captures.size() > 1) {
        s += fmt::format("  total over {} captures: median {:.3f} ms, min {:.3f}, max {:.3f}, cv {:.2f}%\n",
                         run.run.captures.size(), run.run.total_ms.median, run.run.total_ms.min, run.run.total_ms.max, 100.0 * run.run.total_ms.cv);
        s += measure::stage_table_text(run.run.stages, run.run.identical);
    }
    if (o.measure.kernel_stats) s += measure::kernel_table_text(run.kernels);
    s += fmt::format("  digest {} (edit lists {})\n", run.run.brick_digest, run.run.list_digest);
    return s;
}

nlohmann::json device_json(const ocl::Device& device, const DeviceRun& run) {
    std::uint64_t bricks = 0, evaluations = 0, entries = 0;
    std::uint32_t max_edits = 0;
    std::map<std::string, std::uint64_t> memory;
    nlohmann::json geometries = nlohmann::json::array();
    double host_ms = 0.0;
    for (const auto& b : run.builds()) {
        bricks += b.leaf_count;
        evaluations += b.edit_evaluations;
        entries += b.level_reports.empty() ? 0 : b.level_reports.back().edit_entries * (b.leaf_count > 0);
        max_edits = std::max(max_edits, b.edits_per_leaf_max);
        host_ms += b.host_ms;
        for (const auto& [k, v] : b.memory) memory[k] += v;
        nlohmann::json levels = nlohmann::json::array();
        for (const auto& l : b.level_reports)
            levels.push_back({{"level", l.level}, {"cell_size", l.cell_size}, {"bricks", l.bricks},
                              {"edit_entries", l.edit_entries}, {"max_edits", l.max_edits},
                              {"count_ms", l.count_ms}, {"scan_ms", l.scan_ms}, {"subdivide_ms", l.subdivide_ms},
                              {"cull_ms", l.cull_ms}});
        nlohmann::json launches = nlohmann::json::array();
        const measure::Capture& last = run.run.captures.back();
        for (std::size_t i = b.first_launch; i < b.end_launch; ++i) launches.push_back(measure::to_json(last[i]));
        geometries.push_back({{"name", b.name}, {"bricks", b.leaf_count}, {"levels", levels},
                              {"origin", {b.origin.x, b.origin.y, b.origin.z}}, {"leaf_size", b.leaf_size},
                              {"clamp_c", b.clamp_c}, {"band", b.band},
                              {"edits_per_leaf", {{"mean", b.edits_per_leaf_mean}, {"max", b.edits_per_leaf_max}}},
                              {"edit_evaluations", b.edit_evaluations}, {"dependency_entries", b.dependency_entries},
                              {"memory", b.memory}, {"device_ms", b.device_ms}, {"host_ms", b.host_ms},
                              {"launches", launches}});
    }
    const double ms = run.run.total_ms.median;
    const double seconds = ms * 1e-3;
    return {{"device", device.info().to_json()},
            {"settings", settings_json(run.settings)},
            {"tuning", run.tuning.record},
            {"bricks", bricks},
            {"digest", run.run.brick_digest},
            {"list_digest", run.run.list_digest},
            {"stages", measure::to_json(run.run.stages)},
            {"device_ms", ms},
            {"host_ms", host_ms},
            {"total_ms", measure::to_json(run.run.total_ms)},
            {"captures", {{"repeat", run.run.captures.size()}, {"identical", run.run.identical}}},
            {"kernels", measure::to_json(run.kernels)},
            {"memory", memory},
            {"edits_per_leaf", {{"mean", bricks ? static_cast<double>(entries) / static_cast<double>(bricks) : 0.0}, {"max", max_edits}}},
            {"edit_evaluations", evaluations},
            {"bricks_per_second", seconds > 0 ? static_cast<double>(bricks) / seconds : 0.0},
            {"edit_evaluations_per_second", seconds > 0 ? static_cast<double>(evaluations) / seconds : 0.0},
            {"geometries", geometries}};
}

void run_build(BuildOptions o, const GlobalOptions& global) {
    apply_global_options(global);
    const construct::BuildSettings settings = o.flags.resolve();
    const Scene file_scene = load_scene(o.file);
    const double t = o.time.value_or(file_scene.time);
    const Scene scene = scene_at(file_scene, t);
    ocl::DeviceSet devices = ocl::DeviceSet::open(global.device);
    const TuningChoice tuning = open_tuning(global);

    std::string text = fmt::format("build {} ({}), t = {} s: brick size {}, branching {}, {}^3 samples, {}, "
                                   "culling {}{}, guard {}\n",
                                   scene.name, o.file, t, settings.leaf_size, settings.branching, settings.samples,
                                   construct::to_string(settings.format), settings.cull ? "on" : "off",
                                   settings.dependencies ? " with dependencies" : "", settings.guard);
    nlohmann::json device_reports = nlohmann::json::array();
    std::string first_digest, first_lists;
    bool agree = true, lists_agree = true;
    for (ocl::Device& device : devices) {
        const DeviceRun run = run_device(device, scene, o, tuning.get());
        text += report_text(device, run, o);
        device_reports.push_back(device_json(device, run));
        if (first_digest.empty()) {
            first_digest = run.run.brick_digest;
            first_lists = run.run.list_digest;
        } else {
            agree = agree && run.run.brick_digest == first_digest;
            lists_agree = lists_agree && run.run.list_digest == first_lists;
        }
    }
    if (devices.size() > 1)
        text += fmt::format("devices agree bit for bit: bricks and pool {}, edit lists {}\n", agree ? "yes" : "NO",
                            lists_agree ? "yes" : "NO");
    if (o.json) {
        const nlohmann::json& first = device_reports[0];
        nlohmann::json report = {
            {"command", "build"},
            {"scene", {{"file", o.file}, {"name", scene.name}, {"time", t}, {"geometries", scene.geometries.size()}}},
            {"settings", first["settings"]},
            {"tuning", first["tuning"]},
            {"tuning_db", tuning.path ? nlohmann::json(tuning.path->string()) : nlohmann::json(nullptr)},
            {"repeat", o.measure.repeat},
            {"warmup", o.measure.warmups()},
            {"bricks", first["bricks"]},
            {"digest", first["digest"]},
            {"stages", first["stages"]},
            {"memory", first["memory"]},
            {"devices", device_reports},
            {"devices_agree", agree},
            {"edit_lists_agree", lists_agree}};
        write_file_atomic(*o.json, format_json(report));
        text += fmt::format("report: {}\n", *o.json);
    }
    std::fputs(text.c_str(), stdout);
}

}  // namespace

void add_build_command(CLI::App& app, const GlobalOptions& global) {
    auto o = std::make_shared<BuildOptions>();
    auto* cmd = app.add_subcommand("build", "Build the sparse brick set of every geometry of a scene on each selected "
                                            "device: per-stage and per-level times, memory, digests");
    cmd->add_option("file", o->file, "scene file (JSON)")->required();
    cmd->add_option("--time", o->time, "animation time in seconds (default: the scene's)");
    o->flags.add_to(cmd);
    o->measure.add_to(cmd, "build");
    cmd->add_option("--json", o->json, "write a JSON report here");
    cmd->callback([o, &global] { run_build(*o, global); });
}

}  // namespace sdfbrick::cli
