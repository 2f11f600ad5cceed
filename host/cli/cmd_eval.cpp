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

// One device's part of the eval report.
struct DeviceEvalReport {
    ocl::DeviceInfo device;
    int width = 0, height = 0;  // the slice's pixels
    double offset = 0.0;        // the slice's position along its axis
    double device_ms = 0.0, queue_ms = 0.0;
    std::size_t points = 0;
    std::uint64_t edit_evaluations = 0;
    ocl::BuildRecord program;
    reference::ReferenceCheck check;  // samples 0: not compared
    std::string digest;

    double points_per_second() const { return static_cast<double>(points) / (device_ms * 1e-3); }
    double edit_evaluations_per_second() const { return static_cast<double>(edit_evaluations) / (device_ms * 1e-3); }
};

// The whole command's report: the scene, the slice, every device and the field on the first
// device's slice.
struct EvalReport {
    std::string file, scene;
    double time = 0.0;
    std::size_t objects = 0, edits = 0;
    std::string axis;
    double offset = 0.0, pixel_size = 0.0;
    int width = 0, height = 0;
    double field_min = 0.0, field_max = 0.0, inside_fraction = 0.0;
    std::vector<DeviceEvalReport> devices;
    bool devices_agree = true;
    std::string image;
    std::optional<std::string> json_path;
};

nlohmann::json to_json(const DeviceEvalReport& d) {
    return {{"device", d.device.to_json()},
            {"program", {{"origin", to_string(d.program.origin)}, {"build_ms", d.program.build_ms},
                         {"options", d.program.options},
                         {"correctly_rounded_divide_sqrt", d.program.correctly_rounded_divide_sqrt}}},
            {"device_ms", d.device_ms},
            {"queue_ms", d.queue_ms},
            {"points", d.points},
            {"edit_evaluations", d.edit_evaluations},
            {"points_per_second", d.points_per_second()},
            {"edit_evaluations_per_second", d.edit_evaluations_per_second()},
            {"accuracy", {{"reference", "host double precision"},
                          {"samples", d.check.samples},
                          {"max_abs_error", d.check.max_abs_error},
                          {"mean_abs_error", d.check.mean_abs_error},
                          {"sign_mismatches", d.check.sign_mismatches}}},
            {"digest", d.digest}};
}

std::string to_text(const DeviceEvalReport& d, const std::string& axis) {
    std::string s = fmt::format(
        "device {} [{}]: {}x{} slice ({} axis at {:.4f}), kernel {:.3f} ms (queue {:.3f} ms), "
        "{:.3g} points/s, {:.3g} edit evaluations/s; program {} ({:.0f} ms{})\n",
        d.device.index, d.device.name, d.width, d.height, axis, d.offset, d.device_ms, d.queue_ms, d.points_per_second(),
        d.edit_evaluations_per_second(), to_string(d.program.origin), d.program.build_ms,
        d.program.correctly_rounded_divide_sqrt ? ", correctly rounded div/sqrt" : ", div/sqrt NOT correctly rounded");
    if (d.check.samples == 0)
        return s + fmt::format("  not compared with the host reference (--check 0); digest {}\n", d.digest);
    return s + fmt::format("  vs host reference (double) on {} points: max |error| {:.3g}, mean {:.3g}, "
                           "inside/outside disagreements {}; digest {}\n",
                           d.check.samples, d.check.max_abs_error, d.check.mean_abs_error, d.check.sign_mismatches,
                           d.digest);
}

nlohmann::json to_json(const EvalReport& r) {
    nlohmann::json devices = nlohmann::json::array();
    for (const DeviceEvalReport& d : r.devices) devices.push_back(to_json(d));
    return {{"command", "eval"},
            {"scene", {{"file", r.file}, {"name", r.scene}, {"time", r.time}, {"objects", r.objects}, {"edits", r.edits}}},
            {"slice", {{"axis", r.axis}, {"offset", r.offset}, {"width", r.width}, {"height", r.height},
                       {"pixel_size", r.pixel_size}}},
            {"field", {{"min", r.field_min}, {"max", r.field_max}, {"inside_fraction", r.inside_fraction}}},
            {"devices", devices},
            {"devices_agree", r.devices_agree},
            {"image", r.image}};
}

std::string to_text(const EvalReport& r) {
    std::string s = fmt::format("scene {} ({}), t = {} s, {} objects, {} edits\n", r.scene, r.file, r.time, r.objects,
                                r.edits);
    for (const DeviceEvalReport& d : r.devices) s += to_text(d, r.axis);
    if (r.devices.size() > 1)
        s += fmt::format("devices agree bit for bit: {}\n", r.devices_agree ? "yes" : "NO (digests differ)");
    s += fmt::format("field on the slice: min {:.4f}, max {:.4f}, inside {:.1f}%; picture: {}\n", r.field_min,
                     r.field_max, 100.0 * r.inside_fraction, r.image);
    if (r.json_path) s += fmt::format("report: {}\n", *r.json_path);
    return s;
}

