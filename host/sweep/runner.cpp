#include "sweep/runner.h"

#include <algorithm>
#include <chrono>
#include <fstream>
#include <memory>
#include <set>
#include <sstream>

#include <fmt/format.h>

#include "core/errors.h"
#include "core/files.h"
#include "measure/peaks.h"
#include "measure/statistics.h"
#include "reference/accuracy.h"
#include "pipeline/run.h"
#include "reference/device_tracer.h"
#include "scene/scene_json.h"
#include "tune/apply.h"

namespace sdfbrick::sweep {

namespace {


std::string cell(const nlohmann::json& v) {
    if (v.is_null()) return "";
    std::string s = v.is_string() ? v.get<std::string>() : v.is_boolean() ? (v.get<bool>() ? "1" : "0") : v.dump();
    if (s.find_first_of(",\"\n\r") == std::string::npos) return s;
    std::string q = "\"";
    for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
    return q + "\"";
}

template <class T>
nlohmann::json opt(const std::optional<T>& v) {
    return v ? nlohmann::json(*v) : nlohmann::json(nullptr);
}

// What one device needs across points: its pipeline (compiled programs), peaks and references.
struct DeviceState {
    ocl::Device* device = nullptr;
    std::unique_ptr<pipeline::Runner> runner;
    std::optional<measure::DevicePeaks> peaks;
    std::map<std::string, reference::ReferenceResult> references;  // per scene file
};

Row run_point(const SweepSpec& spec, const SweepPoint& p, DeviceState& state, const Scene& scene,
              const tune::TuningDb* tuning) {
    ocl::Device& device = *state.device;
    construct::BuildSettings settings;
    settings.leaf_size = p.brick_size;
    settings.cull = p.cull;
    settings.format = *construct::format_from_string(p.format);
    settings.samples = p.samples;
    if (p.chunk) settings.chunk = *p.chunk;
    if (p.group) settings.eval_group = *p.group;
    render::TraceSettings trace;
    trace.width = spec.width;
    trace.height = spec.height;
    trace.method = *render::method_from_string(p.method);
    trace.normals = *render::normals_from_string(p.normals);
    if (p.trace_group) std::tie(trace.group_x, trace.group_y) = parse_group_2d(*p.trace_group, "trace group");
    tune::apply_tuning(tuning, device.info(), {p.chunk.has_value(), p.group.has_value(), p.trace_group.has_value()},
                       settings, &trace);
    settings.validate(device.info());

    if (!state.runner) state.runner = std::make_unique<pipeline::Runner>(device);
    const pipeline::Run run = state.runner->run(scene, {pipeline::Work::trace, settings, trace, spec.warmup, spec.repeat});
    const render::SceneBricks& bricks = run.bricks;

    Row r;
    r["chunk"] = settings.chunk;
    r["group"] = settings.eval_group;
    r["trace_group"] = fmt::format("{}x{}", trace.group_x, trace.group_y);
    r["status"] = "ok";
    r["identical"] = run.identical;
    std::uint64_t evaluations = 0, pool_bytes = 0, memory = 0;
    int levels = 0;
    for (const construct::GeometryBuild& b : bricks.builds) {
        evaluations += b.edit_evaluations;
        pool_bytes += b.pool ? b.pool->bytes() : 0;
        levels = std::max(levels, b.levels);
        for (const auto& [k, v] : b.memory) memory += v;
    }
    for (const auto& [k, v] : bricks.bvh.memory) memory += v;
    r["bricks"] = bricks.bricks;
    r["levels"] = levels;
    r["edit_evaluations"] = evaluations;
    r["memory_bytes"] = memory;
    r["build_ms"] = run.build_ms.median;
    r["build_min_ms"] = run.build_ms.min;
    r["build_max_ms"] = run.build_ms.max;
    r["build_cv"] = run.build_ms.cv;
    r["trace_ms"] = run.trace_ms.median;
    r["trace_min_ms"] = run.trace_ms.min;
    r["trace_max_ms"] = run.trace_ms.max;
    r["trace_cv"] = run.trace_ms.cv;
    r["bvh_ms"] = run.bvh_ms.median;
    for (const measure::Stage stage : measure::kConstructionStages)
        r[fmt::format("stage_{}_ms", to_string(stage))] = measure::stage_median(run.stages, stage);

    const std::vector<measure::KernelRow> kernels = measure::kernel_rows(run.captures, device.info());
    const auto eval = std::find_if(kernels.begin(), kernels.end(), [](const measure::KernelRow& k) { return k.kernel == "brick_evaluate"; });
    if (eval != kernels.end()) {
        r["evaluate_local_bytes"] = eval->largest.attributes.local_mem_bytes;
        r["evaluate_registers"] = opt(eval->largest.attributes.registers);
        r["evaluate_groups_per_cu"] = opt(eval->occupancy.groups_per_cu_by_local);
        r["evaluate_resident_groups"] = opt(eval->occupancy.resident_groups_per_cu);
        r["evaluate_occupancy"] = opt(eval->occupancy.theoretical);
        r["evaluate_waves"] = opt(eval->occupancy.waves);
    }
    const double build_s = run.build_ms.median * 1e-3;
    r["evaluations_per_second"] = build_s > 0 ? static_cast<double>(evaluations) / build_s : 0.0;
    const double eval_s = measure::stage_median(run.stages, measure::Stage::evaluate) * 1e-3;
    if (!state.peaks) state.peaks = measure::device_peaks(device);
    if (eval_s > 0) {
        const double gbps = static_cast<double>(pool_bytes) / eval_s * 1e-9;
        r["write_gbps"] = gbps;
        r["bandwidth_fraction"] = state.peaks->bandwidth_gbps > 0 ? gbps / state.peaks->bandwidth_gbps : 0.0;
    }
    r["peak_bandwidth_gbps"] = state.peaks->bandwidth_gbps;
    r["peak_fma_gflops"] = state.peaks->fma_gflops;

    if (spec.accuracy) {
        auto it = state.references.find(p.scene);
        if (it == state.references.end()) {
            reference::ReferenceTracer ref(device);
            it = state.references.emplace(p.scene, ref.render(scene, make_camera(scene.camera, spec.width, spec.height))).first;
        }
        const reference::AccuracyMetrics a = reference::compare(run.trace->buffer, it->second.image, bricks.voxel_world);
        r["mismatch"] = a.mismatch_fraction;
        r["depth_mean"] = a.depth_error_mean;
        r["depth_p99"] = a.depth_error_p99;
        r["normal_mean"] = a.normal_error_mean_deg;
        r["normal_p99"] = a.normal_error_p99_deg;
        r["psnr"] = std::isfinite(a.psnr_db) ? nlohmann::json(a.psnr_db) : nlohmann::json(nullptr);
    }
    return r;
}

// The sweep-file key that gave a point the value of a library setting (SettingError::setting()), or
// "" when the value did not come from the sweep (a tuned or built-in default).
std::string sweep_key(const SweepSpec& spec, const SweepPoint& p, const std::string& setting) {
    if (setting == "leaf_size" && !spec.brick_sizes.empty()) return "brick_sizes";
    if (setting == "chunk" && p.chunk) return "chunks";
    if (setting == "eval_group" && p.group) return "groups";
    if ((setting == "group_x" || setting == "group_y") && p.trace_group) return "trace_groups";
    if (setting == "format" && !spec.formats.empty()) return "formats";
    if (setting == "samples" && !spec.samples.empty()) return "samples";
    if (setting == "width" || setting == "height") return setting;
    return "";
}

// The parameter columns of a point, from the point itself (chunk, group and trace group say "auto"
// until run_point records the values used).
Row point_row(const SweepSpec& spec, const SweepPoint& p, const ocl::DeviceInfo* device, const std::string& key) {
    Row r;
    r["index"] = p.index;
    r["scene"] = std::filesystem::path(p.scene).stem().string();
    r["scene_file"] = p.scene;
    r["device"] = p.device;
    r["vendor"] = device ? device->vendor : "";
    r["driver"] = device ? device->driver_version : "";
    r["platform"] = device ? device->platform_name : "";
    r["brick_size"] = p.brick_size;
    r["chunk"] = opt(p.chunk);
    r["group"] = opt(p.group);
    r["trace_group"] = opt(p.trace_group);
    r["cull"] = p.cull;
    r["format"] = p.format;
    r["samples"] = p.samples;
    r["method"] = p.method;
    r["normals"] = p.normals;
    r["width"] = spec.width;
    r["height"] = spec.height;
    r["repeats"] = spec.repeat;
    r["key"] = key;
    return r;
}

}  // namespace

const std::vector<std::string>& csv_columns() {
    static const std::vector<std::string> columns = [] {
        std::vector<std::string> c = {"index", "scene", "scene_file", "device", "vendor", "driver", "platform",
                                      "brick_size", "chunk", "group", "trace_group", "cull", "format", "samples",
                                      "method", "normals", "width", "height", "status", "error", "repeats",
                                      "identical", "bricks", "levels", "edit_evaluations", "memory_bytes",
                                      "build_ms", "build_min_ms", "build_max_ms", "build_cv", "trace_ms",
                                      "trace_min_ms", "trace_max_ms", "trace_cv", "bvh_ms"};
        for (const measure::Stage stage : measure::kConstructionStages) c.push_back(fmt::format("stage_{}_ms", to_string(stage)));
        for (const char* k : {"evaluate_local_bytes", "evaluate_registers", "evaluate_groups_per_cu",
                              "evaluate_resident_groups", "evaluate_occupancy", "evaluate_waves",
                              "evaluations_per_second", "write_gbps", "bandwidth_fraction", "peak_bandwidth_gbps",
                              "peak_fma_gflops", "mismatch", "depth_mean", "depth_p99", "normal_mean", "normal_p99",
                              "psnr"})
            c.push_back(k);
        return c;
    }();
    return columns;
}

std::string to_csv(const std::vector<Row>& rows) {
    std::string out;
    for (const std::string& c : csv_columns()) out += (out.empty() ? "" : ",") + c;
    out += '\n';
    for (const Row& r : rows) {
        std::string line;
        bool first = true;
        for (const std::string& c : csv_columns()) {
            if (!first) line += ',';
            first = false;
            if (r.contains(c)) line += cell(r[c]);
        }
        out += line + '\n';
    }
    return out;
}

ResultCache::ResultCache(std::filesystem::path path) : path_(std::move(path)) {
    std::error_code ec;
    if (!std::filesystem::exists(path_, ec)) return;
    const std::string text = read_file(path_);
    cut_ = !text.empty() && text.back() != '\n';
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);) {
        try {
            const nlohmann::json j = nlohmann::json::parse(line);
            rows_[j.at("key").get<std::string>()] = j.at("row");
        } catch (const nlohmann::json::exception&) {
            // a line cut short by a killed run: that point runs again
        }
    }
}

