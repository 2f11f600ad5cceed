// Warnings about a brick render whose output is defined but may be wrong: rays that stopped at a
// kernel loop bound, and coordinates so large that float spacing is a sizeable part of a voxel.
// Reports carry them typed; the CLI prints each as one "warning:" line.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "image/render_buffer.h"
#include "scene/scene.h"

namespace sdfbrick::render {

enum class Method;   // render/brick_tracer.h
struct SceneBricks;  // render/brick_tracer.h

struct TraceWarning {
    enum class Cause { step_bound, float_precision };
    Cause cause = Cause::step_bound;
    std::string message;  // one line, naming the cause and the figures behind it
};
std::string_view to_string(TraceWarning::Cause c);
// {"cause": "step_bound" | "float_precision", "message": ...}
nlohmann::json to_json(const TraceWarning& w);

// The float spacing at a coordinate's magnitude, as a share of a voxel, above which the tracer's
// positions (float, kernels/sdf_trace.h) are too coarse: the accuracy bounds the tests and docs
// state (depth p99 below 0.2 voxels) need positions good to a tenth of a voxel.
inline constexpr double kPrecisionVoxelShare = 0.1;

// The float precision warning for tracing scene's bricks: the largest coordinate the tracer works with
// (the camera's eye and every object's bounds in the world, every geometry's bounds in its own frame)
// against the voxel in that frame; nothing when the spacing there is within kPrecisionVoxelShare voxels.
std::optional<TraceWarning> precision_warning(const Scene& scene, const SceneBricks& bricks);
// The step bound warning for a traced image of `pixels` pixels: how many rays' search stopped at a
// kernel loop bound.
std::optional<TraceWarning> step_bound_warning(std::uint64_t capped_rays, std::uint64_t pixels, Method method);
// Both, in that order (precision first).
std::vector<TraceWarning> trace_warnings(const Scene& scene, const SceneBricks& bricks, std::uint64_t capped_rays,
                                         std::uint64_t pixels, Method method);

}  // namespace sdfbrick::render
