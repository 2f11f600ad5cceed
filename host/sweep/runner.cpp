#include "sweep/runner.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <chrono>
#include <cerrno>
#include <cstring>
#include <memory>
#include <set>
#include <sstream>

#include <fmt/format.h>

#include "core/errors.h"
#include "core/files.h"
#include "core/quote.h"
#include "measure/peaks.h"
#include "measure/statistics.h"
#include "reference/accuracy.h"
#include "pipeline/report.h"
#include "pipeline/run.h"
#include "reference/device_tracer.h"
#include "scene/scene_json.h"
#include "tune/apply.h"

namespace sdfbrick::sweep {

namespace {

// What one device needs across points: its pipeline (compiled programs), peaks and references.
struct DeviceState {
    ocl::Device* device = nullptr;
    std::unique_ptr<pipeline::Executor> executor;  // one lane, whole placement
    std::optional<measure::DevicePeaks> peaks;
    std::map<std::string, reference::ReferenceResult> references;  // per scene file
};

std::optional<EvaluateOccupancy> evaluate_occupancy(const std::vector<measure::KernelRow>& kernels) {
    const auto eval = std::find_if(kernels.begin(), kernels.end(),
                                   [](const measure::KernelRow& k) { return k.kernel == "brick_evaluate"; });
    if (eval == kernels.end()) return std::nullopt;
    return EvaluateOccupancy{eval->largest.attributes.local_mem_bytes, eval->largest.attributes.registers,
                             eval->occupancy.groups_per_cu_by_local, eval->occupancy.resident_groups_per_cu,
                             eval->occupancy.theoretical, eval->occupancy.waves};
}

PointAccuracy point_accuracy(const reference::AccuracyMetrics& a) {
    return {a.mismatch_fraction, a.depth_error_mean, a.depth_error_p99, a.normal_error_mean_deg,
            a.normal_error_p99_deg, std::isfinite(a.psnr_db) ? std::optional<double>(a.psnr_db) : std::nullopt};
}

std::uint64_t total_bytes(const pipeline::Memory& memory) {
    std::uint64_t sum = 0;
    for (const auto& [name, bytes] : memory) sum += bytes;
    return sum;
}

// The columns of a point's results from its run's figures and the device's peaks.
PointResults point_results(const pipeline::RenderFigures& f, const measure::DevicePeaks& peaks) {
    PointResults r;
    r.identical = f.identical;
    r.bricks = f.construction.bricks;
    r.levels = f.construction.levels;
    r.edit_evaluations = f.construction.edit_evaluations;
    r.memory_bytes = total_bytes(f.construction.memory) + total_bytes(f.bvh.memory);
    r.pool_bytes = f.construction.pool_bytes;
    for (const pipeline::GeometryFigures& g : f.construction.geometries)
        r.check_error_max = std::max(r.check_error_max, g.check_error_max);
    r.build_ms = f.build_ms;
    r.trace_ms = f.trace_ms;
    r.bvh_ms = f.bvh_ms.median;
    for (std::size_t i = 0; i < measure::kConstructionStages.size(); ++i)
        r.stage_ms[i] = measure::stage_median(f.stages, measure::kConstructionStages[i]);
    r.evaluate = evaluate_occupancy(f.kernels);
    const double build_s = f.build_ms.median * 1e-3;
    r.evaluations_per_second = build_s > 0 ? static_cast<double>(f.construction.edit_evaluations) / build_s : 0.0;
    const double eval_s = measure::stage_median(f.stages, measure::Stage::evaluate) * 1e-3;
    if (eval_s > 0) {
        const double gbps = static_cast<double>(f.construction.pool_bytes) / eval_s * 1e-9;
        r.write = WriteBandwidth{gbps, peaks.bandwidth_gbps > 0 ? gbps / peaks.bandwidth_gbps : 0.0};
    }
    r.peak_bandwidth_gbps = peaks.bandwidth_gbps;
    r.peak_fma_gflops = peaks.fma_gflops;
    return r;
}

// row (the point's parameters) with the values used and the results.
SweepRow run_point(const SweepSpec& spec, const SweepPoint& p, DeviceState& state, const Scene& scene,
                   const tune::TuningDb* tuning, SweepRow row) {
    ocl::Device& device = *state.device;
    construct::BuildSettings settings;
    settings.leaf_size = p.brick_size;
    settings.tolerance = p.tolerance;
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
    if (!state.executor) state.executor = std::make_unique<pipeline::Executor>(device);
    pipeline::Job job;
    job.settings = tune::settings_for(settings, trace, tuning,
                                      {.chunk = p.chunk.has_value(), .group = p.group.has_value(),
                                       .trace_group = p.trace_group.has_value()});
    job.warmup = spec.warmup;
    job.repeat = spec.repeat;
    job.brick_digests = false;
    job.image = spec.accuracy;
    const pipeline::Execution e = state.executor->run(scene, job);
    const pipeline::Run& run = e.job();
    settings = e.home_lane().settings.build;
    trace = e.home_lane().settings.trace;
    const pipeline::RenderFigures figures = pipeline::render_figures(e);
    if (!state.peaks) state.peaks = measure::device_peaks(device);
    row.chunk = settings.chunk;
    row.group = settings.eval_group;
    row.trace_group = fmt::format("{}x{}", trace.group_x, trace.group_y);
    row.status = "ok";
    row.results = point_results(figures, *state.peaks);

    if (spec.accuracy) {
        auto it = state.references.find(p.scene);
        if (it == state.references.end()) {
            const SdfCamera camera = make_camera(scene.camera, spec.width, spec.height);
            it = state.references.emplace(p.scene, state.executor->lane(0).reference().render(scene, camera)).first;
        }
        const reference::AccuracyMetrics a = reference::compare(run.trace->buffer, it->second.image, run.bricks.voxel_world);
        row.results->accuracy = point_accuracy(a);
    }
    return row;
}

// The sweep-file key that gave a point the value of a library setting (SettingError::setting()), or
// "" when the value did not come from the sweep (a tuned or built-in default).
std::string sweep_key(const SweepSpec& spec, const SweepPoint& p, const std::string& setting) {
    if (setting == "leaf_size" && !spec.brick_sizes.empty()) return "brick_sizes";
    if (setting == "tolerance" && !spec.tolerances.empty()) return "tolerances";
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
SweepRow point_row(const SweepSpec& spec, const SweepPoint& p, const ocl::DeviceInfo* device, const std::string& key) {
    SweepRow r;
    r.index = p.index;
    r.scene = std::filesystem::path(p.scene).stem().string();
    r.scene_file = p.scene;
    r.device = p.device;
    r.vendor = device ? device->vendor : "";
    r.driver = device ? device->driver_version : "";
    r.platform = device ? device->platform_name : "";
    r.brick_size = p.brick_size;
    r.tolerance = p.tolerance;
    r.chunk = p.chunk;
    r.group = p.group;
    r.trace_group = p.trace_group;
    r.cull = p.cull;
    r.format = p.format;
    r.samples = p.samples;
    r.method = p.method;
    r.normals = p.normals;
    r.width = spec.width;
    r.height = spec.height;
    r.repeats = spec.repeat;
    r.key = key;
    return r;
}

}  // namespace

ResultCache::ResultCache(std::filesystem::path path) : path_(std::move(path)) {
    std::error_code ec;
    if (path_.empty()) return;  // a cache in memory only
    if (path_.has_parent_path() && !std::filesystem::is_directory(path_.parent_path(), ec) &&
        !std::filesystem::create_directories(path_.parent_path(), ec) && ec)
        throw InputError(fmt::format("{}: cannot make the cache's folder: {}", path_.string(), ec.message()));
    fd_ = open_journal(path_);
    const std::string text = read_file(path_);
    cut_ = !text.empty() && text.back() != '\n';
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);) {
        try {
            const nlohmann::json j = nlohmann::json::parse(line);
            rows_[j.at("key").get<std::string>()] = row_from_json(j.at("row"));
        } catch (const std::exception&) {  // json's errors and InputError
            // a line cut short by a killed run (or a row that does not read back): that point runs again
        }
    }
}

