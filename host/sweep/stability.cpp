#include "sweep/stability.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iterator>
#include <memory>
#include <set>
#include <sstream>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "core/errors.h"
#include "image/image.h"
#include "pipeline/executor.h"
#include "reference/device_tracer.h"
#include "reference/host_tracer.h"
#include "render/pictures.h"
#include "scene/scene_json.h"
#include "scene/to_device.h"
#include "tune/apply.h"

namespace sdfbrick::sweep {

namespace {

// The builds of a case: a storage format and uniform or adaptive leaves.
struct BuildChoice {
    construct::BrickFormat format;
    bool adaptive;
};

// The lists to run, each filled with every choice when the spec leaves it empty.
struct Lists {
    std::vector<render::Method> methods;
    std::vector<render::NormalMethod> normals;
    std::vector<BuildChoice> builds;
};

Lists resolve_lists(const StabilitySpec& spec) {
    Lists l;
    l.methods = spec.methods.empty() ? std::vector<render::Method>(render::kMethods.begin(), render::kMethods.end())
                                     : spec.methods;
    l.normals = spec.normals.empty()
                    ? std::vector<render::NormalMethod>(render::kNormalMethods.begin(), render::kNormalMethods.end())
                    : spec.normals;
    const std::vector<construct::BrickFormat> formats =
        spec.formats.empty() ? std::vector<construct::BrickFormat>{construct::BrickFormat::int8, construct::BrickFormat::int16,
                                                                   construct::BrickFormat::float32}
                             : spec.formats;
    const std::vector<bool> adaptive = spec.adaptive.empty() ? std::vector<bool>{false, true} : spec.adaptive;
    for (const construct::BrickFormat f : formats)
        for (const bool a : adaptive) l.builds.push_back({f, a});
    return l;
}

// Each pixel's voxel in world units: the finest voxel of the geometry whose brick it hit, times the
// smallest scale among that geometry's objects (misses: the scene's smallest voxel).
std::vector<double> pixel_voxels(const Scene& scene, const render::SceneBricks& bricks, const RenderBuffer& b) {
    std::vector<double> geometry_voxel(bricks.builds.size(), bricks.voxel_world);
    std::vector<std::uint64_t> end(bricks.builds.size());  // one past each geometry's last global brick
    std::uint64_t first = 0;
    for (std::size_t g = 0; g < bricks.builds.size(); ++g) {
        double scale = 0.0;
        for (const Object& o : scene.objects)
            if (o.geometry == g) scale = scale == 0.0 ? o.transform.scale : std::min(scale, o.transform.scale);
        if (scale > 0.0) geometry_voxel[g] = bricks.settings.voxel() * scale;
        first += bricks.builds[g].leaf_count;
        end[g] = first;
    }
    std::vector<double> out(b.pixels(), bricks.voxel_world);
    for (std::size_t i = 0; i < b.pixels(); ++i) {
        if (!b.is_hit(i)) continue;
        const auto g = std::upper_bound(end.begin(), end.end(), std::uint64_t{b.aux[i].s[0]}) - end.begin();
        if (static_cast<std::size_t>(g) < end.size()) out[i] = geometry_voxel[static_cast<std::size_t>(g)];
    }
    return out;
}

// Pixels whose normal or depth differ bit for bit.
std::uint64_t differing_pixels(const RenderBuffer& a, const RenderBuffer& b) {
    std::uint64_t n = 0;
    for (std::size_t i = 0; i < a.pixels(); ++i) n += std::memcmp(&a.hit[i], &b.hit[i], sizeof(cl_float4)) != 0;
    return n;
}

construct::BuildSettings build_settings(const StabilityCase& c, const BuildChoice& b, double tolerance_voxels) {
    construct::BuildSettings s;
    s.leaf_size = c.brick_size;
    s.format = b.format;
    if (b.adaptive) s.tolerance = tolerance_voxels * s.voxel();
    return s;
}

std::string picture_path(const std::string& folder, const std::string& name) {
    return (std::filesystem::path(folder) / (name + (image_io_has_oiio() ? ".png" : ".ppm"))).string();
}

// A picture encoded now, to be written with the report: a few small files kept as bytes, not images.
Output picture(const Image& image, const std::string& path) {
    std::ostringstream bytes;
    image_output(image, path).write(bytes);
    return text_output(path, std::move(bytes).str());
}

// Everything one case runs, with the state its cells share.
class CaseRun {
public:
    CaseRun(const StabilitySpec& spec, const Lists& lists, pipeline::Executor& executor, const StabilityCase& c,
            std::vector<Output>& pictures)
        : spec_(spec), lists_(lists), executor_(executor), case_(c), pictures_(pictures) {
        const Scene file_scene = load_scene(c.file);
        scene_ = scene_at(file_scene, file_scene.time);
        camera_ = make_camera(scene_.camera, spec.width, spec.height);
        reference_ = executor.lane(0).reference().render(scene_, camera_).image;
        if (spec.pictures) pictures_.push_back(picture(normal_image(reference_), picture_path(*spec.pictures, name() + "-reference")));
    }

