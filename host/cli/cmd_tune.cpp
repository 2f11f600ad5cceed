// `sdfbrick tune`: parses the flags, tunes the selected kernels (tune/kernels.h declares them,
// tune::tune_kernel searches and measures) on each selected device, prints every configuration as it
// is measured, and writes the winners to the tuning database that later runs read. docs/tuning.md.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <memory>

#include <fmt/format.h>

#include "cli/build_flags.h"
#include "cli/commands.h"
#include "core/errors.h"
#include "core/files.h"
#include "pipeline/executor.h"
#include "scene/to_device.h"
#include "scene/scene_json.h"
#include "tune/kernels.h"
#include "tune/t4.h"
#include "tune/tuner.h"

namespace sdfbrick::cli {

namespace {

struct TuneOptions {
    std::vector<std::string> files;
    BuildFlags flags;
    std::vector<std::string> kernels{"evaluate", "trace"};
    tune::TuneSpec spec;  // strategy, budget, seed, warm-up, repeats, trace image
    std::string method = "sphere";
    std::optional<std::string> json;
    std::optional<std::string> t4;  // the run as T4 results
};

// Tuning takes a while: every line is printed as soon as it is known.
void say(const std::string& line) {
    std::fputs(line.c_str(), stdout);
    std::fflush(stdout);
}

std::string now_iso() {
    const std::time_t t = std::time(nullptr);
    char buf[32];
    std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&t));
    return buf;
}

// Every configuration as it is measured.
void print_measured(std::size_t n, const tune::Config& c, double cost, std::span<const double> scene_ms) {
    say(tune::measured_line(n, c, cost, scene_ms));
}

// The selected kernels, in the tuner's order.
std::vector<const tune::TunedKernel*> selected_kernels(const TuneOptions& o) {
    for (const std::string& k : o.kernels)
        if (!tune::find_kernel(k)) throw InputError(fmt::format("--kernels takes evaluate and/or trace, got \"{}\"", k));
    std::vector<const tune::TunedKernel*> out;
    for (const tune::TunedKernel* k : tune::tuned_kernels())
        if (std::find(o.kernels.begin(), o.kernels.end(), k->option) != o.kernels.end()) out.push_back(k);
    return out;
}

void run_tune(const TuneOptions& o, const GlobalOptions& global) {
    apply_global_options(global);
    const std::vector<const tune::TunedKernel*> kernels = selected_kernels(o);
    if (o.spec.budget < 1) throw InputError("--budget must be at least 1");
    validate_image_size(o.spec.width, o.spec.height);
    tune::TuneSpec spec = o.spec;
    spec.method = method_flag(o.method);
    const construct::BuildSettings base = o.flags.resolve();
    std::vector<tune::TuneScene> scenes;
    for (const std::string& file : o.files) {
        const Scene file_scene = load_scene_warned(file);
        scenes.push_back({scene_at(file_scene, file_scene.time), file});
    }
    ocl::DeviceSet devices = ocl::DeviceSet::open(global.device);
    if (global.no_tuning) throw InputError("tune writes the tuning database: drop --no-tuning");
    const TuningChoice choice = open_tuning(global);
    if (!choice.path) throw InputError("no tuning database file: give --tuning-db or set SDFBRICK_TUNING_DB");
    tune::TuningDb db = *choice.db;
    std::vector<std::filesystem::path> paths{*choice.path};
    if (o.json) paths.emplace_back(*o.json);
    if (o.t4) paths.emplace_back(*o.t4);
    check_output_paths(paths);
    for (ocl::Device& device : devices) base.validate(device.info());  // the checks build makes, before any work

    std::string names;
    for (const tune::TuneScene& s : scenes) names += fmt::format("{}{} ({})", names.empty() ? "" : ", ", s.scene.name, s.file);
    say(fmt::format("tune {}, brick size {}, {} repeats after {} warm-up, strategy {}, budget {}\n", names,
                    base.leaf_size, o.spec.repeat, o.spec.warmup, o.spec.strategy, o.spec.budget));
    nlohmann::json device_reports = nlohmann::json::array();
    const std::string started = now_iso();
    for (ocl::Device& device : devices) {
        pipeline::Executor executor(device);
        device_reports.push_back(
            tune::tune_device(executor.lane(0), scenes, kernels, base, spec, db, now_iso(), say, print_measured));
    }
    db.save(*choice.path);
    say(fmt::format("tuning database: {}\n", choice.path->string()));
    std::vector<Output> outputs;
    if (o.json)
        outputs.push_back(text_output(*o.json, format_json({{"command", "tune"}, {"scenes", o.files},
                                                            {"tuning_db", choice.path->string()}, {"devices", device_reports}})));
    if (o.t4) outputs.push_back(text_output(*o.t4, tune::t4_results(device_reports, started).dump(2) + "\n"));
    write_all(outputs);
    if (o.json) say(fmt::format("report: {}\n", *o.json));
    if (o.t4) say(fmt::format("T4 results: {}\n", *o.t4));
}

struct ImportOptions {
    std::string file;
    std::vector<std::string> kernels{"evaluate", "trace"};
    bool replace = false;
};

