// `sdfbrick eval`: the main job for now. Loads a scene, evaluates a slice of its field on every
// selected device, checks it against the double-precision host reference, prints a summary and
// writes a picture of the slice (and a JSON report on request).
#include <algorithm>
#include <cstdio>
#include <memory>

#include <fmt/format.h>

#include "cl/kernel_source.h"
#include "cli/commands.h"
#include "core/errors.h"
#include "core/files.h"
#include "core/hash.h"
#include "reference/field_eval.h"
#include "scene/scene_json.h"

namespace sdfbrick::cli {

namespace {

struct EvalOptions {
    std::string file;
    std::optional<double> time;
    std::string axis = "z";
    std::optional<double> offset;
    int size = 512;
    std::optional<std::string> out;
    std::optional<std::string> json;
    std::size_t check = 16384;
};

std::string default_image_path(const Scene& scene) {
    return fmt::format("{}-slice.{}", scene.name.empty() ? "scene" : scene.name, image_io_has_oiio() ? "png" : "ppm");
}

void run_eval(const EvalOptions& o, const GlobalOptions& global) {
    apply_global_options(global);
    const Scene file_scene = load_scene(o.file);
    const double t = o.time.value_or(file_scene.time);
    const Scene scene = scene_at(file_scene, t);
    reference::SliceSpec spec;
    spec.axis = o.axis == "x" ? 0 : o.axis == "y" ? 1 : 2;
    spec.offset = o.offset;
    spec.resolution = o.size;
    const std::string image_path = o.out.value_or(default_image_path(scene));

    std::size_t edits = 0;
    for (const Object& obj : scene.objects) edits += scene.geometries[obj.geometry].edits.size();

    ocl::DeviceSet devices = ocl::DeviceSet::open(global.device);
    nlohmann::json report_devices = nlohmann::json::array();
    std::optional<reference::Slice> first;
    std::string first_digest;
    bool all_agree = true;
    std::optional<reference::ReferenceSamples> reference;
    std::string summary = fmt::format("scene {} ({}), t = {} s, {} objects, {} edits\n", scene.name, o.file, t,
                                      scene.objects.size(), edits);
    for (ocl::Device& device : devices) {
        reference::FieldEvaluator evaluator(device);
        reference::Slice slice = reference::evaluate_slice(evaluator, scene, spec);
        if (!reference) reference = reference::reference_samples(slice, scene, o.check);
        const reference::ReferenceCheck check = reference::check_against_reference(slice, *reference);
        const std::string digest = Fnv1a64().add_values(std::span<const float>(slice.values)).hex();
        const double points = static_cast<double>(slice.values.size());
        const double seconds = slice.device_ms * 1e-3;
        const auto& build = evaluator.build();
        if (!first) {
            first_digest = digest;
        } else {
            all_agree = all_agree && digest == first_digest;
        }
        summary += fmt::format(
            "device {} [{}]: {}x{} slice ({} axis at {:.4f}), kernel {:.3f} ms (queue {:.3f} ms), "
            "{:.3g} points/s, {:.3g} edit evaluations/s; program {} ({:.0f} ms{})\n",
            device.info().index, device.info().name, slice.width, slice.height, o.axis, slice.offset,
            slice.device_ms, slice.queue_ms, points / seconds, static_cast<double>(slice.edit_evaluations) / seconds,
            to_string(build.origin), build.build_ms,
            build.correctly_rounded_divide_sqrt ? ", correctly rounded div/sqrt" : ", div/sqrt NOT correctly rounded");
        if (check.samples == 0)
            summary += fmt::format("  not compared with the host reference (--check 0); digest {}\n", digest);
        else
            summary += fmt::format("  vs host reference (double) on {} points: max |error| {:.3g}, mean {:.3g}, "
                                   "inside/outside disagreements {}; digest {}\n",
                                   check.samples, check.max_abs_error, check.mean_abs_error, check.sign_mismatches, digest);
        report_devices.push_back({{"device", device.info().to_json()},
                                  {"program", {{"origin", to_string(build.origin)}, {"build_ms", build.build_ms},
                                               {"options", build.options},
                                               {"correctly_rounded_divide_sqrt", build.correctly_rounded_divide_sqrt}}},
                                  {"device_ms", slice.device_ms},
                                  {"queue_ms", slice.queue_ms},
                                  {"points", slice.values.size()},
                                  {"edit_evaluations", slice.edit_evaluations},
                                  {"points_per_second", points / seconds},
                                  {"edit_evaluations_per_second", static_cast<double>(slice.edit_evaluations) / seconds},
                                  {"accuracy", {{"reference", "host double precision"},
                                                {"samples", check.samples},
                                                {"max_abs_error", check.max_abs_error},
                                                {"mean_abs_error", check.mean_abs_error},
                                                {"sign_mismatches", check.sign_mismatches}}},
                                  {"digest", digest}});
        if (!first) first = std::move(slice);
    }

    const auto [lo, hi] = std::minmax_element(first->values.begin(), first->values.end());
    const auto inside = std::count_if(first->values.begin(), first->values.end(), [](float v) { return v < 0.0f; });
    if (devices.size() > 1)
        summary += fmt::format("devices agree bit for bit: {}\n", all_agree ? "yes" : "NO (digests differ)");
    write_image(reference::slice_image(*first), image_path);
    summary += fmt::format("field on the slice: min {:.4f}, max {:.4f}, inside {:.1f}%; picture: {}\n", *lo, *hi,
                           100.0 * static_cast<double>(inside) / static_cast<double>(first->values.size()), image_path);

    if (o.json) {
        const nlohmann::json report = {
            {"command", "eval"},
            {"scene", {{"file", o.file}, {"name", scene.name}, {"time", t}, {"objects", scene.objects.size()}, {"edits", edits}}},
            {"slice", {{"axis", o.axis}, {"offset", first->offset}, {"width", first->width}, {"height", first->height},
                       {"pixel_size", first->pixel_size}}},
            {"field", {{"min", *lo}, {"max", *hi}, {"inside_fraction", static_cast<double>(inside) / static_cast<double>(first->values.size())}}},
            {"devices", report_devices},
            {"devices_agree", all_agree},
            {"image", image_path}};
        write_file_atomic(*o.json, format_json(report));
        summary += fmt::format("report: {}\n", *o.json);
    }
    std::fputs(summary.c_str(), stdout);
}

}  // namespace

void add_eval_command(CLI::App& app, const GlobalOptions& global) {
    auto o = std::make_shared<EvalOptions>();
    auto* cmd = app.add_subcommand(
        "eval",
        "The main job: evaluate a slice of the scene's distance field on each selected device, compare it with "
        "the double-precision host reference, print a summary and write a picture of the slice");
    cmd->add_option("file", o->file, "scene file (JSON)")->required();
    cmd->add_option("--time", o->time, "animation time in seconds (default: the scene's)");
    cmd->add_option("--axis", o->axis, "slice perpendicular to this axis")->check(CLI::IsMember({"x", "y", "z"}))->capture_default_str();
    cmd->add_option("--offset", o->offset, "slice position along the axis (default: the centre of the scene's bounds)");
    cmd->add_option("--size", o->size, "pixels along the longer side of the slice")->check(CLI::Range(2, 8192))->capture_default_str();
    cmd->add_option("-o,--out", o->out, "picture to write (.png/.exr with OpenImageIO; .ppm/.pfm always); default NAME-slice.png");
    cmd->add_option("--json", o->json, "write a JSON report here");
    cmd->add_option("--check", o->check, "pixels to compare with the host reference (0 = none)")->capture_default_str();
    cmd->callback([o, &global] { run_eval(*o, global); });
}

}  // namespace sdfbrick::cli