    std::string name() const { return std::filesystem::path(case_.file).stem().string(); }

    // Builds on every device; returns the error message, or "" when every device built.
    std::string build(const BuildChoice& b) {
        settings_ = build_settings(case_, b, spec_.tolerance_voxels);
        try {
            built_.reset();
            pipeline::Job job;
            job.work = pipeline::Work::bvh;
            job.settings = tune::settings_for(settings_, render::TraceSettings{}, spec_.tuning, {});
            job.brick_digests = false;
            built_ = executor_.run(scene_, job, executor_.size() > 1 ? pipeline::Placement::replicate
                                                                    : pipeline::Placement::whole);
        } catch (const std::exception& e) {
            return e.what();
        }
        return "";
    }

    StabilityCell cell(const BuildChoice& b, render::Method m, render::NormalMethod n, const std::string& build_error) {
        StabilityCell c;
        c.case_name = name();
        c.file = case_.file;
        c.brick_size = case_.brick_size;
        c.method = m;
        c.normals = n;
        c.format = b.format;
        c.tolerance = settings_.tolerance;
        if (!build_error.empty()) {
            c.error = build_error;
        } else {
            try {
                trace(c);
            } catch (const std::exception& e) {
                c.error = e.what();
            }
        }
        c.failures = c.error ? std::vector<std::string>{"error"} : threshold_failures(c.accuracy, kStabilityThresholds);
        if (c.capped_rays > 0) c.failures.push_back("step cap");
        if (c.device_differences.value_or(0) > 0) c.failures.push_back("devices");
        return c;
    }

private:
    void trace(StabilityCell& c) {
        pipeline::Job job;
        job.settings = [&](const ocl::DeviceInfo& device) {  // the build's settings and tuned trace group
            const auto lane = std::find_if(built_->lanes.begin(), built_->lanes.end(),
                                           [&](const pipeline::LaneRun& l) { return l.device.index == device.index; });
            pipeline::LaneSettings s = lane->settings;
            s.trace.width = spec_.width;
            s.trace.height = spec_.height;
            s.trace.method = c.method;
            s.trace.normals = c.normals;
            return s;
        };
        pipeline::Execution traced = executor_.trace(scene_, *built_, job);
        std::optional<RenderBuffer> first;
        for (std::size_t i = 0; i < traced.lanes.size(); ++i) {
            pipeline::Run& run = traced.lanes[i].run;
            RenderBuffer& buffer = run.trace->buffer;
            if (first) {
                c.device_differences = c.device_differences.value_or(0) + differing_pixels(*first, buffer);
                continue;
            }
            const render::SceneBricks& bricks = built_->lanes[i].run.bricks;
            const std::vector<double> voxels = pixel_voxels(scene_, bricks, buffer);
            c.accuracy = reference::compare(buffer, reference_, voxels);
            const reference::HostCamera rays =
                reference::make_host_camera(scene_.camera, reference_.width, reference_.height);
            reference::add_surface_error(c.accuracy, buffer, reference_, rays);
            c.capped_rays = render::work_counts(buffer).capped_rays;
            for (const render::TraceWarning& w : run.trace->warnings) c.warnings.push_back(w.message);
            c.bricks = bricks.bricks;
            c.build_ms = built_->lanes[i].run.build_ms.median;
            c.trace_ms = run.trace_ms.median;
            if (pictured(c)) write_pictures(c, buffer, voxels);
            first = std::move(buffer);
        }
    }

