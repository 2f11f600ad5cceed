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
#include "render/brick_tracer.h"
#include "render/pictures.h"
#include "pipeline/run.h"
#include "reference/device_tracer.h"
#include "scene/scene_json.h"

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

// What one device did.
struct DeviceRender {
    RenderBuffer buffer;
    Image shaded;
    std::optional<reference::ReferenceResult> reference;
    std::optional<reference::AccuracyMetrics> accuracy;
    nlohmann::json json;
    std::string digest;
};

DeviceRender render_on(ocl::Device& device, const Scene& scene, const RenderOptions& o,
                       const construct::BuildSettings& base_settings, const tune::TuningDb* tuning_db, bool check_trees,
                       std::string& text) {
    DeviceRender r;
    const SdfCamera camera = make_camera(scene.camera, o.trace.width, o.trace.height);
    const double pixels = static_cast<double>(o.trace.width) * o.trace.height;
    text += fmt::format("device {} [{}]\n", device.info().index, device.info().name);
    r.json = {{"device", device.info().to_json()}};
    nlohmann::json stages = nlohmann::json::array();
    if (!o.reference) {
        construct::BuildSettings settings = base_settings;
        render::TraceSettings trace = o.trace;
        tune::Given given = o.flags.given();
        given.trace_group = o.trace_group_given;
        const tune::Applied tuning = tune::apply_tuning(tuning_db, device.info(), given, settings, &trace);
        text += "  " + tuning.text + "\n";
        r.json["tuning"] = tuning.record;
        pipeline::Runner runner(device);
        pipeline::Run run = runner.run(scene, {pipeline::Work::trace, settings, trace, o.measure.warmups(), o.measure.repeat});
        const render::SceneBricks& bricks = run.bricks;
        r.digest = run.trace_digest;
        r.buffer = std::move(run.trace->buffer);
        r.shaded = std::move(run.trace->colour);
        const double trace_ms = run.trace_ms.median;
        std::map<std::string, std::uint64_t> memory = bricks.bvh.memory;
        for (const auto& b : bricks.builds)
            for (const auto& [k, v] : b.memory) memory[k] += v;
        if (bricks.combined_pool) memory["combined pool"] = bricks.combined_pool->bytes();
        const render::WorkCounts work = render::work_counts(r.buffer);
        stages = measure::to_json(run.stages);
        r.json["settings"] = settings_json(settings);
        r.json["trace_group"] = {trace.group_x, trace.group_y};
        r.json["stages"] = stages;
        r.json["build_ms"] = measure::to_json(run.build_ms);
        r.json["bvh_ms"] = measure::to_json(run.bvh_ms);
        r.json["trace_ms"] = measure::to_json(run.trace_ms);
        r.json["captures"] = {{"warmup", o.measure.warmups()}, {"repeat", o.measure.repeat}, {"identical", run.identical}};
        r.json["bricks"] = bricks.bricks;
        r.json["bvh"] = {{"nodes", bricks.bvh.node_count}, {"tlas_nodes", bricks.bvh.tlas_node_count},
                         {"instances", bricks.bvh.instance_objects.size()}, {"device_ms", bricks.bvh.device_ms}};
        r.json["memory"] = memory;
        r.json["rays_per_second"] = trace_ms > 0 ? pixels / (trace_ms * 1e-3) : 0.0;
        r.json["work_per_pixel"] = {{"node_visits", work.node_visits}, {"brick_steps", work.brick_steps}};
        r.json["digest"] = r.digest;
        r.json["voxel_world"] = bricks.voxel_world;
        const std::vector<measure::KernelRow> kernels = measure::kernel_rows(run.captures, device.info());
        r.json["kernels"] = measure::to_json(kernels);
        text += fmt::format("  build {:.3f} ms ({} bricks), bvh {:.3f} ms ({} nodes), trace {:.3f} ms "
                            "({:.3g} rays/s, {:.1f} node visits and {:.1f} brick steps per ray){}\n",
                            run.build_ms.median, bricks.bricks, run.bvh_ms.median, bricks.bvh.node_count, trace_ms,
                            pixels / (trace_ms * 1e-3), work.node_visits, work.brick_steps,
                            trace.shade ? fmt::format(", shade {:.3f} ms", measure::stage_median(run.stages, measure::Stage::shade)) : "");
        if (o.measure.repeat > 1) text += measure::stage_table_text(run.stages, run.identical);
        if (o.measure.kernel_stats) text += measure::kernel_table_text(kernels);
        if (check_trees) {  // several devices: the trees must agree too (and be valid)
            const std::vector<SdfBvhNode> nodes = bricks.bvh.nodes->read();
            r.json["bvh_digest"] = Fnv1a64().add_values(std::span<const SdfBvhNode>(nodes)).hex();
            std::string problems;
            for (std::size_t g = 0; g < bricks.builds.size(); ++g) {
                const std::vector<SdfBounds> boxes = bricks.builds[g].aabbs->read();
                const std::string p = bvh::check_tree(nodes, bricks.bvh.roots[g], boxes);
                if (!p.empty()) problems += fmt::format("geometry {}: {}; ", bricks.builds[g].name, p);
            }
            r.json["bvh_valid"] = problems.empty();
            if (!problems.empty()) text += "  BVH INVALID: " + problems + "\n";
        }
        if (o.compare) {
            reference::ReferenceTracer ref(device);
            r.reference = ref.render(scene, camera);
            r.accuracy = reference::compare(r.buffer, r.reference->image, bricks.voxel_world);
            const reference::AccuracyMetrics& a = *r.accuracy;
            r.json["accuracy"] = reference::to_json(a);
            text += fmt::format("  accuracy vs reference: hit mismatch {:.4f}%, depth error mean {:.4f} p99 {:.4f} max "
                                "{:.3f} voxels, normal error mean {:.3f} p99 {:.3f} deg, PSNR {:.2f} dB{}\n",
                                100.0 * a.mismatch_fraction, a.depth_error_mean, a.depth_error_p99, a.depth_error_max,
                                a.normal_error_mean_deg, a.normal_error_p99_deg, a.psnr_db,
                                a.reference_unconverged ? fmt::format(" ({} reference pixels unconverged)",
                                                                      a.reference_unconverged)
                                                        : "");
        }
    } else {
        reference::ReferenceTracer ref(device);
        r.reference = ref.render(scene, camera);
        r.buffer = r.reference->image;
        r.digest = pipeline::buffer_digest(r.buffer);
        r.json["digest"] = r.digest;
    }
    if (r.reference) {
        const reference::ReferenceResult& ref = *r.reference;
        stages.push_back({{"name", "reference"}, {"device_ms", ref.device_ms}});
        r.json["stages"] = stages;
        r.json["reference"] = {{"device_ms", ref.device_ms}, {"march_steps", ref.march_steps},
                               {"hit_pixels", ref.hit_pixels}, {"unconverged_pixels", ref.unconverged_pixels},
                               {"fallback_points", ref.fallback_points}, {"overflow_points", ref.overflow_points}};
        text += fmt::format("  reference tracer {:.3f} ms ({} hits, {} unconverged)\n", ref.device_ms, ref.hit_pixels,
                            ref.unconverged_pixels);
    }
    return r;
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

void run_render(RenderOptions o, const GlobalOptions& global) {
    apply_global_options(global);
    const construct::BuildSettings settings = o.flags.resolve();
    if (std::find(std::begin(kModes), std::end(kModes), o.mode) == std::end(kModes))
        throw InputError(fmt::format("--mode must be normals, depth, shaded, steps or bricks, got \"{}\"", o.mode));
    const auto method = render::method_from_string(o.method);
    if (!method) throw InputError(fmt::format("--method must be sphere or analytic, got \"{}\"", o.method));
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
    ocl::DeviceSet devices = ocl::DeviceSet::open(global.device);
    const TuningChoice tuning = open_tuning(global);
    const std::filesystem::path out = o.out.value_or(fmt::format("{}-{}.{}", scene.name.empty() ? "scene" : scene.name,
                                                                 o.mode, image_io_has_oiio() ? "png" : "ppm"));

    std::string text = fmt::format("render {} ({}), t = {} s: {}x{}, mode {}, ", scene.name, o.file, t, o.trace.width,
                                   o.trace.height, o.mode);
    text += o.reference ? "reference tracer (analytic edits)\n"
                        : fmt::format("method {}, normals {}; bricks {} {}, {}^3 samples, culling {}\n", o.method,
                                      o.normals, settings.leaf_size, construct::to_string(settings.format),
                                      settings.samples, settings.cull ? "on" : "off");
    std::vector<DeviceRender> runs;
    nlohmann::json device_reports = nlohmann::json::array();
    bool agree = true;
    for (ocl::Device& device : devices) {
        runs.push_back(render_on(device, scene, o, settings, tuning.get(), devices.size() > 1, text));
        device_reports.push_back(runs.back().json);
        if (runs.size() > 1) {
            const std::string diff = difference_text(runs.front().buffer, runs.back().buffer);
            agree = agree && diff.empty() && runs.back().json.value("bvh_digest", "") == runs.front().json.value("bvh_digest", "");
            if (!diff.empty()) text += fmt::format("  differs from device {}: {}\n", devices[0].info().index, diff);
        }
    }
    if (devices.size() > 1) text += fmt::format("devices agree bit for bit: {}\n", agree ? "yes" : "NO");

    const DeviceRender& first = runs.front();
    write_image(picture(o.mode, first.buffer, first.shaded, out), out);
    text += fmt::format("image: {}\n", out.string());
    nlohmann::json images = {{"image", out.string()}};
    if (o.compare) {
        const auto ref_path = with_suffix(out, "-reference");
        const auto diff_path = with_suffix(out, "-difference");
        write_image(picture(o.mode == "depth" ? "depth" : "normals", first.reference->image, {}, ref_path), ref_path);
        write_image(reference::difference_image(first.buffer, first.reference->image, first.json["voxel_world"]), diff_path);
        images["reference"] = ref_path.string();
        images["difference"] = diff_path.string();
        text += fmt::format("reference image: {}, difference image: {}\n", ref_path.string(), diff_path.string());
    }
    if (o.json) {
        nlohmann::json settings_record = first.json.value("settings", settings_json(settings));
        settings_record.update({{"width", o.trace.width}, {"height", o.trace.height}, {"mode", o.mode},
                                {"method", o.method}, {"normals", o.normals}, {"reference", o.reference},
                                {"repeat", o.measure.repeat}, {"warmup", o.measure.warmups()}});
        if (o.trace.shade) settings_record.update({{"shadow_rays", o.trace.shadow_rays}, {"ao_rays", o.trace.ao_rays}});
        nlohmann::json report = {
            {"command", "render"},
            {"scene", {{"file", o.file}, {"name", scene.name}, {"time", t}, {"objects", scene.objects.size()},
                       {"geometries", scene.geometries.size()}}},
            {"settings", settings_record},
            {"images", images},
            {"devices", device_reports},
            {"devices_agree", agree}};
        for (const char* key : {"stages", "rays_per_second", "bricks", "memory", "accuracy", "digest", "tuning"})
            if (first.json.contains(key)) report[key] = first.json[key];
        write_file_atomic(*o.json, format_json(report));
        text += fmt::format("report: {}\n", *o.json);
    }
    std::fputs(text.c_str(), stdout);
}

}  // namespace

void add_render_command(CLI::App& app, const GlobalOptions& global) {
    auto o = std::make_shared<RenderOptions>();
    auto* cmd = app.add_subcommand("render", "Build a scene's bricks and BVH, ray trace them from the scene's camera "
                                             "and write the picture; --compare measures it against the reference");
    cmd->add_option("file", o->file, "scene file (JSON)")->required();
    cmd->add_option("--time", o->time, "animation time in seconds (default: the scene's)");
    o->flags.add_to(cmd);
    cmd->add_option("--width", o->trace.width, "image width (1..3840)")->capture_default_str();
    cmd->add_option("--height", o->trace.height, "image height (1..2160)")->capture_default_str();
    cmd->add_option("--mode", o->mode, "normals, depth, shaded, steps (heat map) or bricks (brick ids)")->capture_default_str();
    cmd->add_option("--method", o->method, "in-brick search: sphere (sphere tracing) or analytic (trilinear cell roots)")->capture_default_str();
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
