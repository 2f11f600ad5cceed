// Tests of the double-precision host reference (host/reference): primitives against values derived
// by hand, transforms, combine rules, Lipschitz bounds, level bounds (scene.cpp), sample points and
// the reference surface cells of the brick hierarchy.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <set>
#include <thread>
#include <span>
#include <tuple>
#include <vector>

#include <glm/gtc/quaternion.hpp>

#include "core/errors.h"
#include "reference/reference_field.h"
#include "reference/surface_cells.h"
#include "scene/scene.h"

namespace sdfbrick::reference {
namespace {

using construct::Domain;
using construct::make_domain;
using construct::morton_child;

constexpr double kEps = 1e-12;
constexpr double kPi = 3.14159265358979323846;

std::array<double, 4> P(double a, double b = 0.0, double c = 0.0, double d = 0.0) { return {a, b, c, d}; }

double prim(Primitive p, const std::array<double, 4>& params, double x, double y, double z) {
    return primitive_distance(p, params, glm::dvec3(x, y, z));
}

Edit make_edit(Primitive p, const std::array<double, 4>& params, Op op = Op::Add, double blend = 0.0,
               const Transform& t = {}) {
    Edit e;
    e.primitive = p;
    e.params = params;
    e.op = op;
    e.blend = blend;
    e.transform = t;
    return e;
}

Edit sphere_at(glm::dvec3 c, double r, Op op = Op::Add, double blend = 0.0) {
    Transform t;
    t.translation = c;
    return make_edit(Primitive::Sphere, P(r), op, blend, t);
}

Transform make_transform(glm::dvec3 translation, double angle, glm::dvec3 axis, double scale) {
    Transform t;
    t.translation = translation;
    t.rotation = glm::angleAxis(angle, glm::normalize(axis));
    t.scale = scale;
    return t;
}

// ---- primitives against hand-derived values ----

TEST(ReferencePrimitive, Sphere) {
    const auto p = P(1.0);
    EXPECT_NEAR(prim(Primitive::Sphere, p, 2, 0, 0), 1.0, kEps);
    EXPECT_NEAR(prim(Primitive::Sphere, p, 0, 0, 0), -1.0, kEps);
    EXPECT_NEAR(prim(Primitive::Sphere, p, 0, 1, 0), 0.0, kEps);
    EXPECT_NEAR(prim(Primitive::Sphere, p, 0, 0, -0.25), -0.75, kEps);
    EXPECT_NEAR(prim(Primitive::Sphere, p, 1, 1, 1), std::sqrt(3.0) - 1.0, kEps);
    EXPECT_NEAR(prim(Primitive::Sphere, P(2.5), 0.6, 0.0, 0.8), -1.5, kEps);
}

TEST(ReferencePrimitive, Box) {
    const auto b = P(1, 2, 3);
    EXPECT_NEAR(prim(Primitive::Box, b, 0, 0, 0), -1.0, kEps);         // nearest face x = 1
    EXPECT_NEAR(prim(Primitive::Box, b, 0.5, 0, 0), -0.5, kEps);
    EXPECT_NEAR(prim(Primitive::Box, b, 0, 0, 2.5), -0.5, kEps);       // face z = 3 nearer than x
    EXPECT_NEAR(prim(Primitive::Box, b, 2, 0, 0), 1.0, kEps);
    EXPECT_NEAR(prim(Primitive::Box, b, 0, -5, 0), 3.0, kEps);
    EXPECT_NEAR(prim(Primitive::Box, b, 2, 3, 0), std::sqrt(2.0), kEps);  // off an edge
    EXPECT_NEAR(prim(Primitive::Box, b, -2, 3, -4), std::sqrt(3.0), kEps);  // off a corner
    EXPECT_NEAR(prim(Primitive::Box, b, 1, 2, 3), 0.0, kEps);            // the corner
    EXPECT_NEAR(prim(Primitive::Box, b, 1, 0.3, -2.9), 0.0, kEps);       // on a face
}

TEST(ReferencePrimitive, RoundBox) {
    const auto b = P(1, 1, 1, 0.5);  // outer half extents 1, corners rounded with radius 0.5
    EXPECT_NEAR(prim(Primitive::RoundBox, b, 0, 0, 0), -1.0, kEps);
    EXPECT_NEAR(prim(Primitive::RoundBox, b, 2, 0, 0), 1.0, kEps);  // outer faces stay at 1
    EXPECT_NEAR(prim(Primitive::RoundBox, b, 1, 0.3, 0), 0.0, kEps);
    // Off the corner: distance to the corner sphere (centre (0.5, 0.5, 0.5), radius 0.5).
    EXPECT_NEAR(prim(Primitive::RoundBox, b, 2, 2, 2), 1.5 * std::sqrt(3.0) - 0.5, kEps);
    // The sharp corner (1,1,1) is outside the rounded box.
    EXPECT_NEAR(prim(Primitive::RoundBox, b, 1, 1, 1), 0.5 * std::sqrt(3.0) - 0.5, kEps);
    // Off an edge (x, y beyond, z inside): distance to the edge cylinder of radius 0.5 around (0.5, 0.5, z).
    EXPECT_NEAR(prim(Primitive::RoundBox, b, 1.5, 1.5, 0.2), std::sqrt(2.0) - 0.5, kEps);
    // r = 0 is the plain box.
    EXPECT_NEAR(prim(Primitive::RoundBox, P(1, 2, 3, 0), -2, 3, -4), std::sqrt(3.0), kEps);
}

TEST(ReferencePrimitive, Torus) {
    const auto t = P(2.0, 0.5);  // in the xz plane, around +y
    EXPECT_NEAR(prim(Primitive::Torus, t, 2, 0, 0), -0.5, kEps);
    EXPECT_NEAR(prim(Primitive::Torus, t, 0, 0, -2), -0.5, kEps);
    EXPECT_NEAR(prim(Primitive::Torus, t, 0, 0, 0), 1.5, kEps);
    EXPECT_NEAR(prim(Primitive::Torus, t, 3, 0, 0), 0.5, kEps);
    EXPECT_NEAR(prim(Primitive::Torus, t, 0, 0, 2.5), 0.0, kEps);
    EXPECT_NEAR(prim(Primitive::Torus, t, 2, 0.5, 0), 0.0, kEps);  // top of the tube
    EXPECT_NEAR(prim(Primitive::Torus, t, 0, 2, 0), std::sqrt(8.0) - 0.5, kEps);  // on the axis
    EXPECT_NEAR(prim(Primitive::Torus, t, 0.6 * 2, 1.0, 0.8 * 2), 0.5, kEps);
}

TEST(ReferencePrimitive, Capsule) {
    const auto c = P(1.0, 0.5);  // segment from y=-1 to y=1, radius 0.5
    EXPECT_NEAR(prim(Primitive::Capsule, c, 0, 0, 0), -0.5, kEps);
    EXPECT_NEAR(prim(Primitive::Capsule, c, 0, 0.9, 0), -0.5, kEps);
    EXPECT_NEAR(prim(Primitive::Capsule, c, 0, 2, 0), 0.5, kEps);
    EXPECT_NEAR(prim(Primitive::Capsule, c, 0, 1.5, 0), 0.0, kEps);
    EXPECT_NEAR(prim(Primitive::Capsule, c, 1, 0, 0), 0.5, kEps);
    EXPECT_NEAR(prim(Primitive::Capsule, c, 0, 0, -0.5), 0.0, kEps);
    EXPECT_NEAR(prim(Primitive::Capsule, c, 3, -5, 0), 4.5, kEps);  // nearest point of the segment: (0,-1,0)
    EXPECT_NEAR(prim(Primitive::Capsule, P(0.0, 1.0), 0, 3, 4), 4.0, kEps);  // h = 0: a sphere
}

TEST(ReferencePrimitive, Cylinder) {
    const auto c = P(1.0, 0.5);  // half height 1, radius 0.5
    EXPECT_NEAR(prim(Primitive::Cylinder, c, 0, 0, 0), -0.5, kEps);
    EXPECT_NEAR(prim(Primitive::Cylinder, c, 0, 0.8, 0), -0.2, kEps);  // cap nearer than the side
    EXPECT_NEAR(prim(Primitive::Cylinder, c, 0, 2, 0), 1.0, kEps);
    EXPECT_NEAR(prim(Primitive::Cylinder, c, 0, -2, 0), 1.0, kEps);
    EXPECT_NEAR(prim(Primitive::Cylinder, c, 2, 0, 0), 1.5, kEps);
    EXPECT_NEAR(prim(Primitive::Cylinder, c, 0, 0, -2), 1.5, kEps);
    EXPECT_NEAR(prim(Primitive::Cylinder, c, 1.5, 2, 0), std::sqrt(2.0), kEps);  // off the rim
    EXPECT_NEAR(prim(Primitive::Cylinder, c, 0.3, 1, 0.4), 0.0, kEps);  // the rim
    EXPECT_NEAR(prim(Primitive::Cylinder, c, 0.1, 1, 0.1), 0.0, kEps);  // on the cap
}

TEST(ReferencePrimitive, Cone) {
    const auto c = P(1.0, 1.0, 0.5);  // half height 1, radius 1 at y=-1, 0.5 at y=+1
    const double side = 1.5 / std::sqrt(4.25);  // distance from the axis point (0,0) to the side line 2x + y/2 = 3/2
    EXPECT_NEAR(prim(Primitive::Cone, c, 0, 0, 0), -side, kEps);
    EXPECT_NEAR(prim(Primitive::Cone, c, 0, -2, 0), 1.0, kEps);
    EXPECT_NEAR(prim(Primitive::Cone, c, 0, 2, 0), 1.0, kEps);
    EXPECT_NEAR(prim(Primitive::Cone, c, 0.5, -1.5, 0), 0.5, kEps);  // under the bottom cap
    EXPECT_NEAR(prim(Primitive::Cone, c, 0.8, -1.5, 0), 0.5, kEps);  // under the bottom cap, beyond r2
    EXPECT_NEAR(prim(Primitive::Cone, c, 0.3, 1.5, 0), 0.5, kEps);   // over the top cap
    EXPECT_NEAR(prim(Primitive::Cone, c, 2, -1, 0), 1.0, kEps);      // off the bottom rim
    EXPECT_NEAR(prim(Primitive::Cone, c, 1, -1, 0), 0.0, kEps);      // bottom rim
    EXPECT_NEAR(prim(Primitive::Cone, c, 0, 1, 0.5), 0.0, kEps);     // top rim
    EXPECT_NEAR(prim(Primitive::Cone, c, 0.75, 0, 0), 0.0, kEps);    // on the side at mid height
    EXPECT_NEAR(prim(Primitive::Cone, c, 0, 0.95, 0), -0.05, kEps);  // just under the top cap
    // Radius order: wide at the bottom, narrow at the top.
    EXPECT_LT(prim(Primitive::Cone, c, 0.9, -0.99, 0), 0.0);
    EXPECT_GT(prim(Primitive::Cone, c, 0.9, 0.99, 0), 0.0);
    // Outside the side, perpendicular to it: (0.75, 0) + 0.5 * unit normal (2, 0.5) / sqrt(4.25).
    const double n = std::sqrt(4.25);
    EXPECT_NEAR(prim(Primitive::Cone, c, 0.75 + 0.5 * 2 / n, 0.5 * 0.5 / n, 0), 0.5, kEps);
    // r1 = r2: the cylinder.
    EXPECT_NEAR(prim(Primitive::Cone, P(1, 0.5, 0.5), 1.5, 2, 0), std::sqrt(2.0), kEps);
    EXPECT_NEAR(prim(Primitive::Cone, P(1, 0.5, 0.5), 0, 0.8, 0), -0.2, kEps);
}

TEST(ReferencePrimitive, Ellipsoid) {
    const auto e = P(1, 2, 3);
    EXPECT_NEAR(prim(Primitive::Ellipsoid, e, 0, 0, 0), -1.0, kEps);
    EXPECT_NEAR(prim(Primitive::Ellipsoid, e, 2, 0, 0), 1.0, kEps);
    EXPECT_NEAR(prim(Primitive::Ellipsoid, e, 0, 4, 0), 1.0, kEps);   // (|p/r| - 1) min r = (2 - 1) 1
    EXPECT_NEAR(prim(Primitive::Ellipsoid, e, 0, 0, -9), 2.0, kEps);
    EXPECT_NEAR(prim(Primitive::Ellipsoid, e, 0, 2, 0), 0.0, kEps);
    EXPECT_NEAR(prim(Primitive::Ellipsoid, e, 0, 0, 3), 0.0, kEps);
    // The zero set is the exact ellipsoid.
    for (int i = 0; i < 16; ++i) {
        const double th = 0.3 + 0.17 * i, ph = 0.11 * i;
        const glm::dvec3 s(1 * std::sin(th) * std::cos(ph), 2 * std::sin(th) * std::sin(ph), 3 * std::cos(th));
        EXPECT_NEAR(primitive_distance(Primitive::Ellipsoid, e, s), 0.0, kEps);
    }
    // A sphere when all radii are equal.
    EXPECT_NEAR(prim(Primitive::Ellipsoid, P(2, 2, 2), 0, 3, 4), 3.0, kEps);
}

TEST(ReferencePrimitive, Menger) {
    // One iteration: the unit cube minus three square tubes of half width 1/3 along the axes.
    const auto m1 = P(1.0, 1.0);
    EXPECT_NEAR(prim(Primitive::Menger, m1, 0, 0, 0), 1.0 / 3.0, kEps);      // centre: in the holes
    EXPECT_NEAR(prim(Primitive::Menger, m1, 0.9, 0, 0), 1.0 / 3.0, kEps);    // inside the x tube
    EXPECT_NEAR(prim(Primitive::Menger, m1, 2, 0, 0), 1.0, kEps);            // outside the cube
    EXPECT_NEAR(prim(Primitive::Menger, m1, 0.9, 0.9, 0.9), -0.1, kEps);     // corner sub-cube
    EXPECT_NEAR(prim(Primitive::Menger, m1, 0.9, 0.9, 0), -0.1, kEps);       // edge sub-cube
    EXPECT_NEAR(prim(Primitive::Menger, m1, 1, 0.5, 0.5), 0.0, kEps);        // solid part of a face
    EXPECT_NEAR(prim(Primitive::Menger, m1, 0.5, 0.5, 0.2), -1.0 / 6.0, kEps);  // wall of the z tube is 1/6 away
    EXPECT_NEAR(prim(Primitive::Menger, m1, 0.5, 0.2, 0.2), 2.0 / 15.0, kEps);  // in the x tube, wall at |y| = 1/3
    // Scale: half size 2 doubles distances.
    EXPECT_NEAR(prim(Primitive::Menger, P(2.0, 1.0), 1.8, 0, 0), 2.0 / 3.0, kEps);
    EXPECT_NEAR(prim(Primitive::Menger, P(2.0, 1.0), 4, 0, 0), 2.0, kEps);
    // Two iterations: the centre of the edge sub-cube (2/3, 2/3, 0) lies in its own z tube (half width 1/9).
    const auto m2 = P(1.0, 2.0);
    EXPECT_NEAR(prim(Primitive::Menger, m2, 2.0 / 3.0, 2.0 / 3.0, 0), 1.0 / 9.0, kEps);
    EXPECT_NEAR(prim(Primitive::Menger, m2, 0.9, 0.9, 0.9), -0.1, kEps);            // solid corner: face x = 1
    EXPECT_NEAR(prim(Primitive::Menger, m2, 2.0 / 3.0, 2.0 / 3.0, 2.0 / 3.0), 1.0 / 9.0, kEps);  // corner sub-cube's centre
    EXPECT_NEAR(prim(Primitive::Menger, m2, 0.7, 0.7, 0.9), 7.0 / 90.0, kEps);  // in that z tube: 1/9 - 1/30 to its wall
    EXPECT_NEAR(prim(Primitive::Menger, P(1.0, 0.0), 0, 0, 0), -1.0, kEps);        // 0 iterations: the cube
}

// 2D signed distance to a convex polygon given counter-clockwise (independent check of the solids of
// revolution: their distance is the distance to the cross-section in the (radius, y) half plane).
double polygon_distance(const std::vector<glm::dvec2>& poly, glm::dvec2 p) {
    double d = 1e300;
    bool inside = true;
    for (std::size_t i = 0; i < poly.size(); ++i) {
        const glm::dvec2 a = poly[i], b = poly[(i + 1) % poly.size()];
        const glm::dvec2 e = b - a, w = p - a;
        const double t = std::clamp(glm::dot(w, e) / glm::dot(e, e), 0.0, 1.0);
        d = std::min(d, glm::length(w - t * e));
        if (e.x * w.y - e.y * w.x < 0.0) inside = false;
    }
    return inside ? -d : d;
}

TEST(ReferencePrimitive, SolidsOfRevolutionMatchCrossSectionDistance) {
    Rng rng(7);
    struct Case { Primitive p; std::array<double, 4> params; std::vector<glm::dvec2> section; };
    std::vector<Case> cases;
    for (int i = 0; i < 12; ++i) {
        const double h = rng.uniform(0.1, 2.0), r1 = rng.uniform(0.0, 2.0), r2 = rng.uniform(0.0, 2.0);
        if (r1 + r2 > 0.05)
            cases.push_back({Primitive::Cone, P(h, r1, r2), {{-r1, -h}, {r1, -h}, {r2, h}, {-r2, h}}});
        const double r = rng.uniform(0.1, 2.0);
        cases.push_back({Primitive::Cylinder, P(h, r), {{-r, -h}, {r, -h}, {r, h}, {-r, h}}});
    }
    for (const Case& c : cases) {
        for (int i = 0; i < 400; ++i) {
            const glm::dvec3 p = rng.in_box(glm::dvec3(-4.0), glm::dvec3(4.0));
            const double rho = std::sqrt(p.x * p.x + p.z * p.z);
            const double expect = polygon_distance(c.section, {rho, p.y});
            ASSERT_NEAR(primitive_distance(c.p, c.params, p), expect, 1e-11)
                << to_string(c.p) << " params " << c.params[0] << " " << c.params[1] << " " << c.params[2]
                << " at " << p.x << " " << p.y << " " << p.z;
        }
    }
}

TEST(ReferencePrimitive, BoxMatchesClampFormulation) {
    Rng rng(8);
    for (int i = 0; i < 2000; ++i) {
        const glm::dvec3 b = rng.in_box(glm::dvec3(0.1), glm::dvec3(2.0));
        const glm::dvec3 p = rng.in_box(glm::dvec3(-3.0), glm::dvec3(3.0));
        const glm::dvec3 nearest = glm::clamp(p, -b, b);
        const glm::dvec3 gap = b - glm::abs(p);
        const double expect = (nearest == p) ? -std::min(gap.x, std::min(gap.y, gap.z)) : glm::length(p - nearest);
        ASSERT_NEAR(primitive_distance(Primitive::Box, P(b.x, b.y, b.z), p), expect, 1e-12);
    }
}

// ---- transforms ----

TEST(ReferenceEdit, TransformedBox) {
    // Box (1,2,3) turned +90 degrees about z (local x -> world y), scaled by 2, moved to (10,0,0):
    // world half extents (4, 2, 6).
    const Edit e = make_edit(Primitive::Box, P(1, 2, 3), Op::Add, 0.0,
                             make_transform({10, 0, 0}, kPi / 2, {0, 0, 1}, 2.0));
    EXPECT_NEAR(edit_value(e, {15, 0, 0}), 1.0, kEps);
    EXPECT_NEAR(edit_value(e, {10, 5, 0}), 3.0, kEps);
    EXPECT_NEAR(edit_value(e, {10, 0, 0}), -2.0, kEps);
    EXPECT_NEAR(edit_value(e, {14, 2, 6}), 0.0, kEps);
    EXPECT_NEAR(edit_value(e, {5, -3, 7}), std::sqrt(3.0), kEps);
    EXPECT_NEAR(edit_value(e, {10, 0, -7}), 1.0, kEps);
}

TEST(ReferenceEdit, TransformedTorus) {
    // Torus (R 2, r 0.5) turned +90 degrees about x (local y -> world z), scaled by 0.5, moved to (0,0,1):
    // a torus of radii 1 and 0.25 in the plane z = 1, around the z axis.
    const Edit e = make_edit(Primitive::Torus, P(2.0, 0.5), Op::Add, 0.0,
                             make_transform({0, 0, 1}, kPi / 2, {1, 0, 0}, 0.5));
    EXPECT_NEAR(edit_value(e, {1, 0, 1}), -0.25, kEps);
    EXPECT_NEAR(edit_value(e, {0, -1, 1}), -0.25, kEps);
    EXPECT_NEAR(edit_value(e, {0, 0, 1}), 0.75, kEps);
    EXPECT_NEAR(edit_value(e, {1, 0, 1.25}), 0.0, kEps);
    EXPECT_NEAR(edit_value(e, {0, 0, 2}), std::sqrt(2.0) - 0.25, kEps);
    EXPECT_NEAR(edit_value(e, {0, 1.5, 1}), 0.25, kEps);
}

TEST(ReferenceEdit, TransformedCapsuleAndCone) {
    // Capsule along y turned 90 degrees about z: along -x. Scale 3, at (1,2,3).
    const Edit cap = make_edit(Primitive::Capsule, P(1.0, 0.5), Op::Add, 0.0,
                               make_transform({1, 2, 3}, kPi / 2, {0, 0, 1}, 3.0));
    EXPECT_NEAR(edit_value(cap, {1, 2, 3}), -1.5, kEps);
    EXPECT_NEAR(edit_value(cap, {1 + 4.5, 2, 3}), 0.0, kEps);   // end cap: 3 * (1 + 0.5)
    EXPECT_NEAR(edit_value(cap, {1 - 5.5, 2, 3}), 1.0, kEps);
    EXPECT_NEAR(edit_value(cap, {1 + 2, 2 + 2.5, 3}), 1.0, kEps);  // beside the segment: 2.5 - 1.5
    // Cone turned 180 degrees about x: the wide end (r1) goes to the top.
    const Edit cone = make_edit(Primitive::Cone, P(1.0, 1.0, 0.5), Op::Add, 0.0,
                                make_transform({0, 0, 0}, kPi, {1, 0, 0}, 1.0));
    EXPECT_LT(edit_value(cone, {0.9, 0.99, 0}), 0.0);
    EXPECT_GT(edit_value(cone, {0.9, -0.99, 0}), 0.0);
    EXPECT_NEAR(edit_value(cone, {0, 1, 1}), 0.0, kEps);   // the wide rim (radius 1) now at y = +1
    EXPECT_NEAR(edit_value(cone, {0, -1, 0.5}), 0.0, kEps);  // the narrow rim at y = -1
}

TEST(ReferenceEdit, ValueIsScaledPrimitiveOfLocalPoint) {
    Rng rng(11);
    for (std::uint32_t k = 0; k < kAnalyticPrimitiveCount; ++k) {
        const auto p = static_cast<Primitive>(k);
        const std::array<double, 4> params = p == Primitive::Menger ? P(1.2, 3) : P(0.8, 0.6, 0.7, 0.2);
        for (int i = 0; i < 50; ++i) {
            const Transform t = [&] {
                Transform x;
                x.translation = rng.in_box(glm::dvec3(-5), glm::dvec3(5));
                x.rotation = rng.rotation();
                x.scale = rng.uniform(0.2, 4.0);
                return x;
            }();
            const Edit e = make_edit(p, params, Op::Add, 0.0, t);
            const glm::dvec3 local = rng.in_box(glm::dvec3(-2), glm::dvec3(2));
            const double expect = primitive_distance(p, params, local) * t.scale / lipschitz(e);
            EXPECT_NEAR(edit_value(e, t.apply(local)), expect, 1e-11 * (1 + std::abs(expect))) << to_string(p);
        }
    }
}

// ---- smooth minimum and combine rules ----

TEST(ReferenceCombine, SmoothMinMax) {
    for (double k : {0.1, 0.5, 1.0, 3.0}) {
        for (double a : {-2.0, -0.3, 0.0, 0.7, 5.0}) {
            // Compact support: exactly min / max once |a - b| >= k.
            for (double gap : {k, 1.5 * k, 10.0 * k}) {
                EXPECT_EQ(smooth_min(a, a + gap, k), a);
                EXPECT_EQ(smooth_min(a + gap, a, k), a);
                EXPECT_EQ(smooth_max(a, a + gap, k), a + gap);
                EXPECT_EQ(smooth_max(a + gap, a, k), a + gap);
            }
            // Deepest at a = b: k/4 below the min (above the max).
            EXPECT_NEAR(smooth_min(a, a, k), a - k / 4.0, 1e-15);
            EXPECT_NEAR(smooth_max(a, a, k), a + k / 4.0, 1e-15);
            // In between: below the min, by at most k/4; symmetric.
            for (double gap : {0.1 * k, 0.5 * k, 0.9 * k}) {
                const double s = smooth_min(a, a + gap, k);
                EXPECT_LT(s, a);
                EXPECT_GE(s, a - k / 4.0);
                EXPECT_EQ(s, smooth_min(a + gap, a, k));
                EXPECT_NEAR(smooth_max(a, a + gap, k), -smooth_min(-a, -a - gap, k), 1e-14);
            }
        }
    }
    // The empty field stays exact.
    EXPECT_EQ(smooth_min(kFar, 1.0, 0.5), 1.0);
    EXPECT_EQ(smooth_max(kFar, -1.0, 0.5), kFar);
}

TEST(ReferenceCombine, Ops) {
    EXPECT_EQ(combine(Op::Add, 0.0, 1.0, 2.0), 1.0);
    EXPECT_EQ(combine(Op::Subtract, 0.0, 1.0, 2.0), 1.0);    // max(1, -2)
    EXPECT_EQ(combine(Op::Subtract, 0.0, -1.0, -0.5), 0.5);  // max(-1, 0.5)
    EXPECT_EQ(combine(Op::Intersect, 0.0, 1.0, 2.0), 2.0);
    EXPECT_NEAR(combine(Op::Add, 1.0, 0.5, 0.5), 0.25, 1e-15);
    EXPECT_NEAR(combine(Op::Subtract, 1.0, 0.5, -0.5), 0.75, 1e-15);
    EXPECT_NEAR(combine(Op::Intersect, 1.0, 0.5, 0.5), 0.75, 1e-15);
}

// Two unit spheres: A at the origin, B at (1.5, 0, 0).
Geometry two_spheres(Op op_b, double blend) {
    Geometry g;
    g.edits.push_back(sphere_at({0, 0, 0}, 1.0));
    g.edits.push_back(sphere_at({1.5, 0, 0}, 1.0, op_b, blend));
    return g;
}

TEST(ReferenceCombine, TwoSpheres) {
    // add (union)
    EXPECT_NEAR(evaluate(two_spheres(Op::Add, 0), {-2, 0, 0}), 1.0, kEps);
    EXPECT_NEAR(evaluate(two_spheres(Op::Add, 0), {3, 0, 0}), 0.5, kEps);
    EXPECT_NEAR(evaluate(two_spheres(Op::Add, 0), {0.75, 0, 0}), -0.25, kEps);
    EXPECT_NEAR(evaluate(two_spheres(Op::Add, 0.5), {0.75, 0, 0}), -0.375, kEps);   // a = b: - k/4
    EXPECT_NEAR(evaluate(two_spheres(Op::Add, 0.5), {-2, 0, 0}), 1.0, kEps);         // |a-b| = 1.5 >= k
    EXPECT_NEAR(evaluate(two_spheres(Op::Add, 2.0), {-2, 0, 0}), 1.0 - 0.0625 * 0.5, kEps);  // h = 1/4
    // subtract: max(A, -B)
    EXPECT_NEAR(evaluate(two_spheres(Op::Subtract, 0), {0, 0, 0}), -0.5, kEps);
    EXPECT_NEAR(evaluate(two_spheres(Op::Subtract, 0), {1, 0, 0}), 0.5, kEps);
    EXPECT_NEAR(evaluate(two_spheres(Op::Subtract, 0), {-0.5, 0, 0}), -0.5, kEps);
    EXPECT_NEAR(evaluate(two_spheres(Op::Subtract, 0), {0.5, 0, 0}), 0.0, kEps);  // the carved face
    EXPECT_NEAR(evaluate(two_spheres(Op::Subtract, 1.0), {0, 0, 0}), -0.4375, kEps);  // h = 1/2
    // intersect: max(A, B)
    EXPECT_NEAR(evaluate(two_spheres(Op::Intersect, 0), {0.75, 0, 0}), -0.25, kEps);
    EXPECT_NEAR(evaluate(two_spheres(Op::Intersect, 0), {0, 0, 0}), 0.5, kEps);
    EXPECT_NEAR(evaluate(two_spheres(Op::Intersect, 0), {0.5, 0, 0}), 0.0, kEps);
    EXPECT_NEAR(evaluate(two_spheres(Op::Intersect, 1.0), {0.75, 0, 0}), 0.0, kEps);  // -0.25 + 1/4
}

TEST(ReferenceCombine, OrderMatters) {
    // A = unit sphere at the origin, B = unit sphere at (1.5,0,0) subtracted, C = sphere 0.5 at (1.5,0,0) added.
    Geometry abc, acb;
    abc.edits = {sphere_at({0, 0, 0}, 1.0), sphere_at({1.5, 0, 0}, 1.0, Op::Subtract), sphere_at({1.5, 0, 0}, 0.5)};
    acb.edits = {abc.edits[0], abc.edits[2], abc.edits[1]};
    const glm::dvec3 p(1.5, 0, 0);
    EXPECT_NEAR(evaluate(abc, p), -0.5, kEps);  // C added after the cut: solid
    EXPECT_NEAR(evaluate(acb, p), 1.0, kEps);   // C cut away by B
    // The subset overload follows the order it is given.
    const std::uint32_t order_acb[] = {0, 2, 1};
    EXPECT_EQ(evaluate(abc, std::span<const std::uint32_t>(order_acb), p), evaluate(acb, p));
    const std::uint32_t only_ac[] = {0, 2};
    Geometry ac;
    ac.edits = {abc.edits[0], abc.edits[2]};
    EXPECT_EQ(evaluate(abc, std::span<const std::uint32_t>(only_ac), glm::dvec3(0.3, 0.2, 0.1)),
              evaluate(ac, glm::dvec3(0.3, 0.2, 0.1)));
    const std::uint32_t bad[] = {3};
    EXPECT_THROW(evaluate(abc, std::span<const std::uint32_t>(bad), p), std::out_of_range);
}

TEST(ReferenceCombine, EmptyField) {
    EXPECT_EQ(kFar, 1.0e20f);
    Geometry empty;
    EXPECT_EQ(evaluate(empty, glm::dvec3(1, 2, 3)), kFar);
    EXPECT_EQ(evaluate(empty, std::span<const std::uint32_t>(), glm::dvec3(0.0)), kFar);
    // Subtracting from or intersecting with nothing leaves nothing.
    Geometry cut;
    cut.edits = {sphere_at({0, 0, 0}, 1.0, Op::Subtract), sphere_at({0, 0, 0}, 2.0, Op::Intersect, 0.5),
                 sphere_at({0, 0, 0}, 1.0, Op::Subtract, 0.5)};
    EXPECT_EQ(evaluate(cut, glm::dvec3(0.0)), kFar);
    EXPECT_EQ(evaluate(cut, glm::dvec3(5.0)), kFar);
    Scene s;
    EXPECT_EQ(evaluate(s, glm::dvec3(0.0)), kFar);
}

TEST(ReferenceCombine, SceneObjects) {
    Scene s;
    Geometry g;
    g.edits = {sphere_at({0, 0, 0}, 1.0)};
    s.geometries.push_back(g);
    Object a;
    a.geometry = 0;
    a.transform = make_transform({5, 0, 0}, 0.7, {1, 2, 3}, 2.0);  // radius 2 at (5,0,0)
    Object b;
    b.geometry = 0;
    b.transform = make_transform({-5, 0, 0}, 0.0, {0, 1, 0}, 1.0);
    s.objects = {a, b};
    EXPECT_NEAR(evaluate(s, {8, 0, 0}), 1.0, kEps);
    EXPECT_NEAR(evaluate(s, {5, 0, 0}), -2.0, kEps);
    EXPECT_NEAR(evaluate(s, {-5, 0, 0}), -1.0, kEps);
    EXPECT_NEAR(evaluate(s, {0, 0, 0}), 3.0, kEps);   // min(5 - 2, 5 - 1)
    EXPECT_NEAR(evaluate(s, {-5, 3, 0}), 2.0, kEps);
    s.objects[1].geometry = 3;
    EXPECT_THROW(evaluate(s, glm::dvec3(0.0)), std::out_of_range);
}

TEST(ReferenceCombine, Gradient) {
    Geometry g;
    g.edits = {sphere_at({1, 2, 3}, 1.0)};
    const glm::dvec3 n = gradient(g, {1, 2, 5});
    EXPECT_NEAR(n.x, 0.0, 1e-8);
    EXPECT_NEAR(n.y, 0.0, 1e-8);
    EXPECT_NEAR(n.z, 1.0, 1e-8);
    const glm::dvec3 d = glm::normalize(glm::dvec3(1, -2, 2));
    const glm::dvec3 m = gradient(g, glm::dvec3(1, 2, 3) + 0.5 * d);
    EXPECT_NEAR(glm::length(m - d), 0.0, 1e-8);
}

// ---- Lipschitz bounds ----

std::array<double, 4> random_params(Rng& rng, Primitive p) {
    switch (p) {
    case Primitive::Sphere: return P(rng.uniform(0.2, 2.0));
    // Braced lists: their elements are evaluated left to right (function arguments are not), so the
    // parameters drawn are the same with every compiler.
    case Primitive::Box: return {rng.uniform(0.05, 2), rng.uniform(0.05, 2), rng.uniform(0.05, 2), 0.0};
    case Primitive::RoundBox: {
        const double bx = rng.uniform(0.1, 2), by = rng.uniform(0.1, 2), bz = rng.uniform(0.1, 2);
        return P(bx, by, bz, rng.uniform(0.0, std::min(bx, std::min(by, bz))));
    }
    case Primitive::Torus: {
        const double R = rng.uniform(0.3, 2.0);
        return P(R, rng.uniform(0.05, 1.2 * R));
    }
    case Primitive::Capsule: return {rng.uniform(0.0, 2.0), rng.uniform(0.05, 1.0), 0.0, 0.0};
    case Primitive::Cylinder: return {rng.uniform(0.05, 2.0), rng.uniform(0.05, 2.0), 0.0, 0.0};
    case Primitive::Cone: return {rng.uniform(0.05, 2.0), rng.uniform(0.0, 2.0), rng.uniform(0.0, 2.0), 0.0};
    case Primitive::Ellipsoid: return {rng.uniform(0.05, 3), rng.uniform(0.05, 3), rng.uniform(0.05, 3), 0.0};
    case Primitive::Menger: return {rng.uniform(0.3, 2.0), std::floor(rng.uniform(1.0, 7.0)), 0.0, 0.0};
    case Primitive::Mesh: break;  // not a formula: tests/construct/test_mesh_edit.cpp
    }
    return {};
}

Transform random_transform(Rng& rng) {
    Transform t;
    t.translation = rng.in_box(glm::dvec3(-3), glm::dvec3(3));
    t.rotation = rng.rotation();
    t.scale = std::exp(rng.uniform(std::log(0.2), std::log(5.0)));
    return t;
}

// A point pair: a in the box, b at a log-uniform distance in [1e-4, 3] in a random direction.
std::pair<glm::dvec3, glm::dvec3> random_pair(Rng& rng, const glm::dvec3& lo, const glm::dvec3& hi) {
    const glm::dvec3 a = rng.in_box(lo, hi);
    const double dist = std::exp(rng.uniform(std::log(1e-4), std::log(3.0)));
    return {a, a + dist * rng.unit_vector()};
}

TEST(ReferenceLipschitz, Primitives) {
    Rng rng(21);
    for (std::uint32_t k = 0; k < kAnalyticPrimitiveCount; ++k) {
        const auto p = static_cast<Primitive>(k);
        for (int set = 0; set < 6; ++set) {
            const Edit e = make_edit(p, random_params(rng, p), Op::Add, 0.0, random_transform(rng));
            const double L = lipschitz(e);
            EXPECT_GE(L, 1.0);
            for (int i = 0; i < 3000; ++i) {
                // The primitive in its own frame: L-Lipschitz.
                const auto [a, b] = random_pair(rng, glm::dvec3(-3.0), glm::dvec3(3.0));
                const double da = primitive_distance(p, e.params, a), db = primitive_distance(p, e.params, b);
                ASSERT_LE(std::abs(da - db), L * glm::length(a - b) * (1 + 1e-9))
                    << to_string(p) << " params " << e.params[0] << " " << e.params[1] << " " << e.params[2] << " "
                    << e.params[3] << " a " << a.x << " " << a.y << " " << a.z << " b " << b.x << " " << b.y << " " << b.z;
                // The edit value in the geometry frame: 1-Lipschitz.
                const double s = e.transform.scale;
                const auto [wa, wb] = random_pair(rng, e.transform.translation - 3.0 * s, e.transform.translation + 3.0 * s);
                const double va = edit_value(e, wa), vb = edit_value(e, wb);
                ASSERT_LE(std::abs(va - vb), glm::length(wa - wb) * (1 + 1e-9)) << to_string(p);
            }
        }
    }
}

Geometry random_geometry(Rng& rng, int edits, bool allow_smooth = true, bool allow_intersect = true) {
    Geometry g;
    for (int i = 0; i < edits; ++i) {
        const auto p = static_cast<Primitive>(static_cast<std::uint32_t>(rng.uniform(0.0, double(kAnalyticPrimitiveCount))));
        Transform t = random_transform(rng);
        t.translation *= 0.3;
        t.scale = rng.uniform(0.3, 1.2);
        const double ops = allow_intersect ? 2.999 : 1.999;
        const Op op = i == 0 ? Op::Add : static_cast<Op>(static_cast<std::uint32_t>(rng.uniform(0.0, ops)));
        const double blend = allow_smooth && rng.uniform() < 0.6 ? rng.uniform(0.01, 1.0) : 0.0;
        g.edits.push_back(make_edit(p, random_params(rng, p), op, blend, t));
    }
    return g;
}

TEST(ReferenceLipschitz, BlendedGeometries) {
    Rng rng(22);
    for (int gi = 0; gi < 24; ++gi) {
        const Geometry g = random_geometry(rng, 2 + gi % 7);
        for (int i = 0; i < 2000; ++i) {
            const auto [a, b] = random_pair(rng, glm::dvec3(-3.0), glm::dvec3(3.0));
            const double fa = evaluate(g, a), fb = evaluate(g, b);
            if (fa >= kFar || fb >= kFar) continue;  // empty there (only before the first add)
            ASSERT_LE(std::abs(fa - fb), glm::length(a - b) * (1 + 1e-9)) << "geometry " << gi << " pair " << i;
        }
    }
    // Smooth adds of many nearby spheres (the blend's worst case: every input close to the others).
    Geometry blob;
    for (int i = 0; i < 12; ++i) {
        const glm::dvec3 c = rng.in_box(glm::dvec3(-0.5), glm::dvec3(0.5));
        const double r = rng.uniform(0.2, 0.5);
        const double k = rng.uniform(0.2, 1.0);
        blob.edits.push_back(sphere_at(c, r, i % 4 == 3 ? Op::Subtract : Op::Add, k));
    }
    for (int i = 0; i < 5000; ++i) {
        const auto [a, b] = random_pair(rng, glm::dvec3(-1.5), glm::dvec3(1.5));
        ASSERT_LE(std::abs(evaluate(blob, a) - evaluate(blob, b)), glm::length(a - b) * (1 + 1e-9));
    }
}

// ---- level bounds (checks scene.cpp) ----

// A radius that encloses the primitive's solid in its local frame, written here independently.
double local_radius(const Edit& e) {
    const auto& q = e.params;
    switch (e.primitive) {
    case Primitive::Sphere: return q[0];
    case Primitive::Box:
    case Primitive::RoundBox: return glm::length(glm::dvec3(q[0], q[1], q[2]));
    case Primitive::Torus: return q[0] + q[1];
    case Primitive::Capsule: return q[0] + q[1];
    case Primitive::Cylinder: return std::hypot(q[0], q[1]);
    case Primitive::Cone: return std::hypot(q[0], std::max(q[1], q[2]));
    case Primitive::Ellipsoid: return std::max(q[0], std::max(q[1], q[2]));
    case Primitive::Menger: return q[0] * std::sqrt(3.0);
    case Primitive::Mesh: break;
    }
    return 0.0;
}

bool inside(const Aabb& b, const glm::dvec3& p, double tol) {
    return p.x >= b.lo.x - tol && p.y >= b.lo.y - tol && p.z >= b.lo.z - tol && p.x <= b.hi.x + tol &&
           p.y <= b.hi.y + tol && p.z <= b.hi.z + tol;
}

TEST(ReferenceLevelBounds, PointsBelowTheLevelAreInside) {
    Rng rng(31);
    int failures = 0;
    for (std::uint32_t k = 0; k < kAnalyticPrimitiveCount; ++k) {
        const auto p = static_cast<Primitive>(k);
        for (int set = 0; set < 6; ++set) {
            Edit e = make_edit(p, random_params(rng, p), Op::Add, 0.0, random_transform(rng));
            if (set == 0) e.transform.rotation = glm::dquat(1, 0, 0, 0);  // unrotated: the bound should be tight
            for (double c : {0.0, 0.05, 0.4, 1.5}) {
                const Aabb b = level_bounds(e, c);
                ASSERT_FALSE(b.empty()) << to_string(p) << " c " << c;
                const double s = e.transform.scale;
                // Local level c*L/s reaches at most radius + c*L/s ... except for the ellipsoid's bound, whose
                // level sets grow with the axis ratio: |x/r| <= 1 + c/min(r).
                double reach = local_radius(e) + c * lipschitz(e) / s;
                if (p == Primitive::Ellipsoid) {
                    const double mn = std::min(e.params[0], std::min(e.params[1], e.params[2]));
                    reach = local_radius(e) * (1.0 + c * lipschitz(e) / s / mn);
                }
                const double R = 1.05 * s * reach + 1e-6;
                const glm::dvec3 centre = e.transform.translation;
                const double tol = 1e-9 * (1.0 + glm::length(b.extent()));
                std::vector<glm::dvec3> probes;
                // Uniform points of the enclosing cube, and points pulled onto the level set {v = c}.
                for (int i = 0; i < 1500; ++i) probes.push_back(rng.in_box(centre - R, centre + R));
                for (int i = 0; i < 1500; ++i) {
                    glm::dvec3 x = rng.in_box(centre - R, centre + R);
                    for (int it = 0; it < 30; ++it) {
                        const double f = edit_value(e, x) - c;
                        if (std::abs(f) < 1e-12) break;
                        glm::dvec3 gr;
                        for (int a = 0; a < 3; ++a) {
                            glm::dvec3 u = x, v = x;
                            u[a] += 1e-7;
                            v[a] -= 1e-7;
                            gr[a] = (edit_value(e, u) - edit_value(e, v)) / 2e-7;
                        }
                        const double g2 = glm::dot(gr, gr);
                        if (!(g2 > 1e-12)) break;
                        x -= f * gr / g2;
                    }
                    probes.push_back(x);
                }
                for (const glm::dvec3& x : probes) {
                    if (edit_value(e, x) > c) continue;
                    if (!inside(b, x, tol)) {
                        if (++failures <= 10)
                            ADD_FAILURE() << "level_bounds misses a point: " << to_string(p) << " params " << e.params[0]
                                          << " " << e.params[1] << " " << e.params[2] << " " << e.params[3] << " scale "
                                          << s << " c " << c << " point " << x.x << " " << x.y << " " << x.z
                                          << " value " << edit_value(e, x) << " bounds " << b.lo.x << " " << b.lo.y
                                          << " " << b.lo.z << " .. " << b.hi.x << " " << b.hi.y << " " << b.hi.z;
                        break;
                    }
                }
            }
        }
    }
    EXPECT_EQ(failures, 0);
}

// ---- sample points ----

TEST(ReferenceSamples, RandomPoints) {
    Rng rng(41);
    const Geometry g = random_geometry(rng, 5);
    const auto a = random_points(g, 500, 3), b = random_points(g, 500, 3), c = random_points(g, 500, 4);
    ASSERT_EQ(a.size(), 500u);
    EXPECT_EQ(a, b);
    EXPECT_NE(a, c);
    const Aabb box = sampling_box(g);
    const Aabb solid = bounds(g);
    for (int ax = 0; ax < 3; ++ax) {
        EXPECT_LT(box.lo[ax], solid.lo[ax]);
        EXPECT_GT(box.hi[ax], solid.hi[ax]);
    }
    for (const glm::dvec3& p : a) EXPECT_TRUE(inside(box, p, 0.0));
    Geometry only_cut;
    only_cut.edits = {sphere_at({0, 0, 0}, 1.0, Op::Subtract)};
    EXPECT_TRUE(random_points(only_cut, 10, 1).empty());
    EXPECT_TRUE(near_surface_points(only_cut, 10, 1, 0.1).empty());
}

TEST(ReferenceSamples, NearSurfacePoints) {
    Rng rng(42);
    for (int gi = 0; gi < 6; ++gi) {
        const Geometry g = random_geometry(rng, 1 + gi, true, false);
        const double tol = surface_tolerance(g);
        double lowest = kFar;
        for (const glm::dvec3& p : random_points(g, 2000, 1)) lowest = std::min(lowest, evaluate(g, p));
        ASSERT_LT(lowest, 0.0) << "geometry " << gi << " has no solid: pick another seed";
        const auto on = near_surface_points(g, 200, 9, 0.0);
        EXPECT_GE(on.size(), 150u) << "geometry " << gi;
        for (const glm::dvec3& p : on) ASSERT_LT(std::abs(evaluate(g, p)), tol);
        const auto near = near_surface_points(g, 200, 9, 0.05);
        EXPECT_EQ(near, near_surface_points(g, 200, 9, 0.05));
        EXPECT_NE(near, near_surface_points(g, 200, 10, 0.05));
        for (const glm::dvec3& p : near) ASSERT_LE(std::abs(evaluate(g, p)), 0.05 + 1e-9);  // 1-Lipschitz
    }
    // A sphere: on-surface points lie at the radius, offsets move along the normal.
    Geometry s;
    s.edits = {sphere_at({1, 1, 1}, 0.7)};
    for (const glm::dvec3& p : near_surface_points(s, 100, 5, 0.0))
        EXPECT_NEAR(glm::length(p - glm::dvec3(1.0)), 0.7, 1e-9);
    double spread = 0.0;
    for (const glm::dvec3& p : near_surface_points(s, 100, 5, 0.1)) {
        const double d = glm::length(p - glm::dvec3(1.0)) - 0.7;
        EXPECT_LE(std::abs(d), 0.1 + 1e-9);
        EXPECT_NEAR(evaluate(s, p), d, 1e-9);
        spread = std::max(spread, std::abs(d));
    }
    EXPECT_GT(spread, 0.05);
}

// ---- surface cells ----

Geometry unit_sphere() {
    Geometry g;
    g.edits = {sphere_at({0, 0, 0}, 1.0)};
    return g;
}

// Does the unit sphere's surface meet the closed box [lo, hi]?
bool sphere_surface_meets_box(const glm::dvec3& lo, const glm::dvec3& hi) {
    const glm::dvec3 nearest = glm::clamp(glm::dvec3(0.0), lo, hi);
    const glm::dvec3 far = glm::max(glm::abs(lo), glm::abs(hi));
    return glm::length(nearest) <= 1.0 && glm::length(far) >= 1.0;
}

struct IvecLess {
    bool operator()(const glm::ivec3& a, const glm::ivec3& b) const {
        return std::tie(a.x, a.y, a.z) < std::tie(b.x, b.y, b.z);
    }
};

TEST(ReferenceSurfaceCells, Domain) {
    Aabb b{glm::dvec3(-1.0), glm::dvec3(1.0)};
    Domain d2 = make_domain(b, 0.25, 2);
    EXPECT_EQ(d2.origin, glm::dvec3(-1.0));
    EXPECT_EQ(d2.levels, 4);  // 0.25 * 2^3 = 2
    EXPECT_EQ(d2.side(), 2.0);
    EXPECT_EQ(d2.cell_size(0), 2.0);
    EXPECT_EQ(d2.cell_size(3), 0.25);
    Domain d4 = make_domain(b, 0.25, 4);
    EXPECT_EQ(d4.levels, 3);  // 0.25 * 4^2 = 4 >= 2 > 0.25 * 4
    EXPECT_EQ(d4.side(), 4.0);
    Domain off = make_domain(Aabb{glm::dvec3(-0.3, 0.1, 2.0), glm::dvec3(0.3, 0.2, 2.01)}, 0.25, 4);
    EXPECT_EQ(off.origin, glm::dvec3(-0.5, 0.0, 2.0));
    EXPECT_EQ(off.levels, 2);  // needs 0.8 from the origin: 0.25 * 4 = 1
    EXPECT_EQ(make_domain(Aabb{glm::dvec3(0.1), glm::dvec3(0.2)}, 0.25, 2).levels, 1);
    EXPECT_THROW(make_domain(Aabb{}, 0.25, 4), InputError);
    EXPECT_THROW(make_domain(b, 0.0, 4), InputError);
    EXPECT_THROW(make_domain(b, 0.25, 3), InputError);
    EXPECT_EQ(morton_child(2, 1), glm::ivec3(1, 0, 0));
    EXPECT_EQ(morton_child(2, 6), glm::ivec3(0, 1, 1));
    EXPECT_EQ(morton_child(4, 63), glm::ivec3(3, 3, 3));
    EXPECT_EQ(morton_child(4, 8), glm::ivec3(2, 0, 0));
}

TEST(ReferenceSurfaceCells, SphereBruteForce) {
    const Geometry g = unit_sphere();
    // Both domains: origin -2, side 4, leaf 0.25 (16^3 leaves).
    Domain d2{glm::dvec3(-2.0), 0.25, 2, 5};
    Domain d4{glm::dvec3(-2.0), 0.25, 4, 3};
    ASSERT_EQ(d2.side(), d4.side());
    const auto leaves2 = surface_cells(g, d2);
    const auto leaves4 = surface_cells(g, d4);
    EXPECT_EQ(leaves2, leaves4);
    EXPECT_TRUE(std::is_sorted(leaves2.begin(), leaves2.end(), IvecLess{}));
    const std::set<glm::ivec3, IvecLess> kept(leaves2.begin(), leaves2.end());
    int crossed = 0;
    for (int x = 0; x < 16; ++x)
        for (int y = 0; y < 16; ++y)
            for (int z = 0; z < 16; ++z) {
                const glm::ivec3 c(x, y, z);
                const glm::dvec3 lo = d2.cell_lo(4, c), hi = lo + 0.25;
                if (sphere_surface_meets_box(lo, hi)) {
                    ++crossed;
                    EXPECT_TRUE(kept.count(c)) << "surface cell missing: " << x << " " << y << " " << z;
                }
                // And exactly the centre test at the leaf level (hierarchy loses nothing, adds nothing).
                const bool pass = std::abs(evaluate(g, d2.cell_centre(4, c))) <= d2.half_diagonal(4);
                EXPECT_EQ(pass, kept.count(c) == 1) << x << " " << y << " " << z;
            }
    EXPECT_GT(crossed, 100);
    EXPECT_GE(kept.size(), std::size_t(crossed));
}

TEST(ReferenceSurfaceCells, LevelsAreChildrenOfThePreviousLevel) {
    Rng rng(51);
    Geometry g = random_geometry(rng, 6);
    for (const Domain& d : {make_domain(bounds(g), 1.0 / 16, 2), make_domain(bounds(g), 1.0 / 16, 4)}) {
        const auto counts = count_surface_cells(g, d);
        const auto by_level = surface_cells_by_level(g, d);
        ASSERT_EQ(counts.size(), std::size_t(d.levels));
        ASSERT_EQ(by_level.size(), std::size_t(d.levels));
        EXPECT_EQ(counts[0], 1u);
        for (int l = 0; l < d.levels; ++l) {
            ASSERT_EQ(by_level[std::size_t(l)].size(), counts[std::size_t(l)]) << "level " << l;
            std::set<glm::ivec3, IvecLess> cells(by_level[std::size_t(l)].begin(), by_level[std::size_t(l)].end());
            EXPECT_EQ(cells.size(), by_level[std::size_t(l)].size()) << "duplicates at level " << l;
            if (l > 0) {
                EXPECT_LE(counts[std::size_t(l)], counts[std::size_t(l) - 1] * std::uint64_t(d.branching) * d.branching *
                                                      d.branching);
                std::set<glm::ivec3, IvecLess> parents(by_level[std::size_t(l) - 1].begin(),
                                                       by_level[std::size_t(l) - 1].end());
                for (const glm::ivec3& c : cells) {
                    ASSERT_TRUE(parents.count(c / d.branching)) << "orphan at level " << l;
                    // Every kept cell passes its own test.
                    ASSERT_LE(std::abs(evaluate(g, d.cell_centre(l, c))), d.half_diagonal(l));
                }
            }
            // Brute force over the whole level (small levels only): the kept set is exactly the cells passing.
            if (d.cells_per_axis(l) <= 32) {
                const int n = int(d.cells_per_axis(l));
                std::size_t passing = 0;
                for (int x = 0; x < n; ++x)
                    for (int y = 0; y < n; ++y)
                        for (int z = 0; z < n; ++z)
                            if (std::abs(evaluate(g, d.cell_centre(l, {x, y, z}))) <= d.half_diagonal(l)) {
                                ++passing;
                                EXPECT_TRUE(cells.count({x, y, z}));
                            }
                EXPECT_EQ(passing, cells.size()) << "level " << l;
            }
        }
        // Construction order: children of one parent appear together, in Morton order.
        for (int l = 1; l < d.levels; ++l) {
            const auto& v = by_level[std::size_t(l)];
            for (std::size_t i = 1; i < v.size(); ++i) {
                const glm::ivec3 pa = v[i - 1] / d.branching, pb = v[i] / d.branching;
                if (pa == pb) {
                    auto morton = [&](glm::ivec3 c) {
                        const glm::ivec3 lc = c - pa * d.branching;
                        for (int m = 0; m < d.branching * d.branching * d.branching; ++m)
                            if (morton_child(d.branching, m) == lc) return m;
                        return -1;
                    };
                    ASSERT_LT(morton(v[i - 1]), morton(v[i]));
                }
            }
        }
        EXPECT_EQ(surface_cells(g, d).size(), counts.back());
        // Independent of the thread count.
        EXPECT_EQ(count_surface_cells(g, d, 1), counts);
        EXPECT_EQ(surface_cells_by_level(g, d, 3), by_level);
    }
}

TEST(ReferenceSurfaceCells, BranchingTwoAndFourAgree) {
    // Unit sphere, leaf 1/32: make_domain gives origin -1, side 2 for both (2^6 = 4^3 = 64 leaves per axis).
    const Geometry g = unit_sphere();
    const Aabb b = bounds(g);
    const Domain d2 = make_domain(b, 1.0 / 32, 2), d4 = make_domain(b, 1.0 / 32, 4);
    ASSERT_EQ(d2.origin, d4.origin);
    ASSERT_EQ(d2.side(), d4.side());
    EXPECT_EQ(d2.levels, 7);
    EXPECT_EQ(d4.levels, 4);
    const auto c2 = count_surface_cells(g, d2), c4 = count_surface_cells(g, d4);
    EXPECT_EQ(c2.back(), c4.back());
    // Levels of equal cell size agree too: B=2 level 2l is B=4 level l.
    for (int l = 0; l < d4.levels; ++l) EXPECT_EQ(c2[std::size_t(2 * l)], c4[std::size_t(l)]) << "level " << l;
    EXPECT_EQ(surface_cells(g, d2), surface_cells(g, d4));
    // A blended geometry, same check.
    Rng rng(52);
    Geometry r = random_geometry(rng, 8);
    const Aabb rb = bounds(r);
    Domain e4 = make_domain(rb, 1.0 / 16, 4);
    Domain e2 = e4;
    e2.branching = 2;
    e2.levels = 2 * (e4.levels - 1) + 1;
    ASSERT_EQ(e2.side(), e4.side());
    EXPECT_EQ(surface_cells(r, e2), surface_cells(r, e4));
}

TEST(ReferenceSurfaceCells, Timing) {
    // 64 smooth-added spheres and a few subtractions in [-1, 1]^3, leaf 1/64, B = 4.
    Rng rng(61);
    Geometry g;
    for (int i = 0; i < 64; ++i) {
        const glm::dvec3 c = rng.in_box(glm::dvec3(-0.7), glm::dvec3(0.7));
        const double r = rng.uniform(0.05, 0.3);
        g.edits.push_back(sphere_at(c, r, i % 8 == 7 ? Op::Subtract : Op::Add, 0.05));
    }
    const Domain d = make_domain(bounds(g), 1.0 / 64, 4);
    const auto t0 = std::chrono::steady_clock::now();
    const auto counts = count_surface_cells(g, d);
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::uint64_t tested = 1;
    for (std::size_t l = 0; l + 1 < counts.size(); ++l) tested += counts[l] * 64;
    std::printf("[ timing   ] count_surface_cells: %zu edits, %d levels, leaves %llu, %llu centres tested, %.3f s "
                "(%.1f M edit evaluations/s, %u threads)\n",
                g.edits.size(), d.levels, static_cast<unsigned long long>(counts.back()),
                static_cast<unsigned long long>(tested), s, double(tested) * double(g.edits.size()) / s * 1e-6,
                std::thread::hardware_concurrency());
    EXPECT_GT(counts.back(), 1000u);
}

}  // namespace
}  // namespace sdfbrick::reference