const Row* ResultCache::find(const std::string& key) const {
    const auto it = rows_.find(key);
    return it != rows_.end() ? &it->second : nullptr;
}

void ResultCache::add(const std::string& key, const Row& row) {
    rows_[key] = row;
    if (path_.has_parent_path()) std::filesystem::create_directories(path_.parent_path());
    std::ofstream out(path_, std::ios::app);
    if (cut_) out << '\n';
    cut_ = false;
    out << nlohmann::json{{"key", key}, {"row", row}}.dump() << '\n';
    out.flush();
    if (!out) throw std::runtime_error(fmt::format("writing the sweep cache {}", path_.string()));
}

std::vector<std::string> device_labels(const ocl::DeviceSet& devices) {
    std::vector<std::string> labels;
    for (const ocl::Device& d : devices) {
        const auto same = std::count_if(devices.begin(), devices.end(),
                                        [&](const ocl::Device& o) { return o.info().name == d.info().name; });
        labels.push_back(same > 1 ? fmt::format("{} #{}", d.info().name, d.info().index) : d.info().name);
    }
    return labels;
}

std::vector<Row> run_points(const SweepSpec& spec, const std::vector<SweepPoint>& points, ocl::DeviceSet& devices,
                            const tune::TuningDb* tuning, ResultCache& cache,
                            const std::function<void(const Progress&)>& progress) {
    const std::vector<std::string> labels = device_labels(devices);
    std::map<std::string, DeviceState> states;
    for (std::size_t i = 0; i < labels.size(); ++i) states[labels[i]].device = &devices[i];
    std::map<std::string, Scene> scenes;
    std::vector<Row> rows;
    Progress pr;
    pr.total = points.size();
    const auto start = std::chrono::steady_clock::now();
    std::size_t run_count = 0;
    double run_seconds = 0.0;
    for (const SweepPoint& p : points) {
        const std::string key = p.key(spec);
        if (const Row* done = cache.find(key)) {
            rows.push_back(*done);
            ++pr.done;
            ++pr.cached;
            continue;
        }
        const auto device = states.find(p.device);
        if (device == states.end())
            throw InputError(fmt::format("sweep point {} names device \"{}\", which is not open", p.index, p.device));
        pr.elapsed_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        pr.eta_s = run_count ? run_seconds / static_cast<double>(run_count) * static_cast<double>(pr.total - pr.done) : 0.0;
        pr.current = fmt::format("{} {} brick {} chunk {} cull {}", std::filesystem::path(p.scene).stem().string(),
                                 p.device, p.brick_size, p.chunk ? std::to_string(*p.chunk) : "auto", p.cull ? "on" : "off");
        if (progress) progress(pr);
        const auto t0 = std::chrono::steady_clock::now();
        Row row = point_row(spec, p, &device->second.device->info(), key);
        try {
            auto s = scenes.find(p.scene);
            if (s == scenes.end()) {
                const Scene file_scene = load_scene(p.scene);
                s = scenes.emplace(p.scene, scene_at(file_scene, file_scene.time)).first;
            }
            row.update(run_point(spec, p, device->second, s->second, tuning));
        } catch (const SettingError& e) {  // a value the device or scene refuses: the row names its key
            const std::string k = sweep_key(spec, p, e.setting());
            row["status"] = "error";
            row["error"] = k.empty() ? std::string(e.what()) : fmt::format("\"{}\": {}", k, e.what());
        } catch (const std::exception& e) {  // bad input or a device failure: recorded, the sweep goes on
            row["status"] = "error";
            row["error"] = e.what();
        }
        cache.add(key, row);
        rows.push_back(std::move(row));
        ++pr.done;
        ++run_count;
        run_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    }
    pr.elapsed_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    pr.eta_s = 0.0;
    pr.current.clear();
    if (progress) progress(pr);
    return rows;
}

