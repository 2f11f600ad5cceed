#include "pipeline/command_report.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include <fmt/format.h>

#include "bvh/bvh_builder.h"
#include "core/hash.h"
#include "reference/host_tracer.h"
#include "render/pictures.h"

namespace sdfbrick::pipeline {

nlohmann::json settings_json(const construct::BuildSettings& s) {
    return {{"brick_size", s.leaf_size}, {"levels", s.levels}, {"branching", s.branching}, {"samples", s.samples},
            {"format", construct::to_string(s.format)}, {"band_voxels", s.band_voxels}, {"guard", s.guard},
            {"chunk", s.chunk}, {"group", s.eval_group}, {"eval_max_registers", s.eval_registers},
            {"lanes", s.eval_lanes}, {"count_parts", s.count_parts}, {"count_splits", s.count_splits},
            {"count_untested", s.count_untested}, {"cull", s.cull}, {"cull_siblings", s.cull_siblings},
            {"skip_far", s.skip_far}, {"apron_share_edits", s.apron_share_edits}, {"dependencies", s.dependencies},
            {"tolerance", s.tolerance}, {"max_brick_size", s.max_leaf_size}};
}

// ---- build ----

namespace {

nlohmann::json to_json(const DeviceBuildReport& d) {
    nlohmann::json j = d.figures ? pipeline::to_json(*d.figures) : pipeline::to_json(*d.lane);
    j["device"] = d.device.to_json();
    j["settings"] = settings_json(d.settings.build);
    j["tuning"] = d.settings.tuning;
    return j;
}

std::string to_text(const DeviceBuildReport& d, bool kernel_table) {
    return fmt::format("device {} [{}]\n  {}\n", d.device.index, d.device.name, d.settings.tuning_text) +
           (d.figures ? pipeline::to_text(*d.figures, kernel_table) : pipeline::to_text(*d.lane, kernel_table));
}

}  // namespace

nlohmann::json to_json(const BuildCommandReport& r) {
    nlohmann::json devices = nlohmann::json::array();
    for (const DeviceBuildReport& d : r.devices) devices.push_back(to_json(d));
    nlohmann::json j = pipeline::to_json(r.job);
    j.update({{"command", "build"},
              {"scene", {{"file", r.file}, {"name", r.scene}, {"time", r.time}, {"geometries", r.geometries}}},
              {"settings", devices.at(0)["settings"]},
              {"tuning", devices.at(0)["tuning"]},
              {"tuning_db", r.tuning_db ? nlohmann::json(r.tuning_db->string()) : nlohmann::json(nullptr)},
              {"repeat", r.repeat},
              {"warmup", r.warmup},
              {"placement", r.placement},
              {"devices", devices},
              {"devices_agree", r.devices_agree},
              {"edit_lists_agree", r.edit_lists_agree}});
    return j;
}

std::string to_text(const BuildCommandReport& r, bool kernel_table) {
    const construct::BuildSettings& s = r.settings;
    std::string text = fmt::format("build {} ({}), t = {} s: brick size {}, branching {}, {}^3 samples, {}, "
                                   "culling {}{}, guard {}\n",
                                   r.scene, r.file, r.time, s.leaf_size, s.branching, s.samples,
                                   construct::to_string(s.format), s.cull ? "on" : "off",
                                   s.dependencies ? " with dependencies" : "", s.guard);
    if (!r.placement_text.empty())
        text += fmt::format("split over {} devices:\n", r.devices.size()) + pipeline::to_text(r.job, kernel_table) +
                r.placement_text;
    for (const DeviceBuildReport& d : r.devices) text += to_text(d, kernel_table);
    if (r.devices.size() > 1 && r.placement_text.empty())
        text += fmt::format("devices agree bit for bit: bricks and pool {}, edit lists {}\n",
                            r.devices_agree ? "yes" : "NO", r.edit_lists_agree ? "yes" : "NO");
    if (r.json_path) text += fmt::format("report: {}\n", *r.json_path);
    return text;
}

void add_execution(BuildCommandReport& report, const Execution& e, const Scene& scene, bool reference_levels) {
    report.job = build_figures(e);
    if (reference_levels) add_reference_levels(report.job.construction, scene, e.home_lane().settings.build);
    report.placement = placement_json(e);
    report.placement_text = placement_text(e);
    for (std::size_t i = 0; i < e.lanes.size(); ++i) {
        DeviceBuildReport d{e.lanes[i].device, e.lanes[i].settings, {}, {}};
        if (e.split) {
            d.lane = lane_figures(e, i);
        } else {
            d.figures = i == e.home ? report.job : build_figures(e.lanes[i].run, d.device);
            report.devices_agree = report.devices_agree && d.figures->digest == report.job.digest;
            report.edit_lists_agree = report.edit_lists_agree && d.figures->list_digest == report.job.list_digest;
        }
        report.devices.push_back(std::move(d));
    }
}

// ---- render ----

bool is_render_mode(std::string_view mode) {
    return std::find(std::begin(kRenderModes), std::end(kRenderModes), mode) != std::end(kRenderModes);
}

namespace {

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
                       "{:.3f} voxels (p99 {:.4g} max {:.4g} world{}), normal error mean {:.3f} p99 {:.3f} deg, PSNR "
                       "{:.2f} dB{}\n",
                       100.0 * a.mismatch_fraction, a.depth_error_mean, a.depth_error_p99, a.depth_error_max,
                       a.depth_error_p99_world, a.depth_error_max_world,
                       a.surface_error_p99_world ? fmt::format("; between the surfaces p99 {:.4g} max {:.4g}",
                                                               *a.surface_error_p99_world, *a.surface_error_max_world)
                                                 : "",
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

TreeCheck check_trees(const render::SceneBricks& bricks) {
    TreeCheck c;
    const std::vector<SdfBvhWideNode> nodes = bricks.bvh.nodes->read();
    c.digest = Fnv1a64().add_values(std::span<const SdfBvhWideNode>(nodes)).hex();
    for (std::size_t g = 0; g < bricks.builds.size(); ++g) {
        const construct::GeometryBuild& b = bricks.builds[g];
        const std::vector<SdfBounds> boxes = b.aabbs->read();
        const std::vector<std::uint8_t> in_tree = bvh::hit_bricks(b.pool->read(), bricks.settings, b);
        const std::string p = bvh::check_tree(nodes, bricks.bvh.roots[g], boxes, in_tree);
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

// A run's render: its figures, the BVH check (several devices), and with compare its accuracy
// against the reference image (and an adaptive build's seams).
BrickRender brick_render(RenderFigures figures, const Run& run, const Scene& scene, bool compare,
                         const RenderBuffer* reference, bool check_tree) {
    BrickRender b{std::move(figures), {}, {}, {}};
    if (check_tree) b.tree = check_trees(run.bricks);
    if (compare && reference) {
        b.accuracy = reference::compare(run.trace->buffer, *reference, b.figures.voxel_world);
        reference::add_surface_error(*b.accuracy, run.trace->buffer, *reference,
                                     reference::make_host_camera(scene.camera, reference->width, reference->height));
        if (run.bricks.settings.adaptive())
            b.seams = render::count_seam_mismatches(scene, run.bricks, run.trace->buffer, *reference);
    }
    return b;
}

// Bit-identical images and, where checked, identical trees on every device.
bool devices_agree(const RenderCommandReport& r) {
    const auto tree_digest = [](const DeviceRenderReport& d) {
        return d.bricks && d.bricks->tree ? d.bricks->tree->digest : std::string();
    };
    return std::all_of(r.devices.begin(), r.devices.end(), [&](const DeviceRenderReport& d) {
        return d.difference.empty() && tree_digest(d) == tree_digest(r.devices.front());
    });
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

}  // namespace

RenderCommandReport render_report(const RenderRequest& request, const Scene& scene, double time,
                                  const construct::BuildSettings& settings) {
    RenderCommandReport r;
    r.file = request.file;
    r.scene = scene.name;
    r.time = time;
    r.objects = scene.objects.size();
    r.geometries = scene.geometries.size();
    r.settings = settings;
    r.width = request.trace.width;
    r.height = request.trace.height;
    r.mode = request.mode;
    r.method = std::string(render::to_string(request.trace.method));
    r.normals = std::string(render::to_string(request.trace.normals));
    r.reference = request.reference;
    r.repeat = request.repeat;
    r.warmup = request.warmup;
    if (request.trace.shade) r.shade_rays = {request.trace.shadow_rays, request.trace.ao_rays};
    return r;
}

RenderImages add_execution(RenderCommandReport& report, Execution& e, const Scene& scene, const RenderRequest& request) {
    RenderImages images;
    const std::optional<reference::ReferenceResult>& ref = e.home_lane().reference;
    const bool several = e.lanes.size() > 1 && !e.split;
    report.placement = placement_json(e);
    report.placement_text = placement_text(e);
    report.home = e.home;
    if (!request.reference) {
        report.job = brick_render(render_figures(e), e.job(), scene, request.compare, ref ? &ref->image : nullptr, several);
        report.digest = e.job().trace_digest;
    }
    for (std::size_t i = 0; i < e.lanes.size(); ++i) {
        LaneRun& l = e.lanes[i];
        DeviceRenderReport d{l.device, l.settings, {}, {}, {}, {}, {}};
        if (l.reference) d.reference = reference_figures(*l.reference);
        if (request.reference) {
            if (l.reference) d.digest = buffer_digest(l.reference->image);
        } else if (e.split) {
            d.lane = lane_figures(e, i);
            d.digest = report.digest;
        } else {
            const RunSpec spec{Work::trace, l.settings.build, l.settings.trace, e.warmup};
            d.bricks = i == e.home ? *report.job
                                   : brick_render(render_figures(l.run, spec, l.device), l.run, scene, request.compare,
                                                  l.reference ? &l.reference->image : nullptr, several);
            d.digest = l.run.trace_digest;
        }
        // A lane with an image of its own (replicate) is compared with the job's.
        const RenderBuffer* own = request.reference ? (l.reference ? &l.reference->image : nullptr)
                                                    : e.split ? nullptr : &l.run.trace->buffer;
        if (own && i != e.home)
            d.difference = difference_text(request.reference ? ref->image : e.job().trace->buffer, *own);
        report.devices.push_back(std::move(d));
    }
    if (request.reference) {
        report.digest = report.devices.at(e.home).digest;
        images.buffer = ref->image;
    } else {
        images.buffer = std::move(e.job().trace->buffer);
        images.shaded = std::move(e.job().trace->colour);
    }
    if (ref) images.reference = ref->image;
    report.devices_agree = devices_agree(report);
    return images;
}

nlohmann::json to_json(const RenderCommandReport& r) {
    nlohmann::json devices = nlohmann::json::array();
    for (const DeviceRenderReport& d : r.devices) devices.push_back(to_json(d));
    const nlohmann::json& first = devices.at(0);
    nlohmann::json settings = first.value("settings", settings_json(r.settings));
    settings.update({{"width", r.width}, {"height", r.height}, {"mode", r.mode}, {"method", r.method},
                     {"normals", r.normals}, {"reference", r.reference}, {"repeat", r.repeat}, {"warmup", r.warmup}});
    if (r.shade_rays) settings.update({{"shadow_rays", r.shade_rays->first}, {"ao_rays", r.shade_rays->second}});
    nlohmann::json images = {{"image", r.image ? nlohmann::json(*r.image) : nlohmann::json(nullptr)}};
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

std::string to_text(const RenderCommandReport& r, bool kernel_table) {
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
    if (r.image) text += fmt::format("image: {}\n", *r.image);
    if (r.comparison_images)
        text += fmt::format("reference image: {}, difference image: {}\n", r.comparison_images->first,
                            r.comparison_images->second);
    if (r.json_path) text += fmt::format("report: {}\n", *r.json_path);
    return text;
}

Image mode_picture(std::string_view mode, const RenderBuffer& buffer, const Image& shaded, bool raw_depth) {
    if (mode == "depth") return raw_depth ? depth_image(buffer) : depth_view(buffer);
    if (mode == "shaded") return shaded;
    if (mode == "steps") return render::steps_image(buffer);
    if (mode == "bricks") return render::brick_image(buffer);
    return normal_image(buffer);
}

}  // namespace sdfbrick::pipeline
