#include "render/warnings.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "render/brick_tracer.h"

namespace sdfbrick::render {
namespace {

// The spacing of floats at magnitude x (x > 0): 2^(floor(log2 x) - 23).
double float_spacing(double x) { return std::ldexp(1.0, std::ilogb(x) - 23); }

double largest_coordinate(const Aabb& b) {
    if (b.empty()) return 0.0;
    return std::max({std::abs(b.lo.x), std::abs(b.lo.y), std::abs(b.lo.z), std::abs(b.hi.x), std::abs(b.hi.y),
                     std::abs(b.hi.z)});
}

struct Coordinate {
    double value = 0.0, voxel = 1.0;
    double share() const { return value > 0.0 ? float_spacing(value) / voxel : 0.0; }
};

}  // namespace

std::string_view to_string(TraceWarning::Cause c) {
    return c == TraceWarning::Cause::step_bound ? "step_bound" : "float_precision";
}

nlohmann::json to_json(const TraceWarning& w) { return {{"cause", to_string(w.cause)}, {"message", w.message}}; }

std::optional<TraceWarning> precision_warning(const Scene& scene, const SceneBricks& bricks) {
    if (bricks.bricks == 0 || bricks.voxel_world <= 0.0) return std::nullopt;
    Aabb world;
    world.grow(scene.camera.eye_position());
    for (const Object& o : scene.objects) world.grow(bounds(scene, o));
    Coordinate worst{largest_coordinate(world), bricks.voxel_world};
    for (const Geometry& g : scene.geometries) {
        const Coordinate c{largest_coordinate(bounds(g)), bricks.settings.voxel()};
        if (c.share() > worst.share()) worst = c;
    }
    if (worst.share() <= kPrecisionVoxelShare) return std::nullopt;
    return TraceWarning{TraceWarning::Cause::float_precision,
                        fmt::format("coordinates of {:.1e} exceed float precision for a voxel of {:.0e} (floats there are "
                                    "{:.2g} voxels apart; positions need {} voxel): depths and hits may be off by that much",
                                    worst.value, worst.voxel, worst.share(), kPrecisionVoxelShare)};
}

std::optional<TraceWarning> step_bound_warning(std::uint64_t capped, std::uint64_t pixels, Method method) {
    if (capped == 0) return std::nullopt;
    return TraceWarning{TraceWarning::Cause::step_bound,
                        fmt::format("{} of {} rays ({:.3g}%) stopped at the in-brick step bound of method {} (a miss there "
                                    "may hide a surface; grazing rays do this to sphere tracing, hybrid and analytic "
                                    "do not stop there)",
                                    capped, pixels, 100.0 * static_cast<double>(capped) / static_cast<double>(pixels),
                                    to_string(method))};
}

std::vector<TraceWarning> trace_warnings(const Scene& scene, const SceneBricks& bricks, std::uint64_t capped_rays,
                                         std::uint64_t pixels, Method method) {
    std::vector<TraceWarning> out;
    if (auto w = precision_warning(scene, bricks)) out.push_back(std::move(*w));
    if (auto w = step_bound_warning(capped_rays, pixels, method)) out.push_back(std::move(*w));
    return out;
}

}  // namespace sdfbrick::render
