// `sdfbrick sweep`: a grid of scenes x brick sizes x chunk sizes x ... x devices, each point measured
// (construction and trace stages, occupancy proxies, memory, accuracy against the reference) into
// CSV and JSON; resumable, shardable. `sdfbrick merge` joins the shards. docs/sweep.md.
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <memory>
#include <sstream>

#include <fmt/format.h>

#include "cli/commands.h"
#include "core/errors.h"
#include "core/files.h"
#include "render/brick_tracer.h"
#include "scene/scene_json.h"
#include "sweep/grid.h"
#include "sweep/runner.h"

namespace sdfbrick::cli {

namespace {

struct SweepOptions {
    std::optional<std::string> file;
    std::vector<std::string> scenes, trace_groups, formats, methods, normals, culls;
    std::vector<double> brick_sizes;
    std::vector<double> tolerances;
    std::vector<int> chunks, groups, samples;
    std::optional<int> width, height, warmup, repeat;
    bool no_accuracy = false;
    std::string out = "sweep";
    std::optional<std::string> cache, shard;
};

sweep::SweepSpec make_spec(const SweepOptions& o, const GlobalOptions& global) {
    sweep::SweepSpec s;
    if (o.file) s = sweep::spec_from_json(load_json(*o.file), *o.file);
    const auto override_with = [](auto& field, const auto& flag) {
        if (!flag.empty()) field = flag;
    };
    override_with(s.scenes, o.scenes);
    override_with(s.brick_sizes, o.brick_sizes);
    override_with(s.tolerances, o.tolerances);
    override_with(s.chunks, o.chunks);
    override_with(s.groups, o.groups);
    override_with(s.trace_groups, o.trace_groups);
    override_with(s.formats, o.formats);
    override_with(s.samples, o.samples);
    override_with(s.methods, o.methods);
    override_with(s.normals, o.normals);
    if (!o.culls.empty()) {
        s.culls.clear();
        for (const std::string& c : o.culls) {
            if (c != "on" && c != "off") throw InputError(fmt::format("--cull takes on and/or off, got \"{}\"", c));
            s.culls.push_back(c == "on");
        }
    }
    if (o.width) s.width = *o.width;
    if (o.height) s.height = *o.height;
    if (o.warmup) s.warmup = *o.warmup;
    if (o.repeat) s.repeat = *o.repeat;
    if (o.no_accuracy) s.accuracy = false;
    if (!global.device.empty()) s.devices = global.device;
    s.validate();
    return s;
}

void run_sweep(const SweepOptions& o, const GlobalOptions& global) {
    apply_global_options(global);
    const sweep::SweepSpec spec = make_spec(o, global);
    const sweep::Shard shard = o.shard ? sweep::parse_shard(*o.shard) : sweep::Shard{};
    ocl::DeviceSet devices = ocl::DeviceSet::open(spec.devices);
    const TuningChoice tuning = open_tuning(global);
    const std::vector<sweep::SweepPoint> grid = sweep::expand(spec, sweep::device_labels(devices));
    const std::vector<sweep::SweepPoint> points = sweep::shard_points(grid, shard);
    sweep::ResultCache cache(o.cache.value_or(o.out + ".cache.jsonl"));
    const bool terminal = isatty(STDERR_FILENO) != 0;
    const auto progress = [terminal](const sweep::Progress& p) {
        if (!terminal) return;
        std::string line = fmt::format("\r[sweep] {}/{} points ({} from the cache), elapsed {}", p.done, p.total, p.cached,
                                       clock_text(p.elapsed_s));
        if (!p.current.empty()) line += fmt::format(", ETA {}: {}", p.done > p.cached ? clock_text(p.eta_s) : "?", p.current);
        std::fprintf(stderr, "%-150.150s%s", line.c_str(), p.current.empty() ? "\n" : "");
        std::fflush(stderr);
    };
    const std::vector<sweep::SweepRow> rows = sweep::run_points(spec, points, devices, tuning.get(), cache, progress);
    const auto errors = static_cast<std::size_t>(
        std::count_if(rows.begin(), rows.end(), [](const sweep::SweepRow& r) { return !r.ok(); }));
    write_all({text_output(o.out + ".csv", sweep::to_csv(rows)),
               text_output(o.out + ".json", format_json(sweep::sweep_document(spec, shard, grid.size(), rows)))});
    std::printf("sweep: %zu points of %zu in the grid (shard %zu/%zu), %zu failed; wrote %s.csv and %s.json\n", rows.size(),
                grid.size(), shard.index, shard.count, errors, o.out.c_str(), o.out.c_str());
    for (const sweep::SweepRow& r : rows)
        if (!r.ok())
            std::printf("  point %zu (%s): %s\n", r.index, r.key.c_str(), r.error.value_or("").c_str());
}

void run_merge(const std::vector<std::string>& files, const std::string& out) {
    std::vector<nlohmann::json> docs;
    for (const std::string& f : files) docs.push_back(load_json(f));
    const sweep::Merged m = sweep::merge(docs, files);
    nlohmann::json doc = docs.front();
    doc["points"] = sweep::to_json(m.rows);
    doc["shard"] = {{"index", 0}, {"count", 1}};
    doc["merged_from"] = files;
    doc["complete"] = m.complete;
    doc["notes"] = m.notes;
    write_all({text_output(out + ".csv", sweep::to_csv(m.rows)), text_output(out + ".json", format_json(doc))});
    std::printf("merge: %zu points from %zu files, %s; wrote %s.csv and %s.json\n", m.rows.size(), files.size(),
                m.complete ? "complete" : "NOT complete", out.c_str(), out.c_str());
    for (const std::string& n : m.notes) std::printf("  %s\n", n.c_str());
}

}  // namespace

void add_sweep_commands(CLI::App& app, const GlobalOptions& global) {
    auto o = std::make_shared<SweepOptions>();
    auto* cmd = app.add_subcommand("sweep", "Measure a grid of configurations (scenes x brick sizes x chunk sizes x "
                                            "work-groups x culling x formats x samples x methods x normals x devices): "
                                            "stages, occupancy, memory, accuracy; CSV and JSON, resumable, shardable");
    cmd->add_option("file", o->file, "sweep file (JSON, docs/sweep.md); flags override its keys");
    cmd->add_option("--scenes", o->scenes, "scene files")->delimiter(',');
    cmd->add_option("--brick-sizes", o->brick_sizes, "leaf brick sizes (with a tolerance: the finest)")->check(finite_number())->delimiter(',');
    cmd->add_option("--tolerances", o->tolerances, "adaptive tolerances (0: uniform)")->check(finite_number())->delimiter(',');
    cmd->add_option("--chunks", o->chunks, "edits per __local chunk (16..256)")->delimiter(',');
    cmd->add_option("--groups", o->groups, "evaluation work-group sizes")->delimiter(',');
    cmd->add_option("--trace-groups", o->trace_groups, "trace work-groups, WxH")->delimiter(',');
    cmd->add_option("--cull", o->culls, "on, off or on,off")->delimiter(',');
    cmd->add_option("--formats", o->formats, "int8, int16, float")->delimiter(',');
    cmd->add_option("--samples", o->samples, "8 and/or 10 (apron 1 or 2)")->delimiter(',');
    cmd->add_option("--methods", o->methods, render::method_names(", "))->delimiter(',');
    cmd->add_option("--normals", o->normals, "central, tetra, continuous")->delimiter(',');
    cmd->add_option("--width", o->width, "image width for trace and accuracy (default 640)");
    cmd->add_option("--height", o->height, "image height (default 360)");
    cmd->add_option("--warmup", o->warmup, "uncaptured runs per point (default 1)");
    cmd->add_option("--repeat", o->repeat, "captures per point (default 3)");
    cmd->add_flag("--no-accuracy", o->no_accuracy, "skip the reference tracer and the accuracy columns");
    cmd->add_option("--out", o->out, "output prefix: PREFIX.csv, PREFIX.json")->capture_default_str();
    cmd->add_option("--cache", o->cache, "finished-points cache for resuming (default PREFIX.cache.jsonl)");
    cmd->add_option("--shard", o->shard, "run shard i of n (i/n, 0-based): every n-th grid point from i");
    add_setting_flags(cmd, {{"shard", "--shard"}});
    cmd->callback([o, &global] { run_sweep(*o, global); });

    auto files = std::make_shared<std::vector<std::string>>();
    auto out = std::make_shared<std::string>("merged");
    auto* merge = app.add_subcommand("merge", "Join sweep shards (their JSON files) into one CSV and JSON; reports "
                                              "missing shards and points");
    merge->add_option("files", *files, "sweep JSON files")->required();
    merge->add_option("--out", *out, "output prefix: PREFIX.csv, PREFIX.json")->capture_default_str();
    merge->callback([files, out] { run_merge(*files, *out); });
}

}  // namespace sdfbrick::cli
