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
#include "pipeline/command_report.h"
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

void run_build(const BuildOptions& o, const GlobalOptions& global) {
    apply_global_options(global, true);
    pipeline::BuildCommandReport report;
    report.settings = o.flags.resolve();
    if (o.json) check_output_path(*o.json);
    const Scene file_scene = load_scene_warned(o.file);
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
    pipeline::add_execution(report, devices->executor.run(scene, job, devices->placement), scene, o.reference_levels);
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
