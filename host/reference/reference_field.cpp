#include "reference/reference_field.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "reference/mesh_distance.h"

namespace sdfbrick::reference {
namespace {

double length2(double x, double y) { return std::sqrt(x * x + y * y); }
double dot2(double ax, double ay, double bx, double by) { return ax * bx + ay * by; }

double box_distance(const glm::dvec3& p, const glm::dvec3& b) {
    const glm::dvec3 q = glm::abs(p) - b;
    return glm::length(glm::max(q, glm::dvec3(0.0))) + std::min(std::max(q.x, std::max(q.y, q.z)), 0.0);
}

// mod(x, 2) = x - 2 floor(x / 2)  (GLSL mod: result in [0, 2) for finite x).
double mod2(double x) { return x - 2.0 * std::floor(x / 2.0); }

double menger(const glm::dvec3& p, double s, int n) {
    const glm::dvec3 u = p / s;
    double d = box_distance(u, glm::dvec3(1.0));
    double sc = 1.0;
    for (int i = 0; i < n; ++i) {
        const glm::dvec3 a(mod2(u.x * sc) - 1.0, mod2(u.y * sc) - 1.0, mod2(u.z * sc) - 1.0);
        sc *= 3.0;
        const glm::dvec3 r(std::abs(1.0 - 3.0 * std::abs(a.x)), std::abs(1.0 - 3.0 * std::abs(a.y)),
                           std::abs(1.0 - 3.0 * std::abs(a.z)));
        const double da = std::max(r.x, r.y);
        const double db = std::max(r.y, r.z);
        const double dc = std::max(r.z, r.x);
        const double c = (std::min(da, std::min(db, dc)) - 1.0) / sc;
        d = std::max(d, c);
    }
    return d * s;
}

double capped_cone(const glm::dvec3& p, double h, double r1, double r2) {
    const double qx = length2(p.x, p.z);
    const double qy = p.y;
    const double k1x = r2, k1y = h;
    const double k2x = r2 - r1, k2y = 2.0 * h;
    const double cax = qx - std::min(qx, qy < 0.0 ? r1 : r2);
    const double cay = std::abs(qy) - h;
    const double t = std::clamp(dot2(k1x - qx, k1y - qy, k2x, k2y) / dot2(k2x, k2y, k2x, k2y), 0.0, 1.0);
    const double cbx = qx - k1x + k2x * t;
    const double cby = qy - k1y + k2y * t;
    const double s = (cbx < 0.0 && cay < 0.0) ? -1.0 : 1.0;
    return s * std::sqrt(std::min(dot2(cax, cay, cax, cay), dot2(cbx, cby, cbx, cby)));
}

}  // namespace

double primitive_distance(Primitive prim, const std::array<double, 4>& params, const glm::dvec3& p) {
    switch (prim) {
    case Primitive::Sphere:
        return glm::length(p) - params[0];
    case Primitive::Box:
        return box_distance(p, glm::dvec3(params[0], params[1], params[2]));
    case Primitive::RoundBox: {
        const double r = params[3];
        const glm::dvec3 q = glm::abs(p) - glm::dvec3(params[0], params[1], params[2]) + r;
        return glm::length(glm::max(q, glm::dvec3(0.0))) + std::min(std::max(q.x, std::max(q.y, q.z)), 0.0) - r;
    }
    case Primitive::Torus:
        return length2(length2(p.x, p.z) - params[0], p.y) - params[1];
    case Primitive::Capsule: {
        const double h = params[0];
        const double y = p.y - std::clamp(p.y, -h, h);
        return glm::length(glm::dvec3(p.x, y, p.z)) - params[1];
    }
    case Primitive::Cylinder: {
        const double dx = length2(p.x, p.z) - params[1];
        const double dy = std::abs(p.y) - params[0];
        return std::min(std::max(dx, dy), 0.0) + length2(std::max(dx, 0.0), std::max(dy, 0.0));
    }
    case Primitive::Cone:
        return capped_cone(p, params[0], params[1], params[2]);
    case Primitive::Ellipsoid: {
        const glm::dvec3 r(params[0], params[1], params[2]);
        return (glm::length(p / r) - 1.0) * std::min(r.x, std::min(r.y, r.z));
    }
    case Primitive::Menger: {
        const double n = std::clamp(std::round(params[1]), 0.0, 16.0);
        return menger(p, params[0], static_cast<int>(n));
    }
    case Primitive::Mesh:
        throw std::invalid_argument("reference::primitive_distance: a mesh's distance needs its triangles (edit_value)");
    }
    throw std::invalid_argument("reference::primitive_distance: unknown primitive " +
                                std::to_string(static_cast<std::uint32_t>(prim)));
}

double edit_value(const Edit& e, const glm::dvec3& p) {
    const glm::dvec3 local = e.transform.inverse_apply(p);
    const double d = e.primitive != Primitive::Mesh ? primitive_distance(e.primitive, e.params, local)
                     : e.mesh->level_set()          ? grid_distance(e.mesh->frame, e.mesh->values, local)
                                                    : mesh_signed_distance(e.mesh->mesh, local);
    return d * e.transform.scale / lipschitz(e);
}

double smooth_min(double a, double b, double k) {
    const double h = std::max(k - std::abs(a - b), 0.0) / k;
    return std::min(a, b) - h * h * k / 4.0;
}

double smooth_max(double a, double b, double k) {
    const double h = std::max(k - std::abs(a - b), 0.0) / k;
    return std::max(a, b) + h * h * k / 4.0;
}

double combine(Op op, double blend, double field, double value) {
    const bool smooth = blend > 0.0;
    switch (op) {
    case Op::Add:
        return smooth ? smooth_min(field, value, blend) : std::min(field, value);
    case Op::Subtract:
        return smooth ? smooth_max(field, -value, blend) : std::max(field, -value);
    case Op::Intersect:
        return smooth ? smooth_max(field, value, blend) : std::max(field, value);
    }
    throw std::invalid_argument("reference::combine: unknown op " + std::to_string(static_cast<std::uint32_t>(op)));
}

double evaluate(const Geometry& g, const glm::dvec3& p) {
    double f = kFar;
    for (const Edit& e : g.edits) f = combine(e.op, e.blend, f, edit_value(e, p));
    return f;
}

double evaluate(const Geometry& g, std::span<const std::uint32_t> edit_indices, const glm::dvec3& p) {
    double f = kFar;
    for (const std::uint32_t i : edit_indices) {
        const Edit& e = g.edits.at(i);
        f = combine(e.op, e.blend, f, edit_value(e, p));
    }
    return f;
}

glm::dvec3 gradient(const Geometry& g, const glm::dvec3& p, double h) {
    glm::dvec3 grad;
    for (int axis = 0; axis < 3; ++axis) {
        glm::dvec3 a = p, b = p;
        a[axis] += h;
        b[axis] -= h;
        grad[axis] = (evaluate(g, a) - evaluate(g, b)) / (2.0 * h);
    }
    return grad;
}

double evaluate(const Scene& s, const glm::dvec3& world) {
    double f = kFar;
    for (const Object& o : s.objects) {
        if (o.geometry >= s.geometries.size())
            throw std::out_of_range("reference::evaluate: object '" + o.name + "' names geometry " +
                                    std::to_string(o.geometry) + " of " + std::to_string(s.geometries.size()));
        const double v = o.transform.scale * evaluate(s.geometries[o.geometry], o.transform.inverse_apply(world));
        f = std::min(f, v);
    }
    return f;
}

// ---- sample points ----

Aabb sampling_box(const Geometry& g) {
    const Aabb b = bounds(g);
    if (b.empty()) return b;
    const glm::dvec3 e = b.extent();
    return b.inflated(0.1 * std::max(e.x, std::max(e.y, e.z)));
}

double surface_tolerance(const Geometry& g) {
    const Aabb b = sampling_box(g);
    const double diag = b.empty() ? 0.0 : glm::length(b.extent());
    return 1e-10 * std::max(1.0, diag);
}

std::vector<glm::dvec3> random_points(const Geometry& g, std::size_t count, std::uint64_t seed) {
    std::vector<glm::dvec3> out;
    const Aabb box = sampling_box(g);
    if (box.empty()) return out;
    Rng rng(seed);
    out.reserve(count);
    for (std::size_t i = 0; i < count; ++i) out.push_back(rng.in_box(box.lo, box.hi));
    return out;
}

std::vector<glm::dvec3> near_surface_points(const Geometry& g, std::size_t count, std::uint64_t seed,
                                            double offset) {
    std::vector<glm::dvec3> out;
    const Aabb box = sampling_box(g);
    if (box.empty() || count == 0) return out;
    const double tol = surface_tolerance(g);
    const double h = 1e-6 * std::max(1.0, glm::length(box.extent()));  // gradient step
    Rng rng(seed);
    out.reserve(count);
    const std::size_t max_draws = 20 * count + 100;
    for (std::size_t draw = 0; draw < max_draws && out.size() < count; ++draw) {
        glm::dvec3 p = rng.in_box(box.lo, box.hi);
        const double t = rng.uniform(-offset, offset);  // drawn for every candidate: fixed stream use
        bool converged = false;
        for (int step = 0; step < 32; ++step) {
            const double f = evaluate(g, p);
            if (std::abs(f) < tol) {
                converged = true;
                break;
            }
            const glm::dvec3 grad = gradient(g, p, h);
            const double g2 = glm::dot(grad, grad);
            if (!(g2 > 1e-12) || !std::isfinite(g2)) break;
            p -= f * grad / g2;
            if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) break;
        }
        if (!converged) continue;
        const glm::dvec3 grad = gradient(g, p, h);
        const double gl = glm::length(grad);
        if (!(gl > 1e-6) || !std::isfinite(gl)) continue;
        out.push_back(p + (t / gl) * grad);
    }
    return out;
}

}  // namespace sdfbrick::reference
