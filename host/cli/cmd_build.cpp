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
#include "pipeline/run.h"
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

// One device's part of the build report.
struct DeviceBuildReport {
    ocl::DeviceInfo device;
    construct::BuildSettings settings;  // with the tuning applied
    tune::Applied tuning;
    pipeline::BuildFigures figures;
};

// The whole command's report: the scene, the settings as given, every device's figures and whether
// the devices agree bit for bit.
struct BuildReport {
    std::string file, scene;
    double time = 0.0;
    std::size_t geometries = 0;
    construct::BuildSettings settings;  // as given (each device applies its tuning)
    std::optional<std::filesystem::path> tuning_db;
    int repeat = 1, warmup = 0;
    std::vector<DeviceBuildReport> devices;
    bool devices_agree = true, edit_lists_agree = true;
    std::optional<std::string> json_path;  // where the JSON report was written
};

nlohmann::json to_json(const DeviceBuildReport& d) {
    nlohmann::json j = pipeline::to_json(d.figures);
    j["device"] = d.device.to_json();
    j["settings"] = settings_json(d.settings);
    j["tuning"] = d.tuning.record;
    return j;
}

std::string to_text(const DeviceBuildReport& d, bool kernel_table) {
    return fmt::format("device {} [{}]\n  {}\n", d.device.index, d.device.name, d.tuning.text) +
           pipeline::to_text(d.figures, kernel_table);
}

nlohmann::json to_json(const BuildReport& r) {
    nlohmann::json devices = nlohmann::json::array();
    for (const DeviceBuildReport& d : r.devices) devices.push_back(to_json(d));
    const nlohmann::json& first = devices.at(0);
    return {{"command", "build"},
            {"scene", {{"file", r.file}, {"name", r.scene}, {"time", r.time}, {"geometries", r.geometries}}},
            {"settings", first["settings"]},
            {"tuning", first["tuning"]},
            {"tuning_db", r.tuning_db ? nlohmann::json(r.tuning_db->string()) : nlohmann::json(nullptr)},
            {"repeat", r.repeat},
            {"warmup", r.warmup},
            {"bricks", first["bricks"]},
            {"digest", first["digest"]},
            {"stages", first["stages"]},
            {"memory", first["memory"]},
            {"devices", devices},
            {"devices_agree", r.devices_agree},
            {"edit_lists_agree", r.edit_lists_agree}};
}

std::string to_text(const BuildReport& r, bool kernel_table) {
    const construct::BuildSettings& s = r.settings;
    std::string text = fmt::format("build {} ({}), t = {} s: brick size {}, branching {}, {}^3 samples, {}, "
                                   "culling {}{}, guard {}\n",
                                   r.scene, r.file, r.time, s.leaf_size, s.branching, s.samples,
                                   construct::to_string(s.format), s.cull ? "on" : "off",
                                   s.dependencies ? " with dependencies" : "", s.guard);
    for (const DeviceBuildReport& d : r.devices) text += to_text(d, kernel_table);
    if (r.devices.size() > 1)
        text += fmt::format("devices agree bit for bit: bricks and pool {}, edit lists {}\n",
                            r.devices_agree ? "yes" : "NO", r.edit_lists_agree ? "yes" : "NO");
    if (r.json_path) text += fmt::format("report: {}\n", *r.json_path);
    return text;
}

DeviceBuildReport build_on(ocl::Device& device, const Scene& scene, const BuildOptions& o, const tune::TuningDb* db) {
    DeviceBuildReport d;
    d.device = device.info();
    tune::Resolved r = tune::resolve_settings(o.flags.resolve(), nullptr, db, device.info(), o.flags.given());
    d.settings = r.build;
    d.tuning = std::move(r.tuning);
    pipeline::Runner runner(device);
    const pipeline::Run run =
        runner.run(scene, {pipeline::Work::construct, d.settings, {}, o.measure.warmups(), o.measure.repeat, true});
    d.figures = pipeline::build_figures(run, device.info());
    if (o.reference_levels) pipeline::add_reference_levels(d.figures.construction, scene, d.settings);
    return d;
}

// --devices split: one build shared by the devices.
void run_build_split(const BuildOptions& o, const GlobalOptions& global, const Scene& scene) {
    SplitDevices d = open_split_devices(global);
    const TuningChoice tuning = open_tuning(global);
    pipeline::SplitSpec spec;
    spec.work = pipeline::Work::construct;
    for (ocl::Device* device : d.devices)
        spec.build.push_back(tune::resolve_settings(o.flags.resolve(), nullptr, tuning.get(), device->info(), o.flags.given()).build);
    spec.warmup = o.measure.warmups();
    spec.repeat = o.measure.repeat;
    spec.rates = &d.rates;
    const pipeline::SplitRun run = pipeline::run_split(d.devices, scene, spec);
    nlohmann::json j = pipeline::to_json(run);
    j["file"] = o.file;
    j["scene"] = scene.name;
    if (o.json) write_file_atomic(*o.json, format_json(j));
    std::fputs((fmt::format("scene {} ({}): construction split over {} devices\n", scene.name, o.file, d.devices.size()) +
                pipeline::to_text(run) + (o.json ? fmt::format("report: {}\n", *o.json) : ""))
                   .c_str(),
               stdout);
}

void run_build(const BuildOptions& o, const GlobalOptions& global) {
    apply_global_options(global, true);
    const pipeline::DeviceMode mode = device_mode(global);
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
    if (mode == pipeline::DeviceMode::split) return run_build_split(o, global, scene);
    ocl::DeviceSet devices = ocl::DeviceSet::open(global.device);
    const TuningChoice tuning = open_tuning(global);
    report.tuning_db = tuning.path;
    for (ocl::Device& device : devices) {
        report.devices.push_back(build_on(device, scene, o, tuning.get()));
        const pipeline::BuildFigures& first = report.devices.front().figures;
        const pipeline::BuildFigures& last = report.devices.back().figures;
        report.devices_agree = report.devices_agree && last.digest == first.digest;
        report.edit_lists_agree = report.edit_lists_agree && last.list_digest == first.list_digest;
    }
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