DeviceEvalReport device_report(const ocl::Device& device, const reference::FieldEvaluator& evaluator,
                               const reference::Slice& slice, const reference::ReferenceCheck& check) {
    DeviceEvalReport d;
    d.device = device.info();
    d.width = slice.width;
    d.height = slice.height;
    d.offset = slice.offset;
    d.device_ms = slice.device_ms;
    d.queue_ms = slice.queue_ms;
    d.points = slice.values.size();
    d.edit_evaluations = slice.edit_evaluations;
    d.program = evaluator.build();
    d.check = check;
    d.digest = Fnv1a64().add_values(std::span<const float>(slice.values)).hex();
    return d;
}

// The slice's geometry and the field on it (the first device's slice).
void describe_slice(const reference::Slice& slice, EvalReport& r) {
    r.offset = slice.offset;
    r.width = slice.width;
    r.height = slice.height;
    r.pixel_size = slice.pixel_size;
    const auto [lo, hi] = std::minmax_element(slice.values.begin(), slice.values.end());
    const auto inside = std::count_if(slice.values.begin(), slice.values.end(), [](float v) { return v < 0.0f; });
    r.field_min = *lo;
    r.field_max = *hi;
    r.inside_fraction = static_cast<double>(inside) / static_cast<double>(slice.values.size());
}

void run_eval(const EvalOptions& o, const GlobalOptions& global) {
    apply_global_options(global);
    const Scene file_scene = load_scene_warned(o.file);
    EvalReport report;
    report.file = o.file;
    report.time = o.time.value_or(file_scene.time);
    const Scene scene = scene_at(file_scene, report.time);
    report.scene = scene.name;
    report.objects = scene.objects.size();
    for (const Object& obj : scene.objects) report.edits += scene.geometries[obj.geometry].edits.size();
    report.axis = o.axis;
    reference::SliceSpec spec;
    spec.axis = o.axis == "x" ? 0 : o.axis == "y" ? 1 : 2;
    spec.offset = o.offset;
    spec.resolution = o.size;
    report.image = o.out.value_or(default_image_path(scene));
    std::vector<std::filesystem::path> paths{report.image};
    if (o.json) paths.push_back(*o.json);
    check_output_paths(paths);

    ocl::DeviceSet devices = ocl::DeviceSet::open(global.device);
    std::optional<reference::Slice> first;
    std::optional<reference::ReferenceSamples> samples;
    for (ocl::Device& device : devices) {
        reference::FieldEvaluator evaluator(device);
        reference::Slice slice = reference::evaluate_slice(evaluator, scene, spec);
        if (!samples) samples = reference::reference_samples(slice, scene, o.check);
        report.devices.push_back(device_report(device, evaluator, slice, reference::check_against_reference(slice, *samples)));
        report.devices_agree = report.devices_agree && report.devices.back().digest == report.devices.front().digest;
        if (!first) first = std::move(slice);
    }
    describe_slice(*first, report);
    std::vector<Output> outputs{image_output(reference::slice_image(*first), report.image)};
    if (o.json) {
        outputs.push_back(text_output(*o.json, format_json(to_json(report))));
        report.json_path = *o.json;
    }
    write_all(outputs);
    std::fputs(to_text(report).c_str(), stdout);
}

}  // namespace

void add_eval_command(CLI::App& app, const GlobalOptions& global) {
    auto o = std::make_shared<EvalOptions>();
    auto* cmd = app.add_subcommand(
        "eval",
        "The main job: evaluate a slice of the scene's distance field on each selected device, compare it with "
        "the double-precision host reference, print a summary and write a picture of the slice");
    cmd->add_option("file", o->file, "scene file (JSON)")->required();
    cmd->add_option("--time", o->time, "animation time in seconds (default: the scene's)")->check(finite_number());
    cmd->add_option("--axis", o->axis, "slice perpendicular to this axis")->check(CLI::IsMember({"x", "y", "z"}))->capture_default_str();
    cmd->add_option("--offset", o->offset, "slice position along the axis (default: the centre of the scene's bounds)")->check(finite_number());
    cmd->add_option("--size", o->size, "pixels along the longer side of the slice")->check(CLI::Range(2, 8192))->capture_default_str();
    cmd->add_option("-o,--out", o->out, "picture to write (.png/.exr with OpenImageIO; .ppm/.pfm always); default NAME-slice.png");
    cmd->add_option("--json", o->json, "write a JSON report here");
    cmd->add_option("--check", o->check, "pixels to compare with the host reference (0 = none)")->capture_default_str();
    cmd->callback([o, &global] { run_eval(*o, global); });
}

}  // namespace sdfbrick::cli
