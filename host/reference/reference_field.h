// The independent double-precision host reference of the distance field: the primitives, the
// edit transform, the combine rules and the scene, written from the mathematical definitions (not
// from the kernels) so that it can catch mistakes in them. Plain C++, no OpenCL, no culling.
//
// Definitions (every function below follows them literally):
//   edit value at a geometry-frame point p:  primitive(conj(q) (p - t) / s) * s / L,  L = lipschitz(e)
//     (a mesh edit's primitive is the exact signed distance to its triangles, brute force with the
//     winding-number sign (mesh_distance.h), not the grid the kernels sample)
//   combining, left to right, starting from F = SDF_FAR (the empty field), with v the edit value:
//     add        k > 0 ? smooth_min(F, v, k)  : min(F, v)
//     subtract   k > 0 ? smooth_max(F, -v, k) : max(F, -v)
//     intersect  k > 0 ? smooth_max(F, v, k)  : max(F, v)
//   smooth_min(a, b, k) = min(a, b) - h^2 k / 4,  smooth_max(a, b, k) = max(a, b) + h^2 k / 4,
//     h = max(k - |a - b|, 0) / k   (compact support: exactly min / max when |a - b| >= k).
//   scene value at a world point: min over objects of  scale * F_geometry(inverse_apply(p)),
//     starting from SDF_FAR (so no objects -> SDF_FAR).
// Scenes and geometries are evaluated as given: apply animation first with scene_at / geometry_at.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "core/rng.h"
#include "scene/scene.h"

namespace sdfbrick::reference {

// The empty field's value, SDF_FAR (1e20f) widened to double exactly.
inline constexpr double kFar = static_cast<double>(SDF_FAR);

// Distance-like value of a primitive at a point of its local frame; params as in kernels/sdf_types.h.
// Menger's iteration count params[1] is rounded to the nearest integer and clamped to [0, 16].
double primitive_distance(Primitive prim, const std::array<double, 4>& params, const glm::dvec3& local);

// The edit's value at a point of the geometry frame (transform and Lipschitz bound applied).
double edit_value(const Edit& e, const glm::dvec3& p);

double smooth_min(double a, double b, double k);
double smooth_max(double a, double b, double k);
// One combine step: the field so far, then the edit's value with its op and blend radius.
double combine(Op op, double blend, double field, double value);

// The geometry's field at a point of its frame: all edits in order (SDF_FAR when there are none).
double evaluate(const Geometry& g, const glm::dvec3& p);
// Only the listed edits, in the given order. An index out of range throws std::out_of_range.
double evaluate(const Geometry& g, std::span<const std::uint32_t> edit_indices, const glm::dvec3& p);
// Central differences with step h on each axis (not normalised).
glm::dvec3 gradient(const Geometry& g, const glm::dvec3& p, double h = 1e-6);

// The scene's field at a world point.
double evaluate(const Scene& s, const glm::dvec3& world);


// The box random_points draws from: bounds(g) grown on every side by 10% of its largest extent
// (empty when bounds(g) is empty, e.g. a geometry of subtract edits only).
Aabb sampling_box(const Geometry& g);
// `count` uniform random points in sampling_box(g); none when that box is empty.
std::vector<glm::dvec3> random_points(const Geometry& g, std::size_t count, std::uint64_t seed);
// Points on / near the surface: random points of sampling_box(g) pulled onto the zero set with
// Newton steps p -= f grad / |grad|^2 (at most 32), kept only when they converge to
// |f| < surface_tolerance(g); then moved along the unit normal by a uniform amount in
// [-offset, offset]. Gives up after 20 * count + 100 draws, so it may return fewer than `count`
// points (none for a geometry without a surface in its sampling box).
std::vector<glm::dvec3> near_surface_points(const Geometry& g, std::size_t count, std::uint64_t seed,
                                            double offset);
// The convergence tolerance of near_surface_points: 1e-10 * max(1, diagonal of sampling_box(g)).
double surface_tolerance(const Geometry& g);

}  // namespace sdfbrick::reference
