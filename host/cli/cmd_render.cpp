// `sdfbrick render`: builds a scene's bricks and BVH, ray traces them from the scene's camera, writes
// the picture, and with --compare measures the render against the device reference tracer (the
// analytic edit lists, no bricks) with the same camera.
#include <cstdio>
#include <filesystem>
#include <memory>

#include <fmt/format.h>

#include "cli/build_flags.h"
#include "cli/commands.h"
#include "core/errors.h"
#include "core/files.h"
#include "reference/accuracy.h"
#include "render/brick_tracer.h"
#include "pipeline/command_report.h"
#include "scene/scene_json.h"
#include "tune/apply.h"

namespace sdfbrick::cli {

namespace {

struct RenderOptions {
    std::string file;
    std::optional<double> time;
    BuildFlags flags;
    TraceFlags tracing;
    render::TraceSettings trace;  // resolved from tracing
    std::string mode;
    std::optional<std::string> out;
    bool reference = false;
    bool compare = false;
    MeasureFlags measure;
    std::optional<std::string> json;
};

bool float_format(const std::filesystem::path& p) {
    const std::string e = p.extension().string();
    return e == ".exr" || e == ".pfm" || e == ".tif" || e == ".tiff" || e == ".hdr";
}

Image picture(const std::string& mode, const RenderBuffer& b, const Image& shaded,
              const std::filesystem::path& path) {
    return pipeline::mode_picture(mode, b, shaded, float_format(path));
}

std::filesystem::path with_suffix(const std::filesystem::path& p, const std::string& suffix) {
    return p.parent_path() / (p.stem().string() + suffix + p.extension().string());
}

// The picture of the job's render (and with --compare the reference and difference pictures) as
// outputs; their paths recorded in the report.
std::vector<Output> picture_outputs(const RenderOptions& o, const pipeline::RenderImages& images, double voxel_world,
                                    const std::filesystem::path& out, pipeline::RenderCommandReport& report) {
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
    o.trace = o.tracing.resolve();
    o.mode = o.tracing.mode;
    if (o.reference && o.mode != "normals" && o.mode != "depth")
        throw InputError("--reference renders the normals and depth modes only");
    if (o.reference && o.compare) throw InputError("--reference and --compare exclude each other");

    const Scene file_scene = load_scene_warned(o.file);
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
    given.trace_group = o.tracing.group_given();
    given.trace_registers = o.tracing.registers_given();
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

    const pipeline::RenderRequest request{o.file, o.mode, o.trace, o.reference, o.compare, o.measure.repeat,
                                          o.measure.warmups()};
    pipeline::RenderCommandReport report = pipeline::render_report(request, scene, t, settings);
    const pipeline::RenderImages images = pipeline::add_execution(report, e, scene, request);
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
    o->tracing.add_to(cmd);
    cmd->add_option("--out", o->out, "picture file (default SCENE-MODE.png; .exr keeps raw depth in depth mode)");
    cmd->add_flag("--reference", o->reference, "render with the reference tracer (analytic edits) instead of bricks");
    cmd->add_flag("--compare", o->compare, "also render the reference and report accuracy; writes -reference and "
                                           "-difference images beside --out");
    o->measure.add_to(cmd, "build, BVH and trace");
    cmd->add_option("--json", o->json, "write a JSON report here");
    cmd->callback([o, &global] { run_render(*o, global); });
}

}  // namespace sdfbrick::cli
