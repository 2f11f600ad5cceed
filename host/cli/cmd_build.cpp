// `sdfbrick build`: sparse brick construction of every geometry of a scene on each selected device,
// with a per-stage and per-level report, memory per resource, and digests that are equal iff the
// outputs are bit-identical (across repeats, culling modes and devices).
#include <cstdio>
#include <filesystem>
#include <memory>

#include <fmt/format.h>

#include "cli/build_flags.h"
#include "cli/commands.h"
#include "core/errors.h"
#include "core/files.h"
#include "pipeline/report.h"
#include "pipeline/executor.h"
#include "scene/scene_json.h"
#include "tune/apply.h"

namespace sdfbrick::cli {

namespace {

struct BuildOptions {
    std::string file;
    std::optional<double> time;
    BuildFlags flags;
    MeasureFlags measure;
    std::optional<std::string> json;
    bool reference_levels = false;
};

// One device's part of the build report: its run of the job (whole, replicate) or its launches and
// shares of the job (split).
struct DeviceBuildReport {
    ocl::DeviceInfo device;
    pipeline::LaneSettings settings;  // with the tuning applied
    std::optional<pipeline::BuildFigures> figures;
    std::optional<pipeline::LaneFigures> lane;
};

// The whole command's report: the scene, the settings as given, the job's figures, every device's
// part and whether the devices agree bit for bit.
struct BuildReport {
    std::string file, scene;
    double time = 0.0;
    std::size_t geometries = 0;
    construct::BuildSettings settings;  // as given (each device applies its tuning)
    std::optional<std::filesystem::path> tuning_db;
    int repeat = 1, warmup = 0;
    pipeline::BuildFigures job;
    nlohmann::json placement;
    std::string placement_text;
    std::vector<DeviceBuildReport> devices;
    bool devices_agree = true, edit_lists_agree = true;
    std::optional<std::string> json_path;  // where the JSON report was written
};

nlohmann::json to_json(const DeviceBuildReport& d) {
    nlohmann::json j = d.figures ? pipeline::to_json(*d.figures) : pipeline::to_json(*d.lane);
    j["device"] = d.device.to_json();
    j["settings"] = settings_json(d.settings.build);
    j["tuning"] = d.settings.tuning;
    return j;
}

std::string to_text(const DeviceBuildReport& d, bool kernel_table) {
    return fmt::format("device {} [{}]\n  {}\n", d.device.index, d.device.name, d.settings.tuning_text) +
           (d.figures ? pipeline::to_text(*d.figures, kernel_table) : pipeline::to_text(*d.lane, kernel_table));
}

nlohmann::json to_json(const BuildReport& r) {
    nlohmann::json devices = nlohmann::json::array();
    for (const DeviceBuildReport& d : r.devices) devices.push_back(to_json(d));
    nlohmann::json j = pipeline::to_json(r.job);
    j.update({{"command", "build"},
              {"scene", {{"file", r.file}, {"name", r.scene}, {"time", r.time}, {"geometries", r.geometries}}},
              {"settings", devices.at(0)["settings"]},
              {"tuning", devices.at(0)["tuning"]},
              {"tuning_db", r.tuning_db ? nlohmann::json(r.tuning_db->string()) : nlohmann::json(nullptr)},
              {"repeat", r.repeat},
              {"warmup", r.warmup},
              {"placement", r.placement},
              {"devices", devices},
              {"devices_agree", r.devices_agree},
              {"edit_lists_agree", r.edit_lists_agree}});
    return j;
}

std::string to_text(const BuildReport& r, bool kernel_table) {
    const construct::BuildSettings& s = r.settings;
    std::string text = fmt::format("build {} ({}), t = {} s: brick size {}, branching {}, {}^3 samples, {}, "
                                   "culling {}{}, guard {}\n",
                                   r.scene, r.file, r.time, s.leaf_size, s.branching, s.samples,
                                   construct::to_string(s.format), s.cull ? "on" : "off",
                                   s.dependencies ? " with dependencies" : "", s.guard);
    if (!r.placement_text.empty())
        text += fmt::format("split over {} devices:\n", r.devices.size()) + pipeline::to_text(r.job, kernel_table) +
                r.placement_text;
    for (const DeviceBuildReport& d : r.devices) text += to_text(d, kernel_table);
    if (r.devices.size() > 1 && r.placement_text.empty())
        text += fmt::format("devices agree bit for bit: bricks and pool {}, edit lists {}\n",
                            r.devices_agree ? "yes" : "NO", r.edit_lists_agree ? "yes" : "NO");
    if (r.json_path) text += fmt::format("report: {}\n", *r.json_path);
    return text;
}

// The report's job, devices and agreement from an execution.
void add_execution(BuildReport& report, const pipeline::Execution& e, const Scene& scene, const BuildOptions& o) {
    report.job = pipeline::build_figures(e);
    if (o.reference_levels) pipeline::add_reference_levels(report.job.construction, scene, e.home_lane().settings.build);
    report.placement = pipeline::placement_json(e);
    report.placement_text = pipeline::placement_text(e);
    for (std::size_t i = 0; i < e.lanes.size(); ++i) {
        DeviceBuildReport d{e.lanes[i].device, e.lanes[i].settings, {}, {}};
        if (e.split) {
            d.lane = pipeline::lane_figures(e, i);
        } else {
            d.figures = i == e.home ? report.job : pipeline::build_figures(e.lanes[i].run, d.device);
            report.devices_agree = report.devices_agree && d.figures->digest == report.job.digest;
            report.edit_lists_agree = report.edit_lists_agree && d.figures->list_digest == report.job.list_digest;
        }
        report.devices.push_back(std::move(d));
    }
}

void run_build(const BuildOptions& o, const GlobalOptions& global) {
    apply_global_options(global, true);
    BuildReport report;
    report.settings = o.flags.resolve();
    if (o.json) check_output_path(*o.json);
    const Scene file_scene = load_scene(o.file);
    report.file = o.file;
    report.time = o.time.value_or(file_scene.time);
    const Scene scene = scene_at(file_scene, report.time);
    report.scene = scene.name;
    report.geometries = scene.geometries.size();
    report.repeat = o.measure.repeat;
    report.warmup = o.measure.warmups();
    const std::unique_ptr<RunDevices> devices = open_run_devices(global);
    const TuningChoice tuning = open_tuning(global);
    report.tuning_db = tuning.path;
    pipeline::Job job;
    job.work = pipeline::Work::construct;
    job.settings = tune::settings_for(report.settings, std::nullopt, tuning.get(), o.flags.given());
    job.warmup = o.measure.warmups();
    job.repeat = o.measure.repeat;
    job.image = false;
    job.rates = devices->rates ? &*devices->rates : nullptr;
    add_execution(report, devices->executor.run(scene, job, devices->placement), scene, o);
    if (o.json) {
        write_file_atomic(*o.json, format_json(to_json(report)));
        report.json_path = *o.json;
    }
    std::fputs(to_text(report, o.measure.kernel_stats).c_str(), stdout);
}

}  // namespace

void add_build_command(CLI::App& app, const GlobalOptions& global) {
    auto o = std::make_shared<BuildOptions>();
    auto* cmd = app.add_subcommand("build", "Build the sparse brick set of every geometry of a scene on each selected "
                                            "device: per-stage and per-level times, memory, digests");
    cmd->add_option("file", o->file, "scene file (JSON)")->required();
    cmd->add_option("--time", o->time, "animation time in seconds (default: the scene's)")->check(finite_number());
    o->flags.add_to(cmd);
    o->measure.add_to(cmd, "build");
    cmd->add_option("--json", o->json, "write a JSON report here");
    cmd->add_flag("--reference-levels", o->reference_levels,
                  "also count each level's surface cells with the double-precision host reference (slow)");
    cmd->callback([o, &global] { run_build(*o, global); });
}

}  // namespace sdfbrick::cli