const SweepRow* ResultCache::find(const std::string& key) const {
    const auto it = rows_.find(key);
    return it != rows_.end() ? &it->second : nullptr;
}

ResultCache::~ResultCache() {
    if (fd_ >= 0) ::close(fd_);
}

void ResultCache::add(const std::string& key, const SweepRow& row) {
    rows_[key] = row;
    if (path_.empty()) return;
    std::string line = cut_ ? "\n" : "";
    cut_ = false;
    line += nlohmann::json{{"key", key}, {"row", to_json(row)}}.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
    line += '\n';
    for (std::size_t done = 0; done < line.size();) {
        const ssize_t n = ::write(fd_, line.data() + done, line.size() - done);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) throw InputError(fmt::format("{}: write failed: {}", path_.string(), std::strerror(n < 0 ? errno : EIO)));
        done += static_cast<std::size_t>(n);
    }
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

std::vector<SweepRow> run_points(const SweepSpec& spec, const std::vector<SweepPoint>& points, ocl::DeviceSet& devices,
                            const tune::TuningDb* tuning, ResultCache& cache,
                            const std::function<void(const Progress&)>& progress) {
    const std::vector<std::string> labels = device_labels(devices);
    std::map<std::string, DeviceState> states;
    for (std::size_t i = 0; i < labels.size(); ++i) states[labels[i]].device = &devices[i];
    std::map<std::string, Scene> scenes;
    std::vector<SweepRow> rows;
    Progress pr;
    pr.total = points.size();
    const auto start = std::chrono::steady_clock::now();
    std::size_t run_count = 0;
    double run_seconds = 0.0;
    for (const SweepPoint& p : points) {
        const std::string key = p.key(spec);
        if (const SweepRow* done = cache.find(key)) {
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
        SweepRow row = point_row(spec, p, &device->second.device->info(), key);
        try {
            auto s = scenes.find(p.scene);
            if (s == scenes.end()) {
                const Scene file_scene = load_scene(p.scene);
                s = scenes.emplace(p.scene, scene_at(file_scene, file_scene.time)).first;
            }
            row = run_point(spec, p, device->second, s->second, tuning, row);
        } catch (const SettingError& e) {  // a value the device or scene refuses: the row names its key
            const std::string k = sweep_key(spec, p, e.setting());
            row.status = "error";
            row.error = k.empty() ? std::string(e.what()) : fmt::format("\"{}\": {}", k, e.what());
        } catch (const std::exception& e) {  // bad input or a device failure: recorded, the sweep goes on
            row.status = "error";
            row.error = e.what();
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

nlohmann::json sweep_document(const SweepSpec& spec, Shard shard, std::size_t grid_points, const std::vector<SweepRow>& rows) {
    return {{"command", "sweep"},
            {"spec", to_json(spec)},
            {"shard", {{"index", shard.index}, {"count", shard.count}}},
            {"grid_points", grid_points},
            {"points", to_json(rows)}};
}

namespace {

// The rows of one document into by_key (a later row of the same key replaces the earlier one).
void merge_points(const nlohmann::json& points, const std::string& where, std::map<std::string, SweepRow>& by_key,
                  std::vector<std::string>& notes) {
    for (std::size_t p = 0; p < points.size(); ++p) {
        SweepRow row;
        try {
            row = row_from_json(points[p]);
        } catch (const InputError& e) {
            throw InputError(fmt::format("{}: /points/{}{}{}", where, p, e.what()[0] == '/' ? "" : ": ", e.what()));
        }
        if (by_key.count(row.key))
            notes.push_back(fmt::format("{}: point {} already merged from an earlier file; the later one is kept",
                                        where, row.index));
        by_key[row.key] = std::move(row);
    }
}

// The fields of a sweep result that merging reads, checked: InputError naming the file and the
// JSON path of the first that is missing or wrongly typed.
struct ShardDocument {
    const nlohmann::json* spec = nullptr;
    std::size_t index = 0, count = 1, grid_points = 0;
};

std::size_t count_field(const nlohmann::json& j, const char* name, const std::string& where, const std::string& path) {
    const auto it = j.find(name);
    if (it == j.end() || !it->is_number_unsigned())
        throw InputError(fmt::format("{}: {}/{}: expected a non-negative integer{}", where, path, name,
                                     it == j.end() ? ", found none" : fmt::format(", got {}", escaped(it->dump(), 40))));
    return it->get<std::size_t>();
}

ShardDocument read_shard_document(const nlohmann::json& doc, const std::string& where) {
    if (!doc.is_object() || doc.value("command", "") != "sweep" || !doc.contains("points") || !doc["points"].is_array() ||
        !doc.contains("spec"))
        throw InputError(fmt::format("{}: not a sweep result (expected the JSON that sdfbrick sweep writes)", where));
    const auto shard = doc.find("shard");
    if (shard == doc.end() || !shard->is_object()) throw InputError(fmt::format("{}: /shard: expected an object", where));
    ShardDocument d{&doc["spec"], count_field(*shard, "index", where, "/shard"), count_field(*shard, "count", where, "/shard"),
                    count_field(doc, "grid_points", where, "")};
    if (d.count == 0 || d.index >= d.count)
        throw InputError(fmt::format("{}: /shard: index {} of {} shards is out of range", where, d.index, d.count));
    return d;
}

}  // namespace

Merged merge(const std::vector<nlohmann::json>& documents, const std::vector<std::string>& where) {
    Merged out;
    std::map<std::string, SweepRow> by_key;
    std::set<std::size_t> shards;
    std::optional<ShardDocument> first;
    bool one_spec = true;
    for (std::size_t d = 0; d < documents.size(); ++d) {
        const ShardDocument doc = read_shard_document(documents[d], where[d]);
        if (!first) first = doc;
        else if (*doc.spec != *first->spec || doc.count != first->count) one_spec = false;
        if (!shards.insert(doc.index).second && one_spec)
            out.notes.push_back(fmt::format("{}: shard {} appears more than once", where[d], doc.index));
        merge_points(documents[d]["points"], where[d], by_key, out.notes);
    }
    for (auto& [key, row] : by_key) out.rows.push_back(std::move(row));
    const std::size_t shard_count = first ? first->count : 0, grid_points = first ? first->grid_points : 0;
    if (one_spec) {
        std::stable_sort(out.rows.begin(), out.rows.end(),
                         [](const SweepRow& a, const SweepRow& b) { return a.index < b.index; });
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