    // Pictures show the first build of the lists with the default normal rule (else the first rule).
    bool pictured(const StabilityCell& c) const {
        if (!spec_.pictures) return false;
        const BuildChoice& b = lists_.builds.front();
        const render::NormalMethod def = render::TraceSettings{}.normals;
        const bool has_default = std::find(lists_.normals.begin(), lists_.normals.end(), def) != lists_.normals.end();
        return c.format == b.format && (c.tolerance > 0.0) == b.adaptive &&
               c.normals == (has_default ? def : lists_.normals.front());
    }

    void write_pictures(const StabilityCell& c, const RenderBuffer& buffer, std::span<const double> voxels) {
        const std::string stem = name() + "-" + std::string(render::to_string(c.method));
        pictures_.push_back(picture(normal_image(buffer), picture_path(*spec_.pictures, stem)));
        pictures_.push_back(picture(reference::difference_image(buffer, reference_, voxels),
                                    picture_path(*spec_.pictures, stem + "-difference")));
    }

    const StabilitySpec& spec_;
    const Lists& lists_;
    pipeline::Executor& executor_;
    std::optional<pipeline::Execution> built_;  // the current build, one per device
    StabilityCase case_;
    std::vector<Output>& pictures_;
    Scene scene_;
    SdfCamera camera_{};
    RenderBuffer reference_;
    construct::BuildSettings settings_;
};

double seconds_since(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

StabilityCase parse_case(const std::string& text, double default_brick_size) {
    const auto at = text.rfind('@');
    if (at == std::string::npos) return {text, default_brick_size};
    const std::string size = text.substr(at + 1);
    char* end = nullptr;
    const double v = std::strtod(size.c_str(), &end);
    if (size.empty() || end != size.c_str() + size.size() || !(v > 0.0) || !std::isfinite(v))
        throw InputError(fmt::format("case \"{}\": the brick size after '@' must be a number > 0", text));
    return {text.substr(0, at), v};
}

std::vector<std::string> threshold_failures(const reference::AccuracyMetrics& a, const StabilityThresholds& t) {
    std::vector<std::string> f;
    if (a.mismatch_fraction > t.mismatch_fraction) f.push_back("mismatch");
    if (a.depth_error_p99 > t.depth_p99_voxels) f.push_back("depth");
    if (a.normal_error_p99_deg > t.normal_p99_deg) f.push_back("normals");
    return f;
}

StabilityReport run_stability(const StabilitySpec& spec, ocl::DeviceSet& devices,
                              const std::function<void(const StabilityProgress&)>& progress) {
    if (spec.cases.empty()) throw InputError("stability: no cases");
    if (devices.size() == 0) throw InputError("stability: no device");
    validate_image_size(spec.width, spec.height);
    const Lists lists = resolve_lists(spec);
    const auto start = std::chrono::steady_clock::now();
    StabilityReport report;
    report.width = spec.width;
    report.height = spec.height;
    report.tolerance_voxels = spec.tolerance_voxels;
    std::vector<ocl::Device*> pointers;
    for (ocl::Device& d : devices) {
        report.devices.push_back(d.info().name);
        pointers.push_back(&d);
    }
    pipeline::Executor executor(pointers);
    StabilityProgress p;
    p.total = spec.cases.size() * lists.builds.size() * lists.methods.size() * lists.normals.size();
    for (const StabilityCase& c : spec.cases) {
        CaseRun run(spec, lists, executor, c, report.pictures);
        for (const BuildChoice& b : lists.builds) {
            p.current = fmt::format("{} {} {}", run.name(), construct::to_string(b.format), b.adaptive ? "adaptive" : "uniform");
            if (progress) progress(p);
            const std::string error = run.build(b);
            for (const render::Method m : lists.methods)
                for (const render::NormalMethod n : lists.normals) {
                    report.cells.push_back(run.cell(b, m, n, error));
                    ++p.done;
                    p.elapsed_s = seconds_since(start);
                    p.eta_s = p.elapsed_s / static_cast<double>(p.done) * static_cast<double>(p.total - p.done);
                }
        }
    }
    p.current.clear();
    if (progress) progress(p);
    report.seconds = seconds_since(start);
    return report;
}

void write_stability_outputs(const StabilityReport& report, const StabilitySpec& spec, std::vector<Output> others) {
    std::vector<Output> outputs = report.pictures;
    outputs.insert(outputs.end(), std::make_move_iterator(others.begin()), std::make_move_iterator(others.end()));
    const bool made = spec.pictures && make_output_folder(*spec.pictures);
    try {
        write_all(outputs);
    } catch (...) {
        std::error_code ignored;
        if (made) std::filesystem::remove(*spec.pictures, ignored);
        throw;
    }
}

nlohmann::json to_json(const StabilityReport& r) {
    nlohmann::json cells = nlohmann::json::array();
    for (const StabilityCell& c : r.cells) {
        nlohmann::json j = {{"case", c.case_name}, {"file", c.file}, {"brick_size", c.brick_size},
                            {"method", render::to_string(c.method)}, {"normals", render::to_string(c.normals)},
                            {"format", construct::to_string(c.format)}, {"build", c.tolerance > 0.0 ? "adaptive" : "uniform"},
                            {"tolerance", c.tolerance}, {"failed", c.failed()}, {"failures", c.failures}};
        if (c.error) {
            j["error"] = *c.error;
        } else {
            j["accuracy"] = reference::to_json(c.accuracy);
            j["capped_rays"] = c.capped_rays;
            j["warnings"] = c.warnings;
            j["bricks"] = c.bricks;
            j["build_ms"] = c.build_ms;
            j["trace_ms"] = c.trace_ms;
        }
        if (c.device_differences) j["device_differences"] = *c.device_differences;
        cells.push_back(std::move(j));
    }
    const StabilityThresholds& t = r.thresholds;
    return {{"command", "stability"},
            {"thresholds", {{"mismatch_fraction", t.mismatch_fraction}, {"depth_p99_voxels", t.depth_p99_voxels},
                            {"normal_p99_deg", t.normal_p99_deg}}},
            {"devices", r.devices}, {"width", r.width}, {"height", r.height},
            {"tolerance_voxels", r.tolerance_voxels}, {"seconds", r.seconds}, {"cells", cells}};
}

namespace {

std::string cell_text(const StabilityCell& c) {
    std::string s = fmt::format("  {:<6} {:<8} {:<8} {:<10} ", construct::to_string(c.format),
                                c.tolerance > 0.0 ? "adaptive" : "uniform", render::to_string(c.method),
                                render::to_string(c.normals));
    if (c.error) return s + "error: " + *c.error + "\n";
    const reference::AccuracyMetrics& a = c.accuracy;
    s += fmt::format("mismatch {:7.4f}%  depth p99 {:8.3f} max {:9.2f} vox  normal mean {:6.2f} p99 {:6.2f} deg  "
                     "build {:8.1f} ms trace {:7.1f} ms",
                     100.0 * a.mismatch_fraction, a.depth_error_p99, a.depth_error_max, a.normal_error_mean_deg,
                     a.normal_error_p99_deg, c.build_ms, c.trace_ms);
    if (c.capped_rays > 0) s += fmt::format("  {} rays at the step cap", c.capped_rays);
    if (c.device_differences) s += fmt::format("  devices differ in {} px", *c.device_differences);
    if (c.failed()) s += fmt::format("  FAIL ({})", fmt::join(c.failures, ", "));
    return s + "\n";
}

}  // namespace

std::string to_text(const StabilityReport& r) {
    std::string s = fmt::format("stability: {} cells, {}x{}, devices: {}; fail when mismatch > {}%, depth p99 > {} "
                                "voxels, normal p99 > {} deg, a ray at the step cap or devices differ\n",
                                r.cells.size(), r.width, r.height, fmt::join(r.devices, ", "),
                                100.0 * r.thresholds.mismatch_fraction, r.thresholds.depth_p99_voxels,
                                r.thresholds.normal_p99_deg);
    for (auto first = r.cells.begin(); first != r.cells.end();) {
        const auto end = std::find_if(first, r.cells.end(), [&](const StabilityCell& c) { return c.case_name != first->case_name; });
        s += fmt::format("{} ({}, bricks {})\n", first->case_name, first->file, first->brick_size);
        std::set<std::string> warnings;  // each of the case's warnings once
        for (auto c = first; c != end; ++c) {
            s += cell_text(*c);
            warnings.insert(c->warnings.begin(), c->warnings.end());
        }
        for (const std::string& w : warnings) s += "  warning: " + w + "\n";
        first = end;
    }
    const std::size_t failed =
        static_cast<std::size_t>(std::count_if(r.cells.begin(), r.cells.end(), [](const StabilityCell& c) { return c.failed(); }));
    s += fmt::format("{} of {} cells failed; {:.1f} s\n", failed, r.cells.size(), r.seconds);
    return s;
}

}  // namespace sdfbrick::sweep
