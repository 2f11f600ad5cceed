// `sdfbrick stability`: the stability atlas (docs/stability.md). Every case x in-brick method x normal
// rule x storage format x uniform/adaptive build, measured against the reference tracer on every
// selected device; a JSON report, a text table, and with --pictures each case's pictures.
#include <unistd.h>

#include <array>
#include <cstdio>
#include <memory>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "cli/commands.h"
#include "core/errors.h"
#include "core/files.h"
#include "scene/scene_json.h"
#include "sweep/stability.h"

namespace sdfbrick::cli {

namespace {

struct StabilityOptions {
    std::vector<std::string> cases, methods, normals, formats, builds;
    double brick_size = 0.125;
    sweep::StabilitySpec spec;
    std::optional<std::string> json;
};

// Each name through from_string; an unknown one is refused naming the flag and the choices.
template <class T, class From, std::size_t N>
std::vector<T> parse_names(const std::vector<std::string>& names, const char* flag, From from, const std::array<T, N>& all) {
    std::vector<std::string> known;
    for (const T v : all) known.emplace_back(to_string(v));
    std::vector<T> out;
    for (const std::string& n : names) {
        const auto v = from(n);
        if (!v) throw InputError(fmt::format("{} takes {}, got \"{}\"", flag, fmt::join(known, ", "), n));
        out.push_back(*v);
    }
    return out;
}

sweep::StabilitySpec make_spec(const StabilityOptions& o) {
    sweep::StabilitySpec s = o.spec;
    for (const std::string& c : o.cases) s.cases.push_back(sweep::parse_case(c, o.brick_size));
    s.methods = parse_names(o.methods, "--methods", render::method_from_string, render::kMethods);
    s.normals = parse_names(o.normals, "--normals", render::normals_from_string, render::kNormalMethods);
    for (const std::string& f : o.formats) {
        const auto v = construct::format_from_string(f);
        if (!v) throw InputError(fmt::format("--formats takes int8, int16, float, got \"{}\"", f));
        s.formats.push_back(*v);
    }
    for (const std::string& b : o.builds) {
        if (b != "uniform" && b != "adaptive") throw InputError(fmt::format("--builds takes uniform, adaptive, got \"{}\"", b));
        s.adaptive.push_back(b == "adaptive");
    }
    if (!(s.tolerance_voxels > 0.0)) throw InputError("--tolerance-voxels must be > 0");
    return s;
}

void run_stability_command(const StabilityOptions& o, const GlobalOptions& global) {
    apply_global_options(global);
    sweep::StabilitySpec spec = make_spec(o);
    if (o.json) check_output_path(*o.json);
    if (o.spec.pictures) check_output_folder(*o.spec.pictures);
    ocl::DeviceSet devices = ocl::DeviceSet::open(global.device);
    const TuningChoice tuning = open_tuning(global);
    spec.tuning = tuning.get();
    const bool terminal = isatty(STDERR_FILENO) != 0;
    const auto progress = [terminal](const sweep::StabilityProgress& p) {
        if (!terminal) return;
        std::string line = fmt::format("\r[stability] {}/{} cells, elapsed {}", p.done, p.total, clock_text(p.elapsed_s));
        if (!p.current.empty()) line += fmt::format(", ETA {}: {}", p.done > 0 ? clock_text(p.eta_s) : "?", p.current);
        std::fprintf(stderr, "%-150.150s%s", line.c_str(), p.current.empty() ? "\n" : "");
        std::fflush(stderr);
    };
    const sweep::StabilityReport report = sweep::run_stability(spec, devices, progress);
    std::vector<Output> json;
    if (o.json) json.push_back(text_output(*o.json, format_json(sweep::to_json(report))));
    sweep::write_stability_outputs(report, spec, std::move(json));
    std::fputs(sweep::to_text(report).c_str(), stdout);
    if (o.json) std::printf("report: %s\n", o.json->c_str());
}

}  // namespace

void add_stability_command(CLI::App& app, const GlobalOptions& global) {
    auto o = std::make_shared<StabilityOptions>();
    auto* cmd = app.add_subcommand("stability", "The stability atlas: hard cases x methods x normal rules x formats x "
                                                "uniform/adaptive against the reference tracer (docs/stability.md)");
    cmd->add_option("cases", o->cases, "scene files, each FILE or FILE@BRICK_SIZE (e.g. scenes/stability/*.json)")->required();
    cmd->add_option("--brick-size", o->brick_size, "finest brick size of cases without @SIZE")->check(finite_number())->capture_default_str();
    cmd->add_option("--methods", o->methods, "in-brick methods (default: all)")->delimiter(',');
    cmd->add_option("--normals", o->normals, "normal rules (default: all)")->delimiter(',');
    cmd->add_option("--formats", o->formats, "int8, int16, float (default: all)")->delimiter(',');
    cmd->add_option("--builds", o->builds, "uniform, adaptive (default: both)")->delimiter(',');
    cmd->add_option("--tolerance-voxels", o->spec.tolerance_voxels, "adaptive builds' tolerance in finest voxels")->check(finite_number())->capture_default_str();
    cmd->add_option("--width", o->spec.width, "image width")->capture_default_str();
    cmd->add_option("--height", o->spec.height, "image height")->capture_default_str();
    cmd->add_option("--pictures", o->spec.pictures, "write each case's reference, render and difference pictures here");
    cmd->add_option("--json", o->json, "write the JSON report here");
    add_setting_flags(cmd, {{"leaf_size", "--brick-size"}, {"width", "--width"}, {"height", "--height"}});
    cmd->callback([o, &global] { run_stability_command(*o, global); });
}

}  // namespace sdfbrick::cli
