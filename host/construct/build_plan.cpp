#include "construct/build_parts.h"

#include <algorithm>
#include <limits>
#include <numeric>
#include <span>

#include "cl/launch.h"
#include "construct/mesh_pool.h"
#include "scene/to_device.h"

namespace sdfbrick::construct::detail {

namespace {

double largest_blend(const Geometry& g) {
    double k = 0.0;
    for (const Edit& e : g.edits) k = std::max(k, e.blend);
    return k;
}

// The coarsest leaf level and each leaf level's C; refuses a tolerance below float precision at the
// domain's coordinates and a finest level too fine for the 63-bit Morton keys of the merge.
void plan_adaptive(BuildPlan& p, const BuildSettings& s, double blend) {
    const double precision = p.magnitude * std::ldexp(1.0, -20);
    if (s.tolerance < precision)
        throw SettingError("tolerance", fmt::format("tolerance {} is finer than float precision allows at coordinates "
                                                    "up to {} (about {:.3g}): use a larger tolerance",
                                                    s.tolerance, p.magnitude, precision));
    if (p.domain.cells_per_axis(p.finest()) > (std::int64_t{1} << 21))
        throw SettingError("leaf_size", fmt::format("an adaptive build allows at most 2^21 finest bricks per axis; "
                                                    "leaf_size {} needs {}",
                                                    s.leaf_size, p.domain.cells_per_axis(p.finest())));
    const double largest = s.max_leaf_size > 0.0 ? s.max_leaf_size : std::numeric_limits<double>::infinity();
    // A level whose stored values round by more than the tolerance (half a step of the snorm format
    // over that level's band) cannot keep the bound anywhere: its bricks are never leaves, so they
    // are neither checked nor culled for their own evaluation.
    const double steps = s.layout().levels();
    const auto rounding_fits = [&](int l) {
        return s.format == BrickFormat::float32 || 0.5 * std::ldexp(double(p.band), p.shift(l)) / steps <= s.tolerance;
    };
    p.coarsest_leaf = p.finest();
    while (p.coarsest_leaf > 1 && p.domain.cell_size(p.coarsest_leaf - 1) <= largest &&
           rounding_fits(p.coarsest_leaf - 1))
        --p.coarsest_leaf;
    p.tolerance = static_cast<float>(s.tolerance);
    for (int l = p.coarsest_leaf; l < p.finest(); ++l) {
        const double band = std::ldexp(double(p.band), p.shift(l));
        p.level_clamp[static_cast<std::size_t>(l)] =
            std::max(p.clamp_c, float_up(band * (1.0 + 1.0 / 256.0) + blend));
    }
}

}  // namespace

BuildPlan plan_build(const Geometry& g, const Aabb& box, const BuildSettings& s) {
    BuildPlan p;
    p.domain = make_domain(box, s.leaf_size, s.branching);
    if (s.levels > 0) {
        if (s.levels < p.domain.levels)
            throw SettingError("levels", fmt::format("levels {} cannot cover geometry \"{}\" at leaf_size {}: it needs "
                                                     "at least {}",
                                                     s.levels, g.name, s.leaf_size, p.domain.levels));
        const int bits_per_level = s.branching == 4 ? 2 : 1;
        if ((s.levels - 1) * bits_per_level > 30)
            throw SettingError("levels", fmt::format("levels {} with branching {} exceeds 2^30 leaf bricks per axis",
                                                     s.levels, s.branching));
        p.domain.levels = s.levels;
    }
    p.log2b = s.branching == 4 ? 2 : 1;
    p.per_parent = std::size_t{1} << (3 * p.log2b);
    const glm::dvec3 lo = p.domain.origin, hi = p.domain.origin + p.domain.side();
    p.magnitude =
        std::max({glm::abs(lo).x, glm::abs(lo).y, glm::abs(lo).z, std::abs(hi.x), std::abs(hi.y), std::abs(hi.z)});
    p.voxel = s.voxel();
    p.band = static_cast<float>(s.band_voxels * p.voxel);
    p.apron = s.layout().apron();
    const double largest = largest_blend(g);
    p.hard = largest == 0.0;
    const double blend = s.guard * largest;
    p.clamp_c = float_up(std::max<double>(p.band, p.threshold(p.domain.levels - 1)) * (1.0 + 1.0 / 256.0) + blend);
    p.coarsest_leaf = p.finest();
    p.level_clamp.assign(static_cast<std::size_t>(p.domain.levels), p.clamp_c);
    if (s.adaptive()) plan_adaptive(p, s, blend);
    return p;
}

BuildInputs::BuildInputs(ocl::Device& d, BuildPrograms& k, Scan& sc, const Geometry& g, const BuildSettings& s,
                         const BuildPlan& p, measure::Scheduler& sched, GeometryBuild& result,
                         const std::vector<SdfEdit>* prepared)
    : device(d),
      programs(k),
      scan(sc),
      geometry(g),
      settings(s),
      plan(p),
      scheduler(sched),
      out(result),
      converted(prepared ? std::vector<SdfEdit>{} : to_device(g)),
      edits_host(prepared ? *prepared : converted),
      edits(ocl::pooled, d, edits_host),
      prepared_edits(ocl::pooled, d, edits.size()),
      edit_reaches(ocl::pooled, d, edits.size()),
      meshes(ocl::pooled, d, std::span<const float>(mesh_pool(std::span<const Geometry>(&g, 1), d, scheduler))),
      origin(plan.domain.origin),
      empty_uints(ocl::pooled, d, 0) {
    // The edits as the folds read them, with their reaches, once for the build (edit_prepare.cl).
    if (edits.size() == 0) return;
    ocl::set_args(programs.prepare_k.get(), edits, static_cast<cl_uint>(edits.size()), prepared_edits, edit_reaches);
    scheduler.launch(measure::Stage::evaluate, -1, programs.prepare_k.get(), round_up(edits.size(), kGroup1d),
                     kGroup1d);
}

}  // namespace sdfbrick::construct::detail
