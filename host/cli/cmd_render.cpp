// `sdfbrick render`: builds a scene's bricks and BVH, ray traces them from the scene's camera, writes
// the picture, and with --compare measures the render against the device reference tracer (the
// analytic edit lists, no bricks) with the same camera.
#include <algorithm>
#include <cstring>
#include <cstdio>
#include <filesystem>
#include <memory>

#include <fmt/format.h>

#include "bvh/bvh_builder.h"
#include "cli/build_flags.h"
#include "cli/commands.h"
#include "core/errors.h"
#include "core/files.h"
#include "core/hash.h"
#include "core/stats.h"
#include "reference/accuracy.h"
#include "render/seams.h"
#include "render/brick_tracer.h"
#include "render/pictures.h"
#include "pipeline/report.h"
#include "pipeline/run.h"
#include "reference/device_tracer.h"
#include "scene/scene_json.h"
#include "tune/apply.h"

namespace sdfbrick::cli {

namespace {

const char* const kModes[] = {"normals", "depth", "shaded", "steps", "bricks"};

struct RenderOptions {
    std::string file;
    std::optional<double> time;
    BuildFlags flags;
    render::TraceSettings trace;
    std::string mode = "normals";
    std::string method = "sphere";
    std::string normals = "continuous";
    std::optional<std::string> out;
    bool reference = false;
    bool compare = false;
    MeasureFlags measure;
    bool trace_group_given = false;
    std::optional<std::string> json;
};

bool float_format(const std::filesystem::path& p) {
    const std::string e = p.extension().string();
    return e == ".exr" || e == ".pfm" || e == ".tif" || e == ".tiff" || e == ".hdr";
}

// Depth for viewing: near surfaces bright, far ones dark, misses black.
Image depth_view(const RenderBuffer& b) {
    double lo = INFINITY, hi = -INFINITY;
    for (std::size_t i = 0; i < b.pixels(); ++i)
        if (b.is_hit(i)) {
            lo = std::min<double>(lo, b.hit[i].s[3]);
            hi = std::max<double>(hi, b.hit[i].s[3]);
        }
    Image out(b.width, b.height, 3);
    for (std::size_t i = 0; i < b.pixels(); ++i) {
        if (!b.is_hit(i)) continue;
        const double v = hi > lo ? 1.0 - 0.8 * (b.hit[i].s[3] - lo) / (hi - lo) : 1.0;
        for (int c = 0; c < 3; ++c) out.pixels[3 * i + c] = static_cast<float>(v);
    }
    return out;
}

Image picture(const std::string& mode, const RenderBuffer& b, const Image& shaded,
              const std::filesystem::path& path) {
    if (mode == "depth") return float_format(path) ? depth_image(b) : depth_view(b);
    if (mode == "shaded") return shaded;
    if (mode == "steps") return render::steps_image(b);
    if (mode == "bricks") return render::brick_image(b);
    return normal_image(b);
}

// A device's BVH read back and checked against its bricks: with several devices the trees must
// agree too, and be valid.
struct TreeCheck {
    std::string digest;
    std::string problems;  // "" when every geometry's tree is valid
};

// The reference tracer's figures (its image goes to the pictures, not the report).
struct ReferenceFigures {
    double device_ms = 0.0;
    std::uint64_t march_steps = 0, hit_pixels = 0, unconverged_pixels = 0, fallback_points = 0, overflow_points = 0;
};

// A brick render: the run's figures and what was checked.
struct BrickRender {
    pipeline::RenderFigures figures;
    std::optional<TreeCheck> tree;                       // several devices
    std::optional<reference::AccuracyMetrics> accuracy;  // --compare
    std::optional<render::SeamMismatches> seams;         // --compare of an adaptive build
};

// One device's part of the render report: its run of the job (whole, replicate) or its launches and
// shares of the job (split).
struct DeviceRenderReport {
    ocl::DeviceInfo device;
    pipeline::LaneSettings settings;              // with the tuning applied
    std::optional<BrickRender> bricks;            // whole, replicate; not with --reference
    std::optional<pipeline::LaneFigures> lane;    // split
    std::optional<ReferenceFigures> reference;    // the lanes that ran the reference tracer
    std::string digest;                           // of the image (hit and aux buffers)
    std::string difference;                       // from the first device; "" when bit-identical
};

// The whole command's report.
struct RenderReport {
    std::string file, scene;
    double time = 0.0;
    std::size_t objects = 0, geometries = 0;
    construct::BuildSettings settings;  // as given (each device applies its tuning)
    int width = 0, height = 0;
    std::string mode, method, normals;
    bool reference = false;
    int repeat = 1, warmup = 0;
    std::optional<std::pair<int, int>> shade_rays;  // shaded mode: shadow and ambient occlusion rays per pixel
    std::optional<BrickRender> job;                 // the job's render (not with --reference)
    std::string digest;                             // of the job's image
    std::size_t home = 0;                           // the device that holds the job's bricks
    nlohmann::json placement;
    std::string placement_text;
    std::vector<DeviceRenderReport> devices;
    bool devices_agree = true;
    std::string image;
    std::optional<std::pair<std::string, std::string>> comparison_images;  // --compare: reference, difference
    std::optional<std::string> json_path;
};

ReferenceFigures reference_figures(const reference::ReferenceResult& r) {
    return {r.device_ms, r.march_steps, r.hit_pixels, r.unconverged_pixels, r.fallback_points, r.overflow_points};
}

nlohmann::json to_json(const ReferenceFigures& r) {
    return {{"device_ms", r.device_ms},
            {"march_steps", r.march_steps},
            {"hit_pixels", r.hit_pixels},
            {"unconverged_pixels", r.unconverged_pixels},
            {"fallback_points", r.fallback_points},
            {"overflow_points", r.overflow_points}};
}

std::string accuracy_text(const reference::AccuracyMetrics& a) {
    return fmt::format("  accuracy vs reference: hit mismatch {:.4f}%, depth error mean {:.4f} p99 {:.4f} max "
                       "{:.3f} voxels, normal error mean {:.3f} p99 {:.3f} deg, PSNR {:.2f} dB{}\n",
                       100.0 * a.mismatch_fraction, a.depth_error_mean, a.depth_error_p99, a.depth_error_max,
                       a.normal_error_mean_deg, a.normal_error_p99_deg, a.psnr_db,
                       a.reference_unconverged
                           ? fmt::format(" ({} reference pixels unconverged)", a.reference_unconverged)
                           : "");
}

nlohmann::json to_json(const BrickRender& b) {
    nlohmann::json j = pipeline::to_json(b.figures);
    if (b.tree) {
        j["bvh_digest"] = b.tree->digest;
        j["bvh_valid"] = b.tree->problems.empty();
    }
    if (b.accuracy) j["accuracy"] = reference::to_json(*b.accuracy);
    if (b.seams) j["accuracy"]["seams"] = render::to_json(*b.seams);
    return j;
}

std::string to_text(const BrickRender& b, bool kernel_table) {
    std::string s = pipeline::to_text(b.figures, kernel_table);
    if (b.tree && !b.tree->problems.empty()) s += "  BVH INVALID: " + b.tree->problems + "\n";
    if (b.accuracy) s += accuracy_text(*b.accuracy);
    if (b.seams)
        s += fmt::format("  hit/miss mismatches within a voxel of a seam between leaf sizes: {} (elsewhere {}; "
                         "{} leaves on seams)\n",
                         b.seams->at_seams, b.seams->elsewhere, b.seams->seam_leaves);
    return s;
}

nlohmann::json to_json(const DeviceRenderReport& d) {
    nlohmann::json j = {{"stages", nlohmann::json::array()}};
    if (d.bricks) j.update(to_json(*d.bricks));
    if (d.lane) j.update(pipeline::to_json(*d.lane));
    j.update({{"device", d.device.to_json()}, {"digest", d.digest}});
    if (d.bricks || d.lane) {
        j["tuning"] = d.settings.tuning;
        j["settings"] = settings_json(d.settings.build);
    }
    if (d.reference) {
        j["stages"].push_back({{"name", "reference"}, {"device_ms", d.reference->device_ms}});
        j["reference"] = to_json(*d.reference);
    }
    return j;
}

std::string to_text(const DeviceRenderReport& d, bool kernel_table) {
    std::string s = fmt::format("device {} [{}]\n", d.device.index, d.device.name);
    if (d.bricks || d.lane) s += "  " + d.settings.tuning_text + "\n";
    if (d.bricks) s += to_text(*d.bricks, kernel_table);
    if (d.lane) s += pipeline::to_text(*d.lane, kernel_table);
    if (d.reference)
        s += fmt::format("  reference tracer {:.3f} ms ({} hits, {} unconverged)\n", d.reference->device_ms,
                         d.reference->hit_pixels, d.reference->unconverged_pixels);
    return s;
}

nlohmann::json to_json(const RenderReport& r) {
    nlohmann::json devices = nlohmann::json::array();
    for (const DeviceRenderReport& d : r.devices) devices.push_back(to_json(d));
    const nlohmann::json& first = devices.at(0);
    nlohmann::json settings = first.value("settings", settings_json(r.settings));
    settings.update({{"width", r.width}, {"height", r.height}, {"mode", r.mode}, {"method", r.method},
                     {"normals", r.normals}, {"reference", r.reference}, {"repeat", r.repeat}, {"warmup", r.warmup}});
    if (r.shade_rays) settings.update({{"shadow_rays", r.shade_rays->first}, {"ao_rays", r.shade_rays->second}});
    nlohmann::json images = {{"image", r.image}};
    if (r.comparison_images) {
        images["reference"] = r.comparison_images->first;
        images["difference"] = r.comparison_images->second;
    }
    nlohmann::json report = {
        {"command", "render"},
        {"scene", {{"file", r.file}, {"name", r.scene}, {"time", r.time}, {"objects", r.objects},
                   {"geometries", r.geometries}}},
        {"settings", settings},
        {"images", images},
        {"placement", r.placement},
        {"devices", devices},
        {"devices_agree", r.devices_agree},
        {"digest", r.digest}};
    if (r.job) {
        const nlohmann::json job = to_json(*r.job);
        for (const char* key : {"stages", "rays_per_second", "bricks", "memory", "accuracy", "wall_ms", "wall_breakdown_ms",
                                "total_ms", "captures"})
            if (job.contains(key)) report[key] = job[key];
    }
    if (!report.contains("stages")) report["stages"] = nlohmann::json::array();
    if (const auto& reference = r.devices.at(r.home).reference)
        report["stages"].push_back({{"name", "reference"}, {"device_ms", reference->device_ms}});
    if (first.contains("tuning")) report["tuning"] = first["tuning"];
    return report;
}

std::string to_text(const RenderReport& r, bool kernel_table) {
    const construct::BuildSettings& s = r.settings;
    std::string text = fmt::format("render {} ({}), t = {} s: {}x{}, mode {}, ", r.scene, r.file, r.time, r.width,
                                   r.height, r.mode);
    text += r.reference ? "reference tracer (analytic edits)\n"
                        : fmt::format("method {}, normals {}; bricks {} {}, {}^3 samples, culling {}\n", r.method,
                                      r.normals, s.leaf_size, construct::to_string(s.format), s.samples,
                                      s.cull ? "on" : "off");
    if (!r.placement_text.empty()) {
        text += fmt::format("split over {} devices:\n", r.devices.size()) + r.placement_text;
        if (r.job) text += to_text(*r.job, false);
    }
    for (const DeviceRenderReport& d : r.devices) {
        text += to_text(d, kernel_table);
        if (!d.difference.empty())
            text += fmt::format("  differs from device {}: {}\n", r.devices.front().device.index, d.difference);
    }
    if (r.devices.size() > 1 && r.placement_text.empty())
        text += fmt::format("devices agree bit for bit: {}\n", r.devices_agree ? "yes" : "NO");
    text += fmt::format("image: {}\n", r.image);
    if (r.comparison_images)
        text += fmt::format("reference image: {}, difference image: {}\n", r.comparison_images->first,
                            r.comparison_images->second);
    if (r.json_path) text += fmt::format("report: {}\n", *r.json_path);
    return text;
}

TreeCheck check_trees(const render::SceneBricks& bricks) {
    TreeCheck c;
    const std::vector<SdfBvhNode> nodes = bricks.bvh.nodes->read();
    c.digest = Fnv1a64().add_values(std::span<const SdfBvhNode>(nodes)).hex();
    for (std::size_t g = 0; g < bricks.builds.size(); ++g) {
        const std::vector<SdfBounds> boxes = bricks.builds[g].aabbs->read();
        const std::string p = bvh::check_tree(nodes, bricks.bvh.roots[g], boxes);
        if (!p.empty()) c.problems += fmt::format("geometry {}: {}; ", bricks.builds[g].name, p);
    }
    return c;
}

// "" when the buffers are bit-identical; else how many pixels differ and the first of them.
std::string difference_text(const RenderBuffer& a, const RenderBuffer& b) {
    std::size_t hits = 0, aux = 0, first = a.pixels();
    for (std::size_t i = 0; i < a.pixels(); ++i) {
        const bool h = std::memcmp(&a.hit[i], &b.hit[i], sizeof(cl_float4)) != 0;
        const bool x = std::memcmp(&a.aux[i], &b.aux[i], sizeof(cl_uint2)) != 0;
        hits += h;
        aux += x;
        if ((h || x) && first == a.pixels()) first = i;
    }
    if (first == a.pixels()) return "";
    const auto px = [](const RenderBuffer& r, std::size_t i) {
        return fmt::format("({:.9g} {:.9g} {:.9g} depth {:.9g}, brick {}, counters {:#x})", r.hit[i].s[0], r.hit[i].s[1],
                           r.hit[i].s[2], r.hit[i].s[3], r.aux[i].s[0], r.aux[i].s[1]);
    };
    return fmt::format("{} pixels differ in normal or depth, {} in brick or counters; first at ({}, {}): {} vs {}", hits,
                       aux, first % a.width, first / a.width, px(a, first), px(b, first));
}

std::filesystem::path with_suffix(const std::filesystem::path& p, const std::string& suffix) {
    return p.parent_path() / (p.stem().string() + suffix + p.extension().string());
}

// The report's scene and setup, before any device ran.
RenderReport report_setup(const RenderOptions& o, const Scene& scene, double time,
                          const construct::BuildSettings& settings) {
    RenderReport r;
    r.file = o.file;
    r.scene = scene.name;
    r.time = time;
    r.objects = scene.objects.size();
    r.geometries = scene.geometries.size();
    r.settings = settings;
    r.width = o.trace.width;
    r.height = o.trace.height;
    r.mode = o.mode;
    r.method = o.method;
    r.normals = o.normals;
    r.reference = o.reference;
    r.repeat = o.measure.repeat;
    r.warmup = o.measure.warmups();
    if (o.trace.shade) r.shade_rays = {o.trace.shadow_rays, o.trace.ao_rays};
    return r;
}

// The job's image and the reference's, for the pictures.
struct Images {
    RenderBuffer buffer;
    Image shaded;
    std::optional<RenderBuffer> reference;
};

// A run's render: its figures, the BVH check (several devices), and with --compare its accuracy
// against the reference image (and an adaptive build's seams).
BrickRender brick_render(pipeline::RenderFigures figures, const pipeline::Run& run, const Scene& scene,
                         const RenderOptions& o, const RenderBuffer* reference, bool check_tree) {
    BrickRender b{std::move(figures), {}, {}, {}};
    if (check_tree) b.tree = check_trees(run.bricks);
    if (o.compare && reference) {
        b.accuracy = reference::compare(run.trace->buffer, *reference, b.figures.voxel_world);
        if (run.bricks.settings.adaptive())
            b.seams = render::count_seam_mismatches(scene, run.bricks, run.trace->buffer, *reference);
    }
    return b;
}

// The report's job and devices, and the images of the job, from an execution.
Images add_execution(RenderReport& report, pipeline::Execution& e, const Scene& scene, const RenderOptions& o) {
    Images images;
    const std::optional<reference::ReferenceResult>& ref = e.home_lane().reference;
    const bool several = e.lanes.size() > 1 && !e.split;
    report.placement = pipeline::placement_json(e);
    report.placement_text = pipeline::placement_text(e);
    report.home = e.home;
    if (!o.reference) {
        report.job = brick_render(pipeline::render_figures(e), e.job(), scene, o, ref ? &ref->image : nullptr, several);
        report.digest = e.job().trace_digest;
    }
    for (std::size_t i = 0; i < e.lanes.size(); ++i) {
        pipeline::LaneRun& l = e.lanes[i];
        DeviceRenderReport d{l.device, l.settings, {}, {}, {}, {}, {}};
        if (l.reference) d.reference = reference_figures(*l.reference);
        if (o.reference) {
            if (l.reference) d.digest = pipeline::buffer_digest(l.reference->image);
        } else if (e.split) {
            d.lane = pipeline::lane_figures(e, i);
            d.digest = report.digest;
        } else {
            const pipeline::RunSpec spec{pipeline::Work::trace, l.settings.build, l.settings.trace, e.warmup};
            d.bricks = i == e.home ? *report.job
                                   : brick_render(pipeline::render_figures(l.run, spec, l.device), l.run, scene, o,
                                                  l.reference ? &l.reference->image : nullptr, several);
            d.digest = l.run.trace_digest;
        }
        // A lane with an image of its own (replicate) is compared with the job's.
        const RenderBuffer* own = o.reference ? (l.reference ? &l.reference->image : nullptr)
                                              : e.split ? nullptr : &l.run.trace->buffer;
        if (own && i != e.home) d.difference = difference_text(o.reference ? ref->image : e.job().trace->buffer, *own);
        report.devices.push_back(std::move(d));
    }
    if (o.reference) {
        report.digest = report.devices.at(e.home).digest;
        images.buffer = ref->image;
    } else {
        images.buffer = std::move(e.job().trace->buffer);
        images.shaded = std::move(e.job().trace->colour);
    }
    if (ref) images.reference = ref->image;
    return images;
}

// Bit-identical images and, where checked, identical trees on every device.
bool devices_agree(const RenderReport& r) {
    const auto tree_digest = [](const DeviceRenderReport& d) {
        return d.bricks && d.bricks->tree ? d.bricks->tree->digest : std::string();
    };
    return std::all_of(r.devices.begin(), r.devices.end(), [&](const DeviceRenderReport& d) {
        return d.difference.empty() && tree_digest(d) == tree_digest(r.devices.front());
    });
}

// The picture of the job's render (and with --compare the reference and difference pictures) as
// outputs; their paths recorded in the report.
std::vector<Output> picture_outputs(const RenderOptions& o, const Images& images, double voxel_world,
                                    const std::filesystem::path& out, RenderReport& report) {
    std::vector<Output> outputs{image_output(picture(o.mode, images.buffer, images.shaded, out), out)};
    report.image = out.string();
    if (!o.compare) return outputs;
    const auto ref_path = with_suffix(out, "-reference");
    const auto diff_path = with_suffix(out, "-difference");
    outputs.push_back(image_output(picture(o.mode == "depth" ? "depth" : "normals", *images.reference, {}, ref_path), ref_path));
    outputs.push_back(image_output(reference::difference_image(images.buffer, *images.reference, voxel_world), diff_path));
    report.comparison_images = {ref_path.string(), diff_path.string()};
    return outputs;
}

void run_render(RenderOptions o, const GlobalOptions& global) {
    apply_global_options(global, true);
    const construct::BuildSettings settings = o.flags.resolve();
    if (std::find(std::begin(kModes), std::end(kModes), o.mode) == std::end(kModes))
        throw InputError(fmt::format("--mode must be normals, depth, shaded, steps or bricks, got \"{}\"", o.mode));
    const auto method = render::method_from_string(o.method);
    if (!method) throw InputError(fmt::format("--method must be {}, got \"{}\"", render::method_names(), o.method));
    const auto normals = render::normals_from_string(o.normals);
    if (!normals) throw InputError(fmt::format("--normals must be central, tetra or continuous, got \"{}\"", o.normals));
    if (o.reference && o.mode != "normals" && o.mode != "depth")
        throw InputError("--reference renders the normals and depth modes only");
    if (o.reference && o.compare) throw InputError("--reference and --compare exclude each other");
    o.trace.method = *method;
    o.trace.normals = *normals;
    o.trace.shade = o.mode == "shaded";
    validate_image_size(o.trace.width, o.trace.height);

    const Scene file_scene = load_scene(o.file);
    const double t = o.time.value_or(file_scene.time);
    const Scene scene = scene_at(file_scene, t);
    const std::filesystem::path out = o.out.value_or(fmt::format("{}-{}.{}", scene.name.empty() ? "scene" : scene.name,
                                                                 o.mode, image_io_has_oiio() ? "png" : "ppm"));
    std::vector<std::filesystem::path> paths{out};
    if (o.compare) {
        paths.push_back(with_suffix(out, "-reference"));
        paths.push_back(with_suffix(out, "-difference"));
    }
    if (o.json) paths.push_back(*o.json);
    check_output_paths(paths);
    const std::unique_ptr<RunDevices> devices = open_run_devices(global);
    const TuningChoice tuning = open_tuning(global);
    tune::Given given = o.flags.given();
    given.trace_group = o.trace_group_given;
    pipeline::Job job;
    job.work = pipeline::Work::trace;
    job.bricks = !o.reference;
    job.brick_digests = false;
    job.reference = o.reference || o.compare;
    job.settings = tune::settings_for(settings, o.trace, tuning.get(), given);
    job.warmup = o.measure.warmups();
    job.repeat = o.measure.repeat;
    job.rates = devices->rates ? &*devices->rates : nullptr;
    pipeline::Execution e = devices->executor.run(scene, job, devices->placement);

    RenderReport report = report_setup(o, scene, t, settings);
    const Images images = add_execution(report, e, scene, o);
    report.devices_agree = devices_agree(report);
    std::vector<Output> outputs =
        picture_outputs(o, images, report.job ? report.job->figures.voxel_world : 0.0, out, report);
    if (o.json) {
        outputs.push_back(text_output(*o.json, format_json(to_json(report))));
        report.json_path = *o.json;
    }
    write_all(outputs);
    std::fputs(to_text(report, o.measure.kernel_stats).c_str(), stdout);
}

}  // namespace

void add_render_command(CLI::App& app, const GlobalOptions& global) {
    auto o = std::make_shared<RenderOptions>();
    auto* cmd = app.add_subcommand("render", "Build a scene's bricks and BVH, ray trace them from the scene's camera "
                                             "and write the picture; --compare measures it against the reference");
    cmd->add_option("file", o->file, "scene file (JSON)")->required();
    cmd->add_option("--time", o->time, "animation time in seconds (default: the scene's)")->check(finite_number());
    o->flags.add_to(cmd);
    cmd->add_option("--width", o->trace.width, "image width (1..3840)")->capture_default_str();
    cmd->add_option("--height", o->trace.height, "image height (1..2160)")->capture_default_str();
    cmd->add_option("--mode", o->mode, "normals, depth, shaded, steps (heat map) or bricks (brick ids)")->capture_default_str();
    cmd->add_option("--method", o->method, "in-brick search: sphere (sphere tracing), analytic (trilinear cell roots) or hybrid "
                                          "(sphere steps far from the surface, cell roots near it)")->capture_default_str();
    cmd->add_option("--normals", o->normals, "central, tetra or continuous")->capture_default_str();
    cmd->add_option("--out", o->out, "picture file (default SCENE-MODE.png; .exr keeps raw depth in depth mode)");
    cmd->add_flag("--reference", o->reference, "render with the reference tracer (analytic edits) instead of bricks");
    cmd->add_flag("--compare", o->compare, "also render the reference and report accuracy; writes -reference and "
                                           "-difference images beside --out");
    o->measure.add_to(cmd, "build, BVH and trace");
    auto* gx = cmd->add_option("--group-x", o->trace.group_x, "trace work-group width (default: tuned for the device, else 16)");
    auto* gy = cmd->add_option("--group-y", o->trace.group_y, "trace work-group height (default: tuned for the device, else 8)");
    add_setting_flags(cmd, {{"width", "--width"}, {"height", "--height"}, {"group_x", "--group-x"}, {"group_y", "--group-y"}});

    cmd->add_option("--shadow-rays", o->trace.shadow_rays, "shaded mode: shadow rays per pixel")->check(CLI::Range(0, 64))->capture_default_str();
    cmd->add_option("--ao-rays", o->trace.ao_rays, "shaded mode: ambient occlusion rays per pixel")->check(CLI::Range(0, 64))->capture_default_str();
    cmd->add_option("--json", o->json, "write a JSON report here");
    cmd->callback([o, gx, gy, &global] {
        o->trace_group_given = gx->count() > 0 || gy->count() > 0;
        run_render(*o, global);
    });
}

}  // namespace sdfbrick::cli