nlohmann::json sweep_document(const SweepSpec& spec, Shard shard, std::size_t grid_points, const std::vector<Row>& rows) {
    return {{"command", "sweep"},
            {"spec", to_json(spec)},
            {"shard", {{"index", shard.index}, {"count", shard.count}}},
            {"grid_points", grid_points},
            {"points", rows}};
}

Merged merge(const std::vector<nlohmann::json>& documents, const std::vector<std::string>& where) {
    Merged out;
    std::map<std::string, std::pair<std::size_t, Row>> by_key;  // key -> (grid index, row)
    std::set<std::size_t> shards;
    std::optional<nlohmann::json> spec;
    bool one_spec = true;
    std::size_t shard_count = 0, grid_points = 0;
    for (std::size_t d = 0; d < documents.size(); ++d) {
        const nlohmann::json& doc = documents[d];
        if (!doc.is_object() || doc.value("command", "") != "sweep" || !doc.contains("points") || !doc["points"].is_array())
            throw InputError(fmt::format("{}: not a sweep result (expected the JSON that sdfbrick sweep writes)", where[d]));
        if (!spec) {
            spec = doc.at("spec");
            shard_count = doc.at("shard").value("count", std::size_t{1});
            grid_points = doc.value("grid_points", std::size_t{0});
        } else if (doc.at("spec") != *spec || doc.at("shard").value("count", std::size_t{1}) != shard_count) {
            one_spec = false;
        }
        const std::size_t shard = doc.at("shard").value("index", 0);
        if (!shards.insert(shard).second && one_spec)
            out.notes.push_back(fmt::format("{}: shard {} appears more than once", where[d], shard));
        for (const nlohmann::json& row : doc["points"]) {
            const std::string key = row.value("key", "");
            if (by_key.count(key)) {
                out.notes.push_back(fmt::format("{}: point {} already merged from an earlier file; the later one is kept",
                                                where[d], row.value("index", 0)));
            }
            by_key[key] = {row.value("index", std::size_t{0}), Row(row)};
        }
    }
    for (auto& [key, v] : by_key) out.rows.push_back(std::move(v.second));
    if (one_spec) {
        std::stable_sort(out.rows.begin(), out.rows.end(),
                         [](const Row& a, const Row& b) { return a.value("index", 0) < b.value("index", 0); });
        for (std::size_t s = 0; s < shard_count; ++s)
            if (!shards.count(s)) out.notes.push_back(fmt::format("shard {}/{} is missing", s, shard_count));
        if (out.rows.size() != grid_points)
            out.notes.push_back(fmt::format("{} of the grid's {} points are present", out.rows.size(), grid_points));
        out.complete = shards.size() == shard_count && out.rows.size() == grid_points;
    } else {
        out.notes.push_back("the inputs are different sweeps (spec or shard count differ): rows are joined, "
                            "completeness is not checked");
    }
    return out;
}

}  // namespace sdfbrick::sweep
