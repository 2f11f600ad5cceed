#include "cli/build_flags.h"

#include <cmath>

#include <fmt/format.h>

#include "cli/commands.h"
#include "core/errors.h"
#include "pipeline/command_report.h"
#include "scene/to_device.h"

namespace sdfbrick::cli {

void BuildFlags::add_to(CLI::App* cmd) {
    construct::BuildSettings& s = settings;
    brick_size_ = cmd->add_option("--brick-size,--min-brick-size", s.leaf_size,
                                  "side of a leaf brick (geometry units); with --tolerance the finest brick")
                      ->check(finite_number())
                      ->capture_default_str();
    tolerance_ = cmd->add_option("--tolerance", s.tolerance,
                                 "adaptive leaves: a brick is a leaf at the coarsest level whose samples reproduce "
                                 "the field within this distance (geometry units; default: uniform)")
                     ->check(finite_number());
    cmd->add_option("--tolerance-voxels", tolerance_voxels, "--tolerance in voxels of the finest brick")
        ->check(finite_number())
        ->excludes(tolerance_);
    cmd->add_option("--max-brick-size", s.max_leaf_size,
                    "adaptive: the largest leaf brick (default: as large as the format's rounding allows within "
                    "the tolerance; the check decides)")
        ->check(finite_number());
    cmd->add_option("--levels", s.levels, "number of levels (default: the fewest that cover the geometry)");
    cmd->add_option("--branching", s.branching, "children per axis: 4 or 2 (octree)")->capture_default_str();
    cmd->add_option("--samples", s.samples, "samples per brick axis: 8 (one-voxel apron) or 10 (two-voxel apron)")->capture_default_str();
    cmd->add_option("--format", format, "brick storage: int8, int16 (snorm over +-band) or float")->capture_default_str();
    cmd->add_option("--band", s.band_voxels, "stored distance range in voxels (+-)")->capture_default_str();
    cmd->add_option("--guard", s.guard, "saturation C = band + guard * largest blend radius (see docs/construction.md)")->capture_default_str();
    chunk_ = cmd->add_option("--chunk", s.chunk, "edits staged per __local chunk (16..256; default: tuned for the device, else 64)");
    group_ = cmd->add_option("--group", s.eval_group, "work-group size of the leaf evaluation (default: tuned for the device, else 128)");
    registers_ = cmd->add_option("--eval-max-registers", s.eval_registers,
                                 "registers per work-item the leaf evaluation may use, NVIDIA only (default: tuned for "
                                 "the device, else 0: the compiler's choice; changes no bit)")
                     ->check(CLI::Range(0, 255));
    cmd->add_option("--lanes", s.eval_lanes, "samples per SIMD value of the leaf evaluation and the check, and "
                                              "children of the count and the sibling cull: 1, 2, 4, 8 or 16 (default: "
                                              "the native float width on CPU devices, else 1; changes no bit)");
    cmd->add_option("--count-parts", s.count_parts, "work-items per candidate child in the count stage: 1, 2, 4, 8 or 16 "
                                                     "(default 0: several on GPUs at levels with few bricks, else 1; "
                                                     "changes no bit)");
    cmd->add_option("--count-splits", s.count_splits, "work-groups per parent in the count stage, each with a share of "
                                                       "its children: a power of two up to 64 (default 0: as few as hold "
                                                       "--count-parts within the kernel's work-group limit, and on CPUs "
                                                       "as many as the cores at levels with fewer parents; changes no "
                                                       "bit)");
    cmd->add_option("--count-untested", s.count_untested,
                    "the count keeps a parent's children without a test where its list has at least this many "
                    "edits, at coarse levels that hold no leaves (default 0: on GPUs the root's children and lists of "
                    "4096 or more, on CPUs none; changes no leaf)");
    cmd->add_option("--cull-siblings", s.cull_siblings,
                    "the cull stage stages each parent's list once for its new children where the level has at "
                    "least this many parents per compute unit (default 2; 0: never; changes no bit)");
    cmd->add_flag("--no-cull", no_cull, "evaluate every edit everywhere (must give the same bricks and pool)");
    cmd->add_flag("!--no-skip-far", s.skip_far,
                  "the leaf evaluation evaluates sphere and capsule edits at every sample, also where they cannot "
                  "change the field (must give the same pool)");
    cmd->add_option("--apron-share-edits", s.apron_share_edits,
                    "a leaf with at least this many edits copies the apron samples its neighbours evaluate instead of "
                    "evaluating them (default 0: none does; changes no bit)");
    cmd->add_flag("--dependencies", s.dependencies, "add the dependencies of kept smooth edits to every edit list");
    add_setting_flags(cmd, {{"leaf_size", "--brick-size"}, {"tolerance", "--tolerance"},
                            {"max_leaf_size", "--max-brick-size"}, {"levels", "--levels"}, {"branching", "--branching"},
                            {"samples", "--samples"}, {"format", "--format"}, {"band_voxels", "--band"},
                            {"guard", "--guard"}, {"chunk", "--chunk"}, {"eval_group", "--group"},
                            {"eval_registers", "--eval-max-registers"},
                            {"eval_lanes", "--lanes"}, {"count_parts", "--count-parts"},
                            {"count_splits", "--count-splits"}, {"count_untested", "--count-untested"},
                            {"cull_siblings", "--cull-siblings"},
                            {"apron_share_edits", "--apron-share-edits"}});
}

construct::BuildSettings BuildFlags::resolve() const {
    construct::BuildSettings s = settings;
    const auto f = construct::format_from_string(format);
    if (!f) throw InputError(fmt::format("--format must be int8, int16 or float, got \"{}\"", format));
    s.format = *f;
    s.cull = !no_cull;
    if (tolerance_ != nullptr && tolerance_->count() > 0 && !(s.tolerance > 0.0))
        throw SettingError("tolerance", fmt::format("tolerance must be a positive number, got {}", s.tolerance));
    if (tolerance_voxels) {
        if (!(*tolerance_voxels > 0.0) || !std::isfinite(*tolerance_voxels))
            throw SettingError("tolerance", fmt::format("--tolerance-voxels must be a positive number, got {}",
                                                        *tolerance_voxels));
        s.tolerance = *tolerance_voxels * s.voxel();
    }
    const bool size_given = brick_size_ != nullptr && brick_size_->count() > 0;
    if (s.adaptive() && !size_given) s.leaf_size = construct::auto_leaf_size(s.tolerance, s.layout());
    return s;
}

tune::Given BuildFlags::given() const {
    tune::Given g;
    g.chunk = chunk_ != nullptr && chunk_->count() > 0;
    g.group = group_ != nullptr && group_->count() > 0;
    g.eval_registers = registers_ != nullptr && registers_->count() > 0;
    return g;
}

void MeasureFlags::add_to(CLI::App* cmd, const char* what) {
    cmd->add_option("--repeat", repeat, fmt::format("captures: {} this many times (per stage: median, min, max, "
                                                    "coefficient of variation; checks outputs are identical)", what))
        ->check(CLI::Range(1, 1000))->capture_default_str();
    cmd->add_option("--warmup", warmup, "uncaptured runs first (default: 1 when --repeat > 1, else 0)")->check(CLI::Range(0, 100));
    cmd->add_flag("--kernel-stats", kernel_stats, "print a per-kernel table: launches, total ms, share, mean/min/max, "
                                                  "attributes and occupancy proxies");
}

void TraceFlags::add_to(CLI::App* cmd) {
    cmd->add_option("--width", trace.width, "image width (1..3840)")->capture_default_str();
    cmd->add_option("--height", trace.height, "image height (1..2160)")->capture_default_str();
    cmd->add_option("--mode", mode, "normals, depth, shaded, steps (heat map) or bricks (brick ids)")->capture_default_str();
    cmd->add_option("--method", method, "in-brick search: sphere (sphere tracing), analytic (trilinear cell roots) or hybrid "
                                         "(sphere steps far from the surface, cell roots near it)")->capture_default_str();
    cmd->add_option("--normals", normals, "central, tetra or continuous")->capture_default_str();
    group_x_ = cmd->add_option("--group-x", trace.group_x, "trace work-group width (default: tuned for the device, else 16)");
    group_y_ = cmd->add_option("--group-y", trace.group_y, "trace work-group height (default: tuned for the device, else 8)");
    add_setting_flags(cmd, {{"width", "--width"}, {"height", "--height"}, {"group_x", "--group-x"}, {"group_y", "--group-y"}});
    cmd->add_option("--shadow-rays", trace.shadow_rays, "shaded mode: shadow rays per pixel")->check(CLI::Range(0, 64))->capture_default_str();
    cmd->add_option("--ao-rays", trace.ao_rays, "shaded mode: ambient occlusion rays per pixel")->check(CLI::Range(0, 64))->capture_default_str();
    registers_ = cmd->add_option("--max-registers", trace.max_registers, "registers per work-item the trace and shade "
                                 "kernels may use, NVIDIA only (default: tuned for the device, else 0: the compiler's choice)")
                     ->check(CLI::Range(0, 255));
}

render::Method method_flag(const std::string& value) {
    const auto m = render::method_from_string(value);
    if (!m) throw InputError(fmt::format("--method must be {}, got \"{}\"", render::method_names(), value));
    return *m;
}

render::TraceSettings TraceFlags::resolve() const {
    if (!pipeline::is_render_mode(mode))
        throw InputError(fmt::format("--mode must be normals, depth, shaded, steps or bricks, got \"{}\"", mode));
    const render::Method m = method_flag(method);
    const auto n = render::normals_from_string(normals);
    if (!n) throw InputError(fmt::format("--normals must be central, tetra or continuous, got \"{}\"", normals));
    render::TraceSettings t = trace;
    t.method = m;
    t.normals = *n;
    t.shade = mode == "shaded";
    validate_image_size(t.width, t.height);
    return t;
}

}  // namespace sdfbrick::cli
