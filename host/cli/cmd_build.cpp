// `sdfbrick build`: sparse brick construction of every geometry of a scene on each selected device,
// with a per-stage and per-level report, memory per resource, and digests that are equal iff the
// outputs are bit-identical (across repeats, culling modes and devices).
#include <algorithm>
#include <cstdio>
#include <memory>

#include <fmt/format.h>

#include "build/brick_builder.h"
#include "cli/build_flags.h"
#include "cli/commands.h"
#include "core/errors.h"
#include "core/files.h"
#include "core/hash.h"
#include "core/stats.h"
#include "scene/scene_json.h"

namespace sdfbrick::cli {

namespace {

const char* const kStages[] = {"edit_bounds", "dependencies", "count", "scan", "subdivide", "cull", "evaluate", "aabb"};

struct BuildOptions {
    std::string file;
    std::optional<double> time;
    BuildFlags flags;
    build::BuildSettings settings;  // flags resolved
    int repeat = 1;
    std::optional<std::string> json;
};

std::string bytes_text(std::uint64_t b) {
    if (b >= (1ull << 30)) return fmt::format("{:.2f} GiB", static_cast<double>(b) / (1ull << 30));
    if (b >= (1ull << 20)) return fmt::format("{:.2f} MiB", static_cast<double>(b) / (1ull << 20));
    if (b >= (1ull << 10)) return fmt::format("{:.1f} KiB", static_cast<double>(b) / (1ull << 10));
    return fmt::format("{} B", b);
}

struct DeviceRun {
    std::vector<build::GeometryBuild> builds;  // last repeat
    std::vector<double> repeat_ms;
    std::string digest, list_digest;
    bool repeats_identical = true;
};

DeviceRun run_device(ocl::Device& device, const Scene& scene, const BuildOptions& o) {
    build::BrickBuilder builder(device);
    DeviceRun run;
    for (int r = 0; r < o.repeat; ++r) {
        std::vector<build::GeometryBuild> builds;
        double ms = 0.0;
        Fnv1a64 digest, lists;
        for (const Geometry& g : scene.geometries) {
            builds.push_back(builder.build(g, o.settings));
            ms += builds.back().device_ms;
            digest.add_part(build::output_digest(builds.back(), o.settings));
            lists.add_part(build::list_digest(builds.back()));
        }
        run.repeat_ms.push_back(ms);
        if (r > 0 && digest.hex() != run.digest) run.repeats_identical = false;
        run.digest = digest.hex();
        run.list_digest = lists.hex();
        run.builds = std::move(builds);
    }
    return run;
}

nlohmann::json stages_json(const std::vector<build::GeometryBuild>& builds) {
    nlohmann::json stages = nlohmann::json::array();
    for (const char* stage : kStages) {
        double ms = 0.0;
        std::size_t launches = 0;
        for (const auto& b : builds)
            for (const auto& l : b.launches)
                if (l.stage == stage) {
                    ms += l.device_ms;
                    ++launches;
                }
        if (launches > 0) stages.push_back({{"name", stage}, {"device_ms", ms}, {"launches", launches}});
    }
    return stages;
}

std::string report_text(const ocl::Device& device, const DeviceRun& run) {
    std::string s = fmt::format("device {} [{}]\n", device.info().index, device.info().name);
    for (const auto& b : run.builds) {
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
    double total = 0.0;
    for (const auto& st : stages_json(run.builds)) {
        stages += fmt::format("{}{} {:.3f}", stages.empty() ? "" : ", ", st["name"].get<std::string>(), st["device_ms"].get<double>());
        total += st["device_ms"].get<double>();
    }
    s += fmt::format("  stages (device ms): {}; total {:.3f} ms\n", stages, total);
    if (run.repeat_ms.size() > 1) {
        const auto [lo, hi] = std::minmax_element(run.repeat_ms.begin(), run.repeat_ms.end());
        s += fmt::format("  {} repeats: median {:.3f} ms, min {:.3f}, max {:.3f}; outputs identical: {}\n",
                         run.repeat_ms.size(), median(run.repeat_ms), *lo, *hi, run.repeats_identical ? "yes" : "NO");
    }
    s += fmt::format("  digest {} (edit lists {})\n", run.digest, run.list_digest);
    return s;
}

nlohmann::json device_json(const ocl::Device& device, const DeviceRun& run) {
    std::uint64_t bricks = 0, evaluations = 0, entries = 0;
    std::uint32_t max_edits = 0;
    std::map<std::string, std::uint64_t> memory;
    nlohmann::json geometries = nlohmann::json::array();
    double host_ms = 0.0;
    for (const auto& b : run.builds) {
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
        for (const auto& l : b.launches)
            launches.push_back({{"stage", l.stage}, {"level", l.level}, {"kernel", l.kernel}, {"global", l.global},
                                {"local", l.local}, {"device_ms", l.device_ms}, {"queue_ms", l.queue_ms}});
        geometries.push_back({{"name", b.name}, {"bricks", b.leaf_count}, {"levels", levels},
                              {"origin", {b.origin.x, b.origin.y, b.origin.z}}, {"leaf_size", b.leaf_size},
                              {"clamp_c", b.clamp_c}, {"band", b.band},
                              {"edits_per_leaf", {{"mean", b.edits_per_leaf_mean}, {"max", b.edits_per_leaf_max}}},
                              {"edit_evaluations", b.edit_evaluations}, {"dependency_entries", b.dependency_entries},
                              {"memory", b.memory}, {"device_ms", b.device_ms}, {"host_ms", b.host_ms},
                              {"launches", launches}});
    }
    const double ms = run.repeat_ms.back();
    const double seconds = ms * 1e-3;
    const auto [lo, hi] = std::minmax_element(run.repeat_ms.begin(), run.repeat_ms.end());
    return {{"device", device.info().to_json()},
            {"bricks", bricks},
            {"digest", run.digest},
            {"list_digest", run.list_digest},
            {"stages", stages_json(run.builds)},
            {"device_ms", ms},
            {"host_ms", host_ms},
            {"repeats", {{"device_ms", run.repeat_ms}, {"median_ms", median(run.repeat_ms)}, {"min_ms", *lo},
                         {"max_ms", *hi}, {"identical", run.repeats_identical}}},
            {"memory", memory},
            {"edits_per_leaf", {{"mean", bricks ? static_cast<double>(entries) / static_cast<double>(bricks) : 0.0}, {"max", max_edits}}},
            {"edit_evaluations", evaluations},
            {"bricks_per_second", seconds > 0 ? static_cast<double>(bricks) / seconds : 0.0},
            {"edit_evaluations_per_second", seconds > 0 ? static_cast<double>(evaluations) / seconds : 0.0},
            {"geometries", geometries}};
}

void run_build(BuildOptions o, const GlobalOptions& global) {
    apply_global_options(global);
    o.settings = o.flags.resolve();
    const Scene file_scene = load_scene(o.file);
    const double t = o.time.value_or(file_scene.time);
    const Scene scene = scene_at(file_scene, t);
    ocl::DeviceSet devices = ocl::DeviceSet::open(global.device);
    o.settings.validate(devices[0].info());

    std::string text = fmt::format("build {} ({}), t = {} s: brick size {}, branching {}, {}^3 samples, {}, chunk {}, "
                                   "group {}, culling {}{}, guard {}\n",
                                   scene.name, o.file, t, o.settings.leaf_size, o.settings.branching, o.settings.samples,
                                   build::to_string(o.settings.format), o.settings.chunk, o.settings.eval_group, o.settings.cull ? "on" : "off",
                                   o.settings.dependencies ? " with dependencies" : "", o.settings.guard);
    nlohmann::json device_reports = nlohmann::json::array();
    std::string first_digest, first_lists;
    bool agree = true, lists_agree = true;
    for (ocl::Device& device : devices) {
        const DeviceRun run = run_device(device, scene, o);
        text += report_text(device, run);
        device_reports.push_back(device_json(device, run));
        if (first_digest.empty()) {
            first_digest = run.digest;
            first_lists = run.list_digest;
        } else {
            agree = agree && run.digest == first_digest;
            lists_agree = lists_agree && run.list_digest == first_lists;
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
            {"settings", settings_json(o.settings)},
            {"repeat", o.repeat},
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
    cmd->add_option("--repeat", o->repeat, "build this many times (reports median, min, max; checks outputs are identical)")
        ->check(CLI::Range(1, 1000))->capture_default_str();
    cmd->add_option("--json", o->json, "write a JSON report here");
    cmd->callback([o, &global] { run_build(*o, global); });
}

}  // namespace sdfbrick::cli
