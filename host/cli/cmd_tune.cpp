// `sdfbrick tune`: searches the evaluation kernel's chunk and work-group size (cost: the count and
// evaluate stages, which the chunk size governs) and the trace kernel's work-group shape (cost: the
// trace stage) per selected device, keeps each configuration's minimum over its repeats, and writes
// the winners to the tuning database that later runs read. docs/tuning.md.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <limits>
#include <memory>

#include <fmt/format.h>

#include "cli/build_flags.h"
#include "cli/commands.h"
#include "core/errors.h"
#include "core/files.h"
#include "pipeline/run.h"
#include "scene/to_device.h"
#include "scene/scene_json.h"
#include "tune/apply.h"
#include "tune/search.h"

namespace sdfbrick::cli {

namespace {

struct TuneOptions {
    std::string file;
    BuildFlags flags;
    std::vector<std::string> kernels{"evaluate", "trace"};
    std::string strategy = "auto";
    std::size_t budget = 40;
    int repeat = 3;
    int warmup = 1;
    int width = 1280, height = 720;
    std::uint64_t seed = 1;
    std::optional<std::string> json;
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

// The evaluation kernel's cost: the stages its chunk size governs.
constexpr measure::Stage kEvaluateObjective[] = {measure::Stage::count, measure::Stage::evaluate};

std::vector<int> powers_of_two(int lo, int hi) {
    std::vector<int> v;
    for (int x = lo; x <= hi; x *= 2) v.push_back(x);
    return v;
}

struct Tuned {
    tune::SearchResult result;
    tune::Config fallback;  // the built-in default
    double fallback_cost = 0.0;
    tune::Strategy strategy = tune::Strategy::full;
    std::size_t space = 0;
};

Tuned run_search(const tune::Space& space, const TuneOptions& o, const tune::Config& fallback,
                 const std::function<double(const tune::Config&)>& cost) {
    Tuned t;
    t.space = space.size();
    t.strategy = tune::strategy_from_string(o.strategy, space, o.budget);
    t.fallback = fallback;
    std::size_t done = 0;
    const auto logged = [&](const tune::Config& c) {
        const double ms = cost(c);
        std::string params;
        for (const auto& [k, v] : c) params += fmt::format(" {} {}", k, v);
        say(fmt::format("    {:>3}.{:<24} {}\n", ++done, params, std::isfinite(ms) ? fmt::format("{:.4f} ms", ms) : "not runnable"));
        return ms;
    };
    t.result = tune::search(space, t.strategy, o.budget, o.seed, logged);
    const auto it = std::find_if(t.result.evaluated.begin(), t.result.evaluated.end(),
                                 [&](const auto& e) { return e.first == fallback; });
    t.fallback_cost = it != t.result.evaluated.end() ? it->second : cost(fallback);
    return t;
}

void record(tune::TuningDb& db, const ocl::DeviceInfo& d, const char* kernel, const Tuned& t, const TuneOptions& o,
            const construct::BuildSettings& s, const char* objective, nlohmann::json& report) {
    if (!std::isfinite(t.result.best_cost)) {
        say(fmt::format("  {}: no configuration ran; nothing written\n", kernel));
        return;
    }
    nlohmann::json rec = {{"time_ms", t.result.best_cost}, {"default_params", t.fallback},
                          {"default_ms", t.fallback_cost}, {"objective", objective}, {"scene", o.file},
                          {"brick_size", s.leaf_size}, {"strategy", to_string(t.strategy)},
                          {"evaluated", t.result.evaluated.size()}, {"space", t.space}, {"repeat", o.repeat},
                          {"tuned_at", now_iso()}, {"platform", d.platform_name}};
    if (std::string(kernel) == tune::kTraceKernel) rec["image"] = {o.width, o.height};
    db.put({d.name, d.driver_version, d.vendor, kernel, t.result.best, rec});
    std::string params;
    for (const auto& [k, v] : t.result.best) params += fmt::format("{}{} {}", params.empty() ? "" : ", ", k, v);
    say(fmt::format("  {}: best {} at {:.4f} ms; default {:.4f} ms ({:+.1f}%); {} of {} configurations ({})\n",
                        kernel, params, t.result.best_cost, t.fallback_cost,
                        100.0 * (t.result.best_cost - t.fallback_cost) / t.fallback_cost, t.result.evaluated.size(),
                        t.space, to_string(t.strategy)));
    nlohmann::json evaluated = nlohmann::json::array();
    for (const auto& [c, ms] : t.result.evaluated)
        evaluated.push_back({{"params", c}, {"ms", std::isfinite(ms) ? nlohmann::json(ms) : nlohmann::json(nullptr)}});
    rec["params"] = t.result.best;
    rec["evaluated_configurations"] = evaluated;
    report[kernel] = rec;
}

void run_tune(const TuneOptions& o, const GlobalOptions& global) {
    apply_global_options(global);
    for (const std::string& k : o.kernels)
        if (k != "evaluate" && k != "trace") throw InputError(fmt::format("--kernels takes evaluate and/or trace, got \"{}\"", k));
    if (o.budget < 1) throw InputError("--budget must be at least 1");
    validate_image_size(o.width, o.height);
    const construct::BuildSettings base = o.flags.resolve();
    const Scene file_scene = load_scene(o.file);
    const Scene scene = scene_at(file_scene, file_scene.time);
    ocl::DeviceSet devices = ocl::DeviceSet::open(global.device);
    if (global.no_tuning) throw InputError("tune writes the tuning database: drop --no-tuning");
    const TuningChoice choice = open_tuning(global);
    if (!choice.path) throw InputError("no tuning database file: give --tuning-db or set SDFBRICK_TUNING_DB");
    tune::TuningDb db = *choice.db;
    const bool want_eval = std::find(o.kernels.begin(), o.kernels.end(), "evaluate") != o.kernels.end();
    const bool want_trace = std::find(o.kernels.begin(), o.kernels.end(), "trace") != o.kernels.end();

    say(fmt::format("tune {} ({}), brick size {}, {} repeats after {} warm-up, strategy {}, budget {}\n", scene.name,
                    o.file, base.leaf_size, o.repeat, o.warmup, o.strategy, o.budget));
    nlohmann::json device_reports = nlohmann::json::array();
    for (ocl::Device& device : devices) {
        const ocl::DeviceInfo& info = device.info();
        say(fmt::format("device {} [{}], driver {}\n", info.index, info.name, info.driver_version));
        nlohmann::json report = {{"device", info.to_json()}};
        pipeline::Runner runner(device);
        construct::BuildSettings settings = base;
        if (want_eval) {
            tune::Space space;
            space.dims = {{"chunk", powers_of_two(16, 256)},
                          {"group", powers_of_two(32, static_cast<int>(std::min<std::size_t>(info.max_work_group_size, 1024)))}};
            const auto cost = [&](const tune::Config& c) {
                construct::BuildSettings s = base;
                s.chunk = c.at("chunk");
                s.eval_group = c.at("group");
                try {
                    s.validate(info);
                } catch (const InputError&) {
                    return std::numeric_limits<double>::infinity();
                }
                try {
                    const pipeline::Run run = runner.run(scene, {pipeline::Work::construct, s, {}, o.warmup, o.repeat});
                    return measure::stages_stats(run.captures, kEvaluateObjective).min;
                } catch (const InputError&) {  // more work-items than the kernel allows here
                    return std::numeric_limits<double>::infinity();
                }
            };
            say("  brick_evaluate (count + evaluate stages):\n");
            const Tuned t = run_search(space, o, {{"chunk", base.chunk}, {"group", base.eval_group}}, cost);
            record(db, info, tune::kEvaluateKernel, t, o, base, "count + evaluate stages, min over repeats", report);
            if (std::isfinite(t.result.best_cost)) {
                settings.chunk = t.result.best.at("chunk");
                settings.eval_group = t.result.best.at("group");
            }
        }
        if (want_trace) {
            const pipeline::Run built = runner.run(scene, {pipeline::Work::bvh, settings, {}, 0, 1, false});
            tune::Space space;
            space.dims = {{"group_x", powers_of_two(4, 64)}, {"group_y", powers_of_two(1, 32)}};
            const auto cost = [&](const tune::Config& c) {
                const std::size_t items = static_cast<std::size_t>(c.at("group_x")) * c.at("group_y");
                if (items < 16 || items > info.max_work_group_size) return std::numeric_limits<double>::infinity();
                render::TraceSettings ts;
                ts.width = o.width;
                ts.height = o.height;
                ts.group_x = c.at("group_x");
                ts.group_y = c.at("group_y");
                try {
                    return runner.trace(scene, built.bricks, {pipeline::Work::trace, settings, ts, o.warmup, o.repeat}).trace_ms.min;
                } catch (const InputError&) {
                    return std::numeric_limits<double>::infinity();
                }
            };
            say(fmt::format("  trace_primary ({}x{}, trace stage):\n", o.width, o.height));
            const render::TraceSettings defaults;
            const Tuned t = run_search(space, o, {{"group_x", defaults.group_x}, {"group_y", defaults.group_y}}, cost);
            record(db, info, tune::kTraceKernel, t, o, settings, "trace stage, min over repeats", report);
        }
        device_reports.push_back(report);
    }
    db.save(*choice.path);
    say(fmt::format("tuning database: {}\n", choice.path->string()));
    if (o.json) {
        write_file_atomic(*o.json, format_json({{"command", "tune"}, {"scene", o.file}, {"tuning_db", choice.path->string()},
                                                {"devices", device_reports}}));
        say(fmt::format("report: {}\n", *o.json));
    }
}

}  // namespace

void add_tune_command(CLI::App& app, const GlobalOptions& global) {
    auto o = std::make_shared<TuneOptions>();
    auto* cmd = app.add_subcommand("tune", "Search the evaluation chunk and work-group size and the trace work-group "
                                           "shape per selected device; write the best to the tuning database");
    cmd->add_option("file", o->file, "scene file (JSON) to tune on")->required();
    o->flags.add_to(cmd);
    cmd->add_option("--kernels", o->kernels, "evaluate and/or trace")->delimiter(',')->capture_default_str();
    cmd->add_option("--strategy", o->strategy, "auto (full when the space fits the budget, else anneal), full, random, anneal")->capture_default_str();
    cmd->add_option("--budget", o->budget, "most configurations measured per kernel (random, anneal)")->capture_default_str();
    cmd->add_option("--repeat", o->repeat, "timed runs per configuration (the minimum is kept)")->check(CLI::Range(1, 100))->capture_default_str();
    cmd->add_option("--warmup", o->warmup, "untimed runs per configuration first")->check(CLI::Range(0, 100))->capture_default_str();
    cmd->add_option("--width", o->width, "trace image width")->capture_default_str();
    cmd->add_option("--height", o->height, "trace image height")->capture_default_str();
    cmd->add_option("--seed", o->seed, "seed of the random and anneal strategies")->capture_default_str();
    cmd->add_option("--json", o->json, "write a JSON report (every configuration measured) here");
    add_setting_flags(cmd, {{"strategy", "--strategy"}, {"width", "--width"}, {"height", "--height"}});
    cmd->callback([o, &global] { run_tune(*o, global); });
}

}  // namespace sdfbrick::cli
