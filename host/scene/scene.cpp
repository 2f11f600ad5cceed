#include "scene/scene.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace sdfbrick {

namespace {

constexpr std::array<std::string_view, kPrimitiveCount> kPrimitiveNames = {
    "sphere", "box", "round_box", "torus", "capsule", "cylinder", "cone", "ellipsoid", "menger", "mesh"};
constexpr std::array<std::string_view, 3> kOpNames = {"add", "subtract", "intersect"};

// Half extents (local frame) of the box that holds { x : primitive(x) <= c }.
glm::dvec3 local_level_half_extents(const Edit& e, double c) {
    const auto& p = e.params;
    switch (e.primitive) {
        case Primitive::Sphere: return glm::dvec3(p[0] + c);
        case Primitive::Box:
        case Primitive::RoundBox: return glm::dvec3(p[0], p[1], p[2]) + c;
        case Primitive::Torus: return glm::dvec3(p[0] + p[1] + c, p[1] + c, p[0] + p[1] + c);
        case Primitive::Capsule: return glm::dvec3(p[1] + c, p[0] + p[1] + c, p[1] + c);
        case Primitive::Cylinder: return glm::dvec3(p[1] + c, p[0] + c, p[1] + c);
        case Primitive::Cone: {
            const double r = std::max(p[1], p[2]);
            return glm::dvec3(r + c, p[0] + c, r + c);
        }
        case Primitive::Ellipsoid: {
            // value = (|x/r| - 1) * min(r) <= c  <=>  x inside the ellipsoid with semi-axes r (1 + c / min(r)).
            const glm::dvec3 r(p[0], p[1], p[2]);
            const double m = std::min({r.x, r.y, r.z});
            return r * (1.0 + c / m);
        }
        case Primitive::Menger:
            // The sponge's value is max(box, ...) >= box, so its level set lies in the box's.
            return glm::dvec3(p[0] + c);
        case Primitive::Mesh:
            // params hold the grid's box; outside it the value is the distance to the box plus a
            // boundary value >= 0 (kernels/sdf_edit.h, sdf_mesh).
            return glm::dvec3(p[0], p[1], p[2]) + c;
    }
    throw std::logic_error("unknown primitive");
}

}  // namespace

std::string_view to_string(Primitive p) { return kPrimitiveNames.at(static_cast<std::size_t>(p)); }
std::string_view to_string(Op op) { return kOpNames.at(static_cast<std::size_t>(op)); }

std::optional<Primitive> primitive_from_string(std::string_view s) {
    for (std::size_t i = 0; i < kPrimitiveNames.size(); ++i)
        if (kPrimitiveNames[i] == s) return static_cast<Primitive>(i);
    return std::nullopt;
}

std::optional<Op> op_from_string(std::string_view s) {
    for (std::size_t i = 0; i < kOpNames.size(); ++i)
        if (kOpNames[i] == s) return static_cast<Op>(i);
    return std::nullopt;
}

Aabb Transform::apply(const Aabb& local) const {
    if (local.empty()) return local;
    // Centre moves with the transform; half extents through |R| (the rotation matrix's absolute values).
    const glm::dmat3 r = glm::mat3_cast(rotation);
    const glm::dvec3 h = 0.5 * local.extent() * scale;
    glm::dvec3 world_h(0.0);
    for (int col = 0; col < 3; ++col)
        for (int row = 0; row < 3; ++row) world_h[row] += std::abs(r[col][row]) * h[col];
    const glm::dvec3 c = apply(local.centre());
    return Aabb{c - world_h, c + world_h};
}

glm::dvec3 Camera::eye_position() const {
    if (kind == Kind::LookAt) return eye;
    const double yaw = glm::radians(yaw_deg);
    const double pitch = glm::radians(pitch_deg);
    const glm::dvec3 dir(std::cos(pitch) * std::sin(yaw), std::sin(pitch), std::cos(pitch) * std::cos(yaw));
    return target + distance * dir;
}

double lipschitz(const Edit& e) {
    // Every analytic formula is 1-Lipschitz (docs/scene-format.md, "Lipschitz bounds"): the exact
    // distances trivially; the ellipsoid's (|x/r| - 1) min(r) has gradient norm <= min(r)/min(r);
    // the Menger sponge is a max of 1-Lipschitz terms. tests/reference/test_reference_field.cpp
    // checks it empirically. A mesh's trilinear lookup of exact distances is sqrt(3)-Lipschitz.
    return e.primitive == Primitive::Mesh ? std::sqrt(3.0) : 1.0;
}

Aabb local_level_bounds(const Edit& e, double c) {
    const glm::dvec3 h = local_level_half_extents(e, std::max(c, 0.0));
    return Aabb{-h, h};
}

Aabb level_bounds(const Edit& e, double c) {
    // value = primitive(local) * s / L <= c  <=>  primitive(local) <= c L / s.
    const double local_c = std::max(c, 0.0) * lipschitz(e) / e.transform.scale;
    return e.transform.apply(local_level_bounds(e, local_c));
}

Edit edit_at(const Edit& e, double t) {
    Edit out = e;
    out.animation.reset();
    if (!e.animation) return out;
    const Animation& a = *e.animation;
    glm::dvec3 pos = e.transform.translation + a.velocity * t + 0.5 * a.acceleration * (t * t);
    if (a.wrap_y) {
        const double lo = (*a.wrap_y)[0], span = (*a.wrap_y)[1] - (*a.wrap_y)[0];
        pos.y = lo + (pos.y - lo - span * std::floor((pos.y - lo) / span));
    }
    out.transform.translation = pos;
    if (a.spin_rate != 0.0) {
        const glm::dquat spin = glm::angleAxis(a.spin_rate * t, glm::normalize(a.spin_axis));
        out.transform.rotation = glm::normalize(spin * e.transform.rotation);
    }
    return out;
}

Geometry geometry_at(const Geometry& g, double t) {
    Geometry out{g.name, {}};
    out.edits.reserve(g.edits.size());
    for (const Edit& e : g.edits) out.edits.push_back(edit_at(e, t));
    return out;
}

Scene scene_at(const Scene& s, double t) {
    Scene out = s;
    out.time = t;
    for (Geometry& g : out.geometries) g = geometry_at(g, t);
    return out;
}

Aabb bounds(const Geometry& g) {
    // With F' = smin(F, v, k): F' <= 0 implies F <= 0 or v <= k (smin >= max(F, v) - k), so the solid
    // lies in the union of the add edits' level-k sets; subtract and intersect only remove material.
    Aabb b;
    for (const Edit& e : g.edits)
        if (e.op == Op::Add) b.grow(influence_bounds(e));
    return b;
}

Aabb bounds(const Scene& s, const Object& o) { return o.transform.apply(bounds(s.geometries.at(o.geometry))); }

}  // namespace sdfbrick