// Imports the best valid result of a T4 file per selected kernel as the database entry of each
// selected device that has none (or, with --replace, any).
void run_import(const ImportOptions& o, const GlobalOptions& global) {
    apply_global_options(global);
    std::vector<const tune::TunedKernel*> kernels;
    for (const std::string& k : o.kernels) {
        const tune::TunedKernel* kernel = tune::find_kernel(k);
        if (!kernel) throw InputError(fmt::format("--kernels takes evaluate and/or trace, got \"{}\"", k));
        kernels.push_back(kernel);
    }
    const nlohmann::json doc = load_json(o.file);
    if (global.no_tuning) throw InputError("tune-import writes the tuning database: drop --no-tuning");
    const TuningChoice choice = open_tuning(global);
    if (!choice.path) throw InputError("no tuning database file: give --tuning-db or set SDFBRICK_TUNING_DB");
    tune::TuningDb db = *choice.db;
    const ocl::DeviceSet devices = ocl::DeviceSet::open(global.device);
    std::size_t imported = 0;
    for (const ocl::Device& device : devices) {
        const ocl::DeviceInfo& d = device.info();
        for (const tune::TunedKernel* kernel : kernels) {
            const bool has = std::any_of(db.entries().begin(), db.entries().end(), [&](const tune::Entry& e) {
                return e.device == d.name && e.driver == d.driver_version && e.kernel == kernel->name;
            });
            if (has && !o.replace) {
                say(fmt::format("{} [{}]: {} already has an entry; kept (--replace to import over it)\n", d.index, d.name, kernel->name));
                continue;
            }
            const auto best = tune::best_t4_result(doc, *kernel, d, o.file);
            if (!best) {
                say(fmt::format("{} [{}]: {}: no valid result with exactly its parameters that this device runs\n", d.index,
                                d.name, kernel->name));
                continue;
            }
            db.put(tune::t4_entry(*best, *kernel, d, o.file, now_iso()));
            ++imported;
            say(fmt::format("{} [{}]: {}: {} ({:.4f} ms, result {})\n", d.index, d.name, kernel->name,
                            kernel->describe(best->params), best->ms, best->index));
        }
    }
    if (imported > 0) db.save(*choice.path);
    say(fmt::format("imported {} entr{} into {}\n", imported, imported == 1 ? "y" : "ies", choice.path->string()));
}

}  // namespace

void add_tune_command(CLI::App& app, const GlobalOptions& global) {
    auto o = std::make_shared<TuneOptions>();
    auto* cmd = app.add_subcommand("tune", "Search the evaluation chunk and work-group size and the trace work-group "
                                           "shape per selected device; write the best to the tuning database");
    cmd->add_option("files", o->files, "scene files (JSON) to tune on; with several, a configuration's cost is the "
                                       "geometric mean of its times on them")->required();
    o->flags.add_to(cmd);
    cmd->add_option("--kernels", o->kernels, "evaluate and/or trace")->delimiter(',')->capture_default_str();
    cmd->add_option("--strategy", o->spec.strategy, "auto (full when the space fits the budget, else anneal), full, random, anneal")->capture_default_str();
    cmd->add_option("--budget", o->spec.budget, "most configurations measured per kernel (random, anneal)")->capture_default_str();
    cmd->add_option("--repeat", o->spec.repeat, "timed runs per configuration (the minimum is kept)")->check(CLI::Range(1, 100))->capture_default_str();
    cmd->add_option("--warmup", o->spec.warmup, "untimed runs per configuration first")->check(CLI::Range(0, 100))->capture_default_str();
    cmd->add_option("--width", o->spec.width, "trace image width")->capture_default_str();
    cmd->add_option("--height", o->spec.height, "trace image height")->capture_default_str();
    cmd->add_option("--method", o->method, "in-brick search of the traced image: sphere, analytic or hybrid")->capture_default_str();
    cmd->add_option("--seed", o->spec.seed, "seed of the random and anneal strategies")->capture_default_str();
    cmd->add_option("--json", o->json, "write a JSON report (every configuration measured) here");
    cmd->add_option("--t4", o->t4, "write every configuration measured as T4 auto-tuning results (docs/tuning.md) here");
    add_setting_flags(cmd, {{"strategy", "--strategy"}, {"width", "--width"}, {"height", "--height"}});
    cmd->callback([o, &global] { run_tune(*o, global); });

    auto imp = std::make_shared<ImportOptions>();
    auto* import_cmd = app.add_subcommand("tune-import", "Import the best result per kernel of a T4 auto-tuning results "
                                                         "file (Kernel Tuner, KTT, tune --t4) into the tuning database for "
                                                         "each selected device that has no entry");
    import_cmd->add_option("file", imp->file, "T4 results file (JSON)")->required();
    import_cmd->add_option("--kernels", imp->kernels, "evaluate and/or trace")->delimiter(',')->capture_default_str();
    import_cmd->add_flag("--replace", imp->replace, "import over the device's own entry too");
    import_cmd->callback([imp, &global] { run_import(*imp, global); });
}

}  // namespace sdfbrick::cli
