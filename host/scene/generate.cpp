#include "scene/generate.h"

#include <algorithm>
#include <array>
#include <cmath>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <glm/gtc/constants.hpp>

#include "core/errors.h"
#include "core/hash.h"

namespace sdfbrick {

namespace {

constexpr std::array<std::string_view, 28> kNames = {
    "spheres", "drops", "cubes", "rain", "fractal", "board", "thin", "sculpt", "rubble", "sculpt_dense",
    // The stability atlas's hard cases (docs/stability.md), one failure mode each.
    "stability/grazing_plane", "stability/grazing_cylinder", "stability/sub_voxel", "stability/blend_tiny",
    "stability/blend_huge", "stability/ellipsoid", "stability/menger6", "stability/instance_stack",
    "stability/far", "stability/camera_inside", "stability/camera_on_face", "stability/face_rays",
    "stability/edits_65536", "stability/instances_10000",
    // Adaptive builds' hard cases: large flat regions beside small detail.
    "stability/ground_trees", "stability/engraved_slab", "stability/grooved_board", "stability/steep_blends"};

// Files keep 4 decimals: readable, and what is generated is exactly what is loaded back.
double r4(double v) { return std::round(v * 1e4) / 1e4; }
glm::dvec3 r4(const glm::dvec3& v) { return {r4(v.x), r4(v.y), r4(v.z)}; }
// Unit to rounding, w >= 0: the file reader keeps such a quaternion bit for bit.
glm::dquat unit(glm::dquat q) {
    q = glm::normalize(q);
    return q.w < 0 ? -q : q;
}

Edit make_edit(Primitive prim, std::array<double, 4> params, const glm::dvec3& pos) {
    Edit e;
    e.primitive = prim;
    for (auto& p : params) p = r4(p);
    e.params = params;
    e.transform.translation = r4(pos);
    return e;
}

Scene finish(std::string name, double time, Geometry g, Camera cam) {
    Scene s;
    s.name = name;
    s.time = time;
    g.name = std::move(name);
    s.geometries.push_back(std::move(g));
    s.objects.push_back(Object{s.geometries[0].name, 0, Transform{}});
    s.camera = cam;
    s.light = Light{{-0.4, -1.0, -0.3}, {1.0, 1.0, 1.0}, 1.0};
    return s;
}

// Falls at `speed` and re-enters at the top of [lo, hi).
Animation falling(double speed, double lo, double hi) {
    Animation a;
    a.velocity = r4(glm::dvec3(0.0, -speed, 0.0));
    a.wrap_y = std::array<double, 2>{lo, hi};
    return a;
}

// Every draw is its own statement or inside a braced list (both evaluated in order): function
// arguments are evaluated in an unspecified order, which would make the scenes compiler-dependent.
glm::dvec3 jitter(Rng& rng, double r) { return rng.in_box(glm::dvec3(-r), glm::dvec3(r)); }

// Calls f(cell, centre) for the n^3 cells of a lattice centred on the origin, x fastest; each
// centre is moved by up to `r` on each axis.
template <class F>
void for_lattice(Rng& rng, int n, double spacing, double r, F&& f) {
    for (int z = 0; z < n; ++z)
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x) {
                const glm::ivec3 cell(x, y, z);
                f(cell, (glm::dvec3(cell) - 0.5 * (n - 1)) * spacing + jitter(rng, r));
            }
}

Camera orbit(glm::dvec3 target, double distance, double yaw, double pitch) {
    Camera c;
    c.kind = Camera::Kind::Orbit;
    c.target = target;
    c.distance = distance;
    c.yaw_deg = yaw;
    c.pitch_deg = pitch;
    return c;
}

// The fidelity scene: two spheres smoothly blended (source document 000, figure 8).
Scene spheres(Rng&) {
    Geometry g;
    Edit a = make_edit(Primitive::Sphere, {1.0, 0, 0, 0}, {-0.7, 0.0, 0.0});
    Edit b = make_edit(Primitive::Sphere, {0.8, 0, 0, 0}, {0.8, 0.25, 0.0});
    b.blend = 0.5;
    g.edits = {a, b};
    return finish("spheres", 0.0, g, orbit({0.0, 0.1, 0.0}, 5.0, 20.0, 15.0));
}

// 1024 falling drops, heavily smooth-blended, inside a column that they wrap around in.
Scene drops(Rng& rng) {
    Geometry g;
    const double lo = -3.0, hi = 3.0;
    for (int i = 0; i < 1024; ++i) {
        const glm::dvec3 pos = rng.in_box({-3.2, lo, -3.2}, {3.2, hi, 3.2});
        Edit e = make_edit(Primitive::Sphere, {rng.uniform(0.12, 0.34), 0, 0, 0}, pos);
        e.blend = r4(rng.uniform(0.15, 0.3));
        e.animation = falling(rng.uniform(0.3, 0.9), lo, hi);
        g.edits.push_back(e);
    }
    return finish("drops", 5.0, g, orbit({0.0, 0.0, 0.0}, 14.0, 30.0, 20.0));
}

// 216 edits on a 6^3 lattice: thin plates, beams and hollow cubes, mostly empty space between.
Scene cubes(Rng& rng) {
    Geometry g;
    for_lattice(rng, 6, 1.6, 0.2, [&](const glm::ivec3& cell, const glm::dvec3& pos) {
        Edit e;
        switch ((cell.x + cell.y + cell.z) % 3) {
            case 0:  // plate
                e = make_edit(Primitive::Box, {rng.uniform(0.45, 0.7), 0.04, rng.uniform(0.45, 0.7), 0}, pos);
                break;
            case 1:  // beam
                e = make_edit(Primitive::Box, {0.05, rng.uniform(0.5, 0.75), 0.05, 0}, pos);
                break;
            default: {  // rounded cube
                const double s = rng.uniform(0.3, 0.5);
                e = make_edit(Primitive::RoundBox, {s, s, s, 0.05}, pos);
            }
        }
        e.transform.rotation = unit(rng.rotation());
        g.edits.push_back(e);
    });
    return finish("cubes", 0.0, g, orbit({0.0, 0.0, 0.0}, 16.0, 35.0, 25.0));
}

// 512 falling edits of varied sizes in clusters of different densities: streaks (capsules),
// drops (spheres, ellipsoids); some streaks blend into their neighbours.
Scene rain(Rng& rng) {
    Geometry g;
    const double lo = -3.5, hi = 3.5;
    struct Cluster { glm::dvec3 centre; double spread; int count; };
    const std::array<Cluster, 4> clusters = {{{{-2.0, 0.0, -1.5}, 0.9, 220},
                                              {{1.8, 0.0, 1.2}, 1.6, 160},
                                              {{1.5, 0.0, -2.2}, 0.6, 80},
                                              {{-1.5, 0.0, 2.3}, 2.4, 52}}};
    for (const Cluster& c : clusters)
        for (int i = 0; i < c.count; ++i) {
            const glm::dvec3 pos = rng.in_box({c.centre.x - c.spread, lo, c.centre.z - c.spread},
                                              {c.centre.x + c.spread, hi, c.centre.z + c.spread});
            const double size = std::pow(rng.uniform(), 2.0);  // many small, few large
            const double pick = rng.uniform();
            Edit e;
            if (pick < 0.6) {
                e = make_edit(Primitive::Capsule, {0.18 + 0.8 * size, 0.08 + 0.2 * size, 0, 0}, pos);
                const double tilt_x = rng.uniform(-0.25, 0.25);
                const double tilt_z = rng.uniform(-0.25, 0.25);
                e.transform.rotation = unit(glm::angleAxis(tilt_x, glm::dvec3(1.0, 0.0, 0.0)) *
                                            glm::angleAxis(tilt_z, glm::dvec3(0.0, 0.0, 1.0)));
            } else if (pick < 0.85) {
                e = make_edit(Primitive::Sphere, {0.14 + 0.45 * size, 0, 0, 0}, pos);
            } else {
                const double r = 0.17 + 0.5 * size;
                e = make_edit(Primitive::Ellipsoid, {r, r * rng.uniform(1.2, 2.0), r, 0}, pos);
            }
            if (rng.uniform() < 0.3) e.blend = r4(rng.uniform(0.05, 0.2));
            e.animation = falling(rng.uniform(1.5, 3.0), lo, hi);
            g.edits.push_back(e);
        }
    return finish("rain", 5.0, g, orbit({0.0, 0.0, 0.0}, 15.0, 25.0, 15.0));
}

// 64 Menger sponges (3 or 4 iterations): few edits, each expensive, with fine structure.
Scene fractal(Rng& rng) {
    Geometry g;
    for_lattice(rng, 4, 1.5, 0.15, [&](const glm::ivec3&, const glm::dvec3& pos) {
        Edit e = make_edit(Primitive::Menger, {rng.uniform(0.42, 0.56), rng.uniform() < 0.5 ? 3.0 : 4.0, 0, 0}, pos);
        e.transform.rotation = unit(rng.rotation());
        g.edits.push_back(e);
    });
    return finish("fractal", 0.0, g, orbit({0.0, 0.0, 0.0}, 10.0, 30.0, 25.0));
}

// Hard CSG with little volume: a flat 8.4 x 0.2 x 8.4 board with grooves cut along both axes and
// across at random angles, and holes drilled through it. Its surface needs few bricks for a
// domain of 8.4^3: a coarse level kept dense would cost the volume, not the surface.
Scene board(Rng& rng) {
    Geometry g;
    g.edits.push_back(make_edit(Primitive::Box, {4.2, 0.1, 4.2, 0}, {0.0, 0.0, 0.0}));
    for (int i = 0; i < 12; ++i) {  // straight grooves on the top face, 6 along x and 6 along z
        const double at = -3.5 + 1.4 * (i % 6) + rng.uniform(-0.2, 0.2);
        const double width = rng.uniform(0.03, 0.08), depth = rng.uniform(0.03, 0.08);
        const bool along_x = i < 6;
        Edit e = make_edit(Primitive::Box, {along_x ? 4.4 : width, depth, along_x ? width : 4.4, 0},
                           {along_x ? 0.0 : at, 0.1, along_x ? at : 0.0});
        e.op = Op::Subtract;
        g.edits.push_back(e);
    }
    for (int i = 0; i < 4; ++i) {  // slanted grooves on the bottom face
        const std::array<double, 4> size{4.0, rng.uniform(0.03, 0.06), rng.uniform(0.02, 0.05), 0};
        const glm::dvec3 at{rng.uniform(-1.0, 1.0), -0.1, rng.uniform(-2.0, 2.0)};
        Edit e = make_edit(Primitive::Box, size, at);
        e.transform.rotation = unit(glm::angleAxis(rng.uniform(0.2, 1.3), glm::dvec3(0.0, 1.0, 0.0)));
        e.op = Op::Subtract;
        g.edits.push_back(e);
    }
    for (int i = 0; i < 8; ++i) {  // holes drilled through
        const double radius = rng.uniform(0.05, 0.2);
        const glm::dvec3 at{rng.uniform(-3.8, 3.8), 0.0, rng.uniform(-3.8, 3.8)};
        Edit e = make_edit(Primitive::Cylinder, {0.3, radius, 0, 0}, at);
        e.op = Op::Subtract;
        g.edits.push_back(e);
    }
    return finish("board", 0.0, g, orbit({0.0, 0.0, 0.0}, 11.0, 30.0, 35.0));
}

// Features thinner than a voxel of a 0.0625 brick (0.0104) beside large smooth surfaces: plates
// 0.008 thick, needles of radius 0.003, a shell 0.01 thick, standing on a large sphere. A uniform
// build at 0.0625 steps over the thin parts; an adaptive one refines only around them.
Scene thin(Rng& rng) {
    Geometry g;
    g.edits.push_back(make_edit(Primitive::Sphere, {1.2, 0, 0, 0}, {0.0, -1.0, 0.0}));  // the ground: large, smooth
    Edit shell = make_edit(Primitive::Sphere, {0.45, 0, 0, 0}, {-0.9, 0.5, 0.3});
    Edit hollow = make_edit(Primitive::Sphere, {0.44, 0, 0, 0}, {-0.9, 0.5, 0.3});
    hollow.op = Op::Subtract;
    Edit window = make_edit(Primitive::Box, {0.5, 0.5, 0.5, 0}, {-0.9, 0.5, 0.8});  // cut open to show the shell
    window.op = Op::Subtract;
    g.edits.insert(g.edits.end(), {shell, hollow, window});
    for (int i = 0; i < 5; ++i) {  // plates 0.008 thick at varied angles
        const std::array<double, 4> size{rng.uniform(0.2, 0.35), 0.004, rng.uniform(0.2, 0.35), 0};
        const glm::dvec3 at{0.2 + 0.25 * i, 0.45 + rng.uniform(-0.1, 0.1), -0.4 + rng.uniform(-0.2, 0.2)};
        Edit e = make_edit(Primitive::Box, size, at);
        const double angle = rng.uniform(0.3, 1.3);
        const glm::dvec3 axis = rng.in_box(glm::dvec3(-1.0), glm::dvec3(1.0)) + glm::dvec3(0.0, 0.0, 1e-3);
        e.transform.rotation = unit(glm::angleAxis(angle, glm::normalize(axis)));
        g.edits.push_back(e);
    }
    for (int i = 0; i < 12; ++i) {  // needles of radius 0.003
        const double half = rng.uniform(0.15, 0.35);
        const glm::dvec3 at{rng.uniform(-0.3, 1.2), rng.uniform(0.35, 0.6), rng.uniform(0.2, 0.9)};
        Edit e = make_edit(Primitive::Capsule, {half, 0.003, 0, 0}, at);
        const double tilt = rng.uniform(0.0, 1.5), turn = rng.uniform(0.0, 3.1);
        e.transform.rotation = unit(glm::angleAxis(tilt, glm::dvec3(1.0, 0.0, 0.0)) *
                                    glm::angleAxis(turn, glm::dvec3(0.0, 1.0, 0.0)));
        g.edits.push_back(e);
    }
    return finish("thin", 0.0, g, orbit({0.1, 0.4, 0.2}, 3.2, 20.0, 20.0));
}

// The rotation that takes the primitive's +y axis to the unit vector `dir`.
glm::dquat y_to(const glm::dvec3& dir) {
    const glm::dvec3 y(0.0, 1.0, 0.0);
    const glm::dvec3 axis = glm::cross(y, dir);
    const double s = glm::length(axis);
    if (s < 1e-9) return dir.y > 0 ? glm::dquat(1.0, 0.0, 0.0, 0.0) : glm::dquat(0.0, 1.0, 0.0, 0.0);
    return unit(glm::angleAxis(std::atan2(s, glm::dot(y, dir)), axis / s));
}

// A sculpted ball: `strokes` brush strokes of 8 smoothly blended capsule segments each, walking
// over a sphere of radius 2; a quarter of the strokes carve.
Geometry sculpted_ball(Rng& rng, int strokes) {
    Geometry g;
    const double ball = 2.0;
    g.edits.push_back(make_edit(Primitive::Sphere, {ball, 0, 0, 0}, {0.0, 0.0, 0.0}));
    for (int stroke = 0; stroke < strokes; ++stroke) {
        glm::dvec3 at = rng.unit_vector();
        glm::dvec3 dir = glm::normalize(glm::cross(at, rng.unit_vector()));
        const double radius = rng.uniform(0.03, 0.07), blend = r4(rng.uniform(0.03, 0.08));
        const bool carve = rng.uniform() < 0.25;
        for (int seg = 0; seg < 8; ++seg) {
            Edit e = make_edit(Primitive::Capsule, {0.08, radius, 0, 0}, at * (ball + rng.uniform(-0.01, 0.01)));
            e.transform.rotation = y_to(dir);
            e.op = carve ? Op::Subtract : Op::Add;
            e.blend = blend;
            g.edits.push_back(e);
            // Step along the stroke, back onto the ball, and turn a little within its tangent plane.
            at = glm::normalize(at + 0.07 * dir);
            dir = glm::normalize(dir + jitter(rng, 0.3));
            dir = glm::normalize(dir - glm::dot(dir, at) * at);
        }
    }
    return g;
}

// 1024 strokes (8,193 edits): every sample near the surface sees tens of small edits, the heavy
// edit-list case.
Scene sculpt(Rng& rng) { return finish("sculpt", 0.0, sculpted_ball(rng, 1024), orbit({0.0, 0.0, 0.0}, 7.0, 30.0, 20.0)); }

// 8,191 strokes (65,529 edits, all but the most a geometry may have) on the same ball: hundreds of
// edits per leaf, and lists of tens of thousands at the top levels, where count and cull fold them.
Scene sculpt_dense(Rng& rng) {
    return finish("sculpt_dense", 0.0, sculpted_ball(rng, 8191), orbit({0.0, 0.0, 0.0}, 7.0, 30.0, 20.0));
}

// drops' long lists without a sphere: 1024 smoothly blended, rotated boxes, round boxes, tori and
// ellipsoids in the same volume (the evaluation skips far spheres and capsules, not these).
Scene rubble(Rng& rng) {
    Geometry g;
    for (int i = 0; i < 1024; ++i) {
        const glm::dvec3 pos = rng.in_box(glm::dvec3(-3.2), glm::dvec3(3.2));
        const double s = rng.uniform(0.14, 0.26);
        Edit e;
        switch (i % 4) {
            case 0: {
                const glm::dvec3 b{s * rng.uniform(0.6, 1.2), s * rng.uniform(0.6, 1.2), s * rng.uniform(0.6, 1.2)};
                e = make_edit(Primitive::Box, {b.x, b.y, b.z, 0}, pos);
                break;
            }
            case 1: e = make_edit(Primitive::RoundBox, {s, s, s, 0.3 * s}, pos); break;
            case 2: e = make_edit(Primitive::Torus, {s, 0.35 * s, 0, 0}, pos); break;
            default: {
                const glm::dvec3 r{s * rng.uniform(0.5, 1.2), s * rng.uniform(0.5, 1.2), s * rng.uniform(0.5, 1.2)};
                e = make_edit(Primitive::Ellipsoid, {r.x, r.y, r.z, 0}, pos);
            }
        }
        e.transform.rotation = unit(rng.rotation());
        e.blend = r4(rng.uniform(0.15, 0.25));
        g.edits.push_back(e);
    }
    return finish("rubble", 0.0, g, orbit({0.0, 0.0, 0.0}, 14.0, 30.0, 20.0));
}

// ---- the stability atlas's hard cases (docs/stability.md) ----
// Sizes are chosen against the voxel the atlas and its tests build with: bricks of 0.125 (voxel
// 0.0208; 0.5 for the 65,536 edits). Lattice coordinates (multiples of 0.25) lie on brick faces for
// any brick size dividing 0.25: a domain's origin is on the leaf lattice (construct/domain.h).

Camera look_at(glm::dvec3 eye, glm::dvec3 target, double fov_deg) {
    Camera c;
    c.kind = Camera::Kind::LookAt;
    c.eye = eye;
    c.target = target;
    c.fov_deg = fov_deg;
    return c;
}

Edit subtracted(Edit e) {
    e.op = Op::Subtract;
    return e;
}

// A flat 8 x 0.2 x 8 slab seen from 0.5 degrees above its top face: the centre ray meets it at 89.5
// degrees from its normal, and every ray below runs along it for many bricks.
Scene grazing_plane(Rng&) {
    Geometry g;
    g.edits.push_back(make_edit(Primitive::Box, {4.0, 0.1, 4.0, 0}, {0.0, 0.0, 0.0}));
    Camera c = orbit({0.0, 0.1, 0.0}, 12.0, 20.0, 0.5);
    c.fov_deg = 30.0;
    return finish("grazing_plane", 0.0, g, c);
}

// A cylinder 6 long and 0.08 in radius seen end-on from just off its axis: the cap faces the camera,
// the side is met at grazing angles along its whole length.
Scene grazing_cylinder(Rng&) {
    Geometry g;
    Edit e = make_edit(Primitive::Cylinder, {3.0, 0.08, 0, 0}, {0.0, 0.0, 0.0});
    e.transform.rotation = unit(glm::angleAxis(glm::half_pi<double>(), glm::dvec3(1.0, 0.0, 0.0)));
    g.edits.push_back(e);
    return finish("grazing_cylinder", 0.0, g, look_at({0.03, 0.05, 5.0}, {0.0, 0.0, -3.0}, 10.0));
}

// Plates 0.006 thick, needles of radius 0.002 and a shell 0.005 thick on a ground slab: every one
// thinner than the finest voxel either build uses.
Scene sub_voxel(Rng& rng) {
    Geometry g;
    g.edits.push_back(make_edit(Primitive::Box, {1.5, 0.05, 1.5, 0}, {0.0, -0.05, 0.0}));
    g.edits.push_back(make_edit(Primitive::Sphere, {0.4, 0, 0, 0}, {-0.7, 0.45, -0.3}));
    g.edits.push_back(subtracted(make_edit(Primitive::Sphere, {0.395, 0, 0, 0}, {-0.7, 0.45, -0.3})));
    g.edits.push_back(subtracted(make_edit(Primitive::Box, {0.5, 0.5, 0.5, 0}, {-0.7, 0.45, 0.2})));
    for (int i = 0; i < 6; ++i) {  // plates
        const std::array<double, 4> size{rng.uniform(0.15, 0.3), 0.003, rng.uniform(0.15, 0.3), 0};
        const glm::dvec3 at{-0.1 + 0.25 * i, 0.35 + rng.uniform(-0.1, 0.1), -0.5 + rng.uniform(-0.2, 0.2)};
        Edit e = make_edit(Primitive::Box, size, at);
        const double angle = rng.uniform(0.3, 1.3);
        const glm::dvec3 axis = rng.in_box(glm::dvec3(-1.0), glm::dvec3(1.0)) + glm::dvec3(0.0, 0.0, 1e-3);
        e.transform.rotation = unit(glm::angleAxis(angle, glm::normalize(axis)));
        g.edits.push_back(e);
    }
    for (int i = 0; i < 12; ++i) {  // needles
        const double half = rng.uniform(0.15, 0.35);
        const glm::dvec3 at{rng.uniform(-0.3, 1.0), rng.uniform(0.3, 0.5), rng.uniform(0.1, 0.8)};
        Edit e = make_edit(Primitive::Capsule, {half, 0.002, 0, 0}, at);
        const double tilt = rng.uniform(0.0, 1.5), turn = rng.uniform(0.0, 3.1);
        e.transform.rotation = unit(glm::angleAxis(tilt, glm::dvec3(1.0, 0.0, 0.0)) *
                                    glm::angleAxis(turn, glm::dvec3(0.0, 1.0, 0.0)));
        g.edits.push_back(e);
    }
    return finish("sub_voxel", 0.0, g, orbit({0.1, 0.3, 0.1}, 3.0, 25.0, 25.0));
}

// Two spheres of radius 0.5 exactly touching, the second blended with radius `blend`.
Scene touching(std::string name, double blend, double distance) {
    Geometry g;
    g.edits.push_back(make_edit(Primitive::Sphere, {0.5, 0, 0, 0}, {-0.5, 0.0, 0.0}));
    Edit b = make_edit(Primitive::Sphere, {0.5, 0, 0, 0}, {0.5, 0.0, 0.0});
    b.blend = blend;
    g.edits.push_back(b);
    return finish(std::move(name), 0.0, g, orbit({0.0, 0.0, 0.0}, distance, 10.0, 15.0));
}

// A blend of 0.001: a neck far thinner than a voxel where the spheres meet.
Scene blend_tiny(Rng&) { return touching("blend_tiny", 0.001, 3.0); }

// A blend of 6, twelve times the radius: the edit reaches 6 units out, every brick of the domain is
// in its range (culling's worst case), and the union swells to a blob of radius about 2.
Scene blend_huge(Rng&) { return touching("blend_huge", 6.0, 8.0); }

// An ellipsoid of semi-axes 3, 0.5 and 0.03 (100:1): its field is a bound that underestimates the
// distance up to 100 times, so sphere steps near its rim are short.
Scene ellipsoid(Rng&) {
    Geometry g;
    Edit e = make_edit(Primitive::Ellipsoid, {3.0, 0.5, 0.03, 0}, {0.0, 0.0, 0.0});
    e.transform.rotation = unit(glm::angleAxis(0.4, glm::normalize(glm::dvec3(1.0, 2.0, 0.5))));
    g.edits.push_back(e);
    return finish("ellipsoid", 0.0, g, orbit({0.0, 0.0, 0.0}, 7.5, 40.0, 30.0));
}

// One Menger sponge of 6 iterations: holes down to 2/729 of its size, far below a voxel.
Scene menger6(Rng&) {
    Geometry g;
    Edit e = make_edit(Primitive::Menger, {1.0, 6.0, 0, 0}, {0.0, 0.0, 0.0});
    e.transform.rotation = unit(glm::angleAxis(0.3, glm::dvec3(0.0, 1.0, 0.0)));
    g.edits.push_back(e);
    return finish("menger6", 0.0, g, orbit({0.0, 0.0, 0.0}, 4.5, 30.0, 25.0));
}

// One shape (a rounded box in a blended ring, every part several voxels thick) at scales 1e-3, 1e-2,
// ..., 1e3, each rotated and at 5 times its scale from the eye, so
// that all seven look the same size, in a ring around the view's centre. Each scale is an object of
// its own copy of the geometry, so that a pixel's depth error is measured in the voxels of the
// object it shows (a brick tells its geometry, not its instance).
Scene instance_stack(Rng& rng) {
    Geometry g;
    g.edits.push_back(make_edit(Primitive::RoundBox, {0.35, 0.35, 0.35, 0.1}, {0.0, 0.0, 0.0}));
    Edit ring = make_edit(Primitive::Torus, {0.5, 0.08, 0, 0}, {0.0, 0.0, 0.0});
    ring.blend = 0.05;
    g.edits.push_back(ring);
    Scene s = finish("instance_stack", 0.0, g, look_at({0.0, 0.0, 0.0}, {0.0, 0.0, -1.0}, 60.0));
    s.geometries.clear();
    s.objects.clear();
    for (int k = -3; k <= 3; ++k) {
        const double scale = std::pow(10.0, k);
        const double angle = 2.0 * glm::pi<double>() * (k + 3) / 7.0;
        Transform t;
        t.scale = scale;
        t.rotation = unit(rng.rotation());
        t.translation = r4(5.0 * scale * glm::dvec3(0.3 * std::cos(angle), 0.3 * std::sin(angle), -1.0));
        g.name = fmt::format("scale_1e{}", k);
        s.geometries.push_back(g);
        s.objects.push_back(Object{g.name, s.geometries.size() - 1, t});
    }
    return s;
}

// Geometry 1e4 units from the origin, seen from 1e3 units away through a 1 degree field of view:
// positions, brick corners and ray origins keep about 1e-3 of absolute precision in float.
Scene far(Rng& rng) {
    Geometry g;
    const glm::dvec3 at{1.0e4, 0.0, 0.0};
    g.edits.push_back(make_edit(Primitive::RoundBox, {2.0, 0.2, 2.0, 0.1}, at + glm::dvec3(0.0, -0.6, 0.0)));
    for (int i = 0; i < 5; ++i) {
        const glm::dvec3 p = at + glm::dvec3(rng.uniform(-1.5, 1.5), rng.uniform(-0.2, 0.4), rng.uniform(-1.5, 1.5));
        Edit e = make_edit(Primitive::Sphere, {rng.uniform(0.2, 0.5), 0, 0, 0}, p);
        e.blend = 0.2;
        g.edits.push_back(e);
    }
    Camera c = orbit(at + glm::dvec3(0.0, -0.3, 0.0), 1.0e3, 35.0, 20.0);
    c.fov_deg = 1.0;
    return finish("far", 0.0, g, c);
}

// The eye 1.2 units deep inside a solid sphere of radius 2 with cavities: no brick holds the eye,
// and every ray starts in solid material.
Scene camera_inside(Rng& rng) {
    Geometry g;
    g.edits.push_back(make_edit(Primitive::Sphere, {2.0, 0, 0, 0}, {0.0, 0.0, 0.0}));
    for (int i = 0; i < 8; ++i) {
        glm::dvec3 p = rng.unit_vector() * rng.uniform(0.9, 1.4);
        p.z = -std::abs(p.z);  // in front of the eye
        g.edits.push_back(subtracted(make_edit(Primitive::Sphere, {rng.uniform(0.2, 0.4), 0, 0, 0}, p)));
    }
    return finish("camera_inside", 0.0, g, look_at({0.0, 0.0, 0.8}, {0.0, 0.0, -1.0}, 70.0));
}

// The eye at (0.5, 0.5, 1), a corner of the brick lattice, 0.03 above a slab's top face: the eye
// lies on the faces of the surface bricks under it, and rays start on brick boundaries.
Scene camera_on_face(Rng& rng) {
    Geometry g;
    g.edits.push_back(make_edit(Primitive::Box, {2.0, 0.25, 2.5, 0}, {0.5, 0.22, -0.5}));
    for (int i = 0; i < 6; ++i) {
        const glm::dvec3 p{rng.uniform(-0.5, 1.5), 0.55, rng.uniform(-2.5, 0.0)};
        Edit e = make_edit(Primitive::Sphere, {rng.uniform(0.1, 0.25), 0, 0, 0}, p);
        e.blend = 0.1;
        g.edits.push_back(e);
    }
    return finish("camera_on_face", 0.0, g, look_at({0.5, 0.5, 1.0}, {0.5, 0.3, -2.0}, 60.0));
}

// Boxes whose faces lie on the brick lattice (multiples of 0.25), seen from (0, 0.25, 3) along -z:
// with an odd image size the centre column's rays lie in the plane x = 0 and the centre row's in
// y = 0.25, both brick faces and box faces, and the centre ray runs along a box edge.
Scene face_rays(Rng& rng) {
    Geometry g;
    g.edits.push_back(make_edit(Primitive::Box, {2.0, 0.25, 2.0, 0}, {0.0, -0.5, -1.0}));
    g.edits.push_back(make_edit(Primitive::Box, {0.5, 0.25, 0.5, 0}, {0.5, 0.0, -1.0}));
    g.edits.push_back(make_edit(Primitive::Box, {0.75, 0.5, 0.5, 0}, {-0.75, -0.25, -2.0}));
    for (int i = 0; i < 6; ++i) {
        const auto q = [&](double lo, double hi) { return 0.25 * std::floor(rng.uniform(lo, hi)); };
        const double hx = 0.25 + q(0.0, 2.0), hy = 0.25 + q(0.0, 2.0), hz = 0.25 + q(0.0, 2.0);
        const glm::dvec3 p{q(-6.0, 6.0), -0.25 + hy, q(-12.0, -4.0)};
        g.edits.push_back(make_edit(Primitive::Box, {hx, hy, hz, 0}, p));
    }
    return finish("face_rays", 0.0, g, look_at({0.0, 0.25, 3.0}, {0.0, 0.25, -1.0}, 50.0));
}

// 65,536 short smooth strokes (the most a geometry holds): small upright capsules, each blended into
// its neighbours, scattered over a 24 x 24 field in a layer 0.1 deep. Building costs about 65,536 x
// (bricks each edit reaches) x samples per brick evaluations, so tests build it with coarse bricks.
Scene edits_65536(Rng& rng) {
    Geometry g;
    for (unsigned i = 0; i < SDF_MAX_EDITS; ++i) {
        const double x = rng.uniform(-12.0, 12.0), z = rng.uniform(-12.0, 12.0);
        const glm::dvec3 p{x, 0.2 + 0.05 * std::sin(0.7 * x) * std::cos(0.5 * z), z};
        Edit e = make_edit(Primitive::Capsule, {rng.uniform(0.01, 0.04), rng.uniform(0.01, 0.025), 0, 0}, p);
        e.blend = r4(rng.uniform(0.01, 0.02));
        g.edits.push_back(e);
    }
    return finish("edits_65536", 0.0, g, orbit({0.0, 0.0, 0.0}, 9.0, 30.0, 35.0));
}

// 10,000 instances of one small geometry (a blended post, ball and ring) on a 100 x 100 grid,
// each turned about y and scaled by 0.8 .. 1.2.
Scene instances_10000(Rng& rng) {
    Geometry g;
    g.edits.push_back(make_edit(Primitive::Cylinder, {0.1, 0.05, 0, 0}, {0.0, 0.1, 0.0}));
    Edit ball = make_edit(Primitive::Sphere, {0.09, 0, 0, 0}, {0.0, 0.25, 0.0});
    ball.blend = 0.05;
    g.edits.push_back(ball);
    g.edits.push_back(make_edit(Primitive::Torus, {0.12, 0.02, 0, 0}, {0.0, 0.02, 0.0}));
    Scene s = finish("instances_10000", 0.0, g, orbit({0.0, 0.0, 0.0}, 30.0, 30.0, 35.0));
    s.camera.fov_deg = 60.0;
    s.objects.clear();
    for (int z = 0; z < 100; ++z)
        for (int x = 0; x < 100; ++x) {
            Transform t;
            t.scale = r4(rng.uniform(0.8, 1.2));
            t.rotation = unit(glm::angleAxis(rng.uniform(0.0, 6.28), glm::dvec3(0.0, 1.0, 0.0)));
            t.translation = r4(glm::dvec3(0.5 * x - 24.75, 0.0, 0.5 * z - 24.75));
            s.objects.push_back(Object{fmt::format("i{}", 100 * z + x), 0, t});
        }
    return s;
}


// A 16 x 0.2 x 16 ground slab with smooth bumps and 400 instances of a small blended tree (trunk,
// crown of three blended spheres) standing on it: a large, slowly curving surface that coarse leaves
// cover, beside many small smooth shapes.
Scene ground_trees(Rng& rng) {
    Geometry ground;
    ground.edits.push_back(make_edit(Primitive::Box, {8.0, 0.1, 8.0, 0}, {0.0, -0.1, 0.0}));
    for (int i = 0; i < 40; ++i) {
        const glm::dvec3 p{rng.uniform(-7.0, 7.0), -0.6, rng.uniform(-7.0, 7.0)};
        Edit bump = make_edit(Primitive::Sphere, {rng.uniform(0.5, 1.2), 0, 0, 0}, p);
        bump.blend = r4(rng.uniform(0.3, 0.6));
        ground.edits.push_back(bump);
    }
    ground.name = "ground";
    Geometry tree;
    tree.name = "tree";
    tree.edits.push_back(make_edit(Primitive::Cylinder, {0.12, 0.025, 0, 0}, {0.0, 0.12, 0.0}));
    for (int i = 0; i < 3; ++i) {
        Edit crown = make_edit(Primitive::Sphere, {0.07 - 0.015 * i, 0, 0, 0}, {0.02 * (i - 1), 0.25 + 0.07 * i, 0.0});
        crown.blend = 0.04;
        tree.edits.push_back(crown);
    }
    Scene s = finish("ground_trees", 0.0, ground, orbit({0.0, 0.0, 0.0}, 14.0, 30.0, 25.0));
    s.geometries.push_back(tree);
    for (int i = 0; i < 400; ++i) {
        Transform t;
        t.scale = r4(rng.uniform(0.7, 1.3));
        t.rotation = unit(glm::angleAxis(rng.uniform(0.0, 6.28), glm::dvec3(0.0, 1.0, 0.0)));
        t.translation = r4(glm::dvec3(rng.uniform(-7.5, 7.5), -0.02, rng.uniform(-7.5, 7.5)));
        s.objects.push_back(Object{fmt::format("tree{}", i), 1, t});
    }
    return s;
}

// A 6 x 0.5 x 4 rounded slab engraved with 3,000 small hard box cuts over its left half: dense hard
// detail that needs the finest bricks beside a plain top and a rounded edge that coarse ones hold.
Scene engraved_slab(Rng& rng) {
    Geometry g;
    g.edits.push_back(make_edit(Primitive::RoundBox, {3.0, 0.25, 2.0, 0.1}, {0.0, 0.0, 0.0}));
    for (int i = 0; i < 3000; ++i) {
        const std::array<double, 4> size{rng.uniform(0.01, 0.04), rng.uniform(0.01, 0.03), rng.uniform(0.01, 0.04), 0};
        const glm::dvec3 at{rng.uniform(-2.8, -0.2), 0.25, rng.uniform(-1.8, 1.8)};
        g.edits.push_back(subtracted(make_edit(Primitive::Box, size, at)));
    }
    return finish("engraved_slab", 0.0, g, orbit({0.0, 0.0, 0.0}, 7.0, 20.0, 35.0));
}

// A board with grooves cut along both axes and 32 pieces of two kinds (a blended stack of cylinder,
// torus and sphere, and a rounded block) standing on its squares: flat faces in coarse leaves next
// to narrow hard grooves and small smooth shapes.
Scene grooved_board(Rng& rng) {
    Geometry board;
    board.name = "board";
    board.edits.push_back(make_edit(Primitive::Box, {4.0, 0.15, 4.0, 0}, {0.0, -0.15, 0.0}));
    for (int i = 1; i < 8; ++i) {
        const double at = -4.0 + i;
        board.edits.push_back(subtracted(make_edit(Primitive::Box, {4.2, 0.02, 0.015, 0}, {0.0, 0.0, at})));
        board.edits.push_back(subtracted(make_edit(Primitive::Box, {0.015, 0.02, 4.2, 0}, {at, 0.0, 0.0})));
    }
    Geometry pawn;
    pawn.name = "pawn";
    pawn.edits.push_back(make_edit(Primitive::Cylinder, {0.04, 0.3, 0, 0}, {0.0, 0.04, 0.0}));
    Edit body = make_edit(Primitive::Cylinder, {0.25, 0.12, 0, 0}, {0.0, 0.3, 0.0});
    body.blend = 0.1;
    pawn.edits.push_back(body);
    Edit collar = make_edit(Primitive::Torus, {0.15, 0.04, 0, 0}, {0.0, 0.55, 0.0});
    collar.blend = 0.05;
    pawn.edits.push_back(collar);
    Edit head = make_edit(Primitive::Sphere, {0.16, 0, 0, 0}, {0.0, 0.72, 0.0});
    head.blend = 0.06;
    pawn.edits.push_back(head);
    Geometry block;
    block.name = "block";
    block.edits.push_back(make_edit(Primitive::RoundBox, {0.3, 0.3, 0.3, 0.05}, {0.0, 0.3, 0.0}));
    block.edits.push_back(subtracted(make_edit(Primitive::Cylinder, {0.4, 0.12, 0, 0}, {0.0, 0.4, 0.0})));
    Scene s = finish("grooved_board", 0.0, board, orbit({0.0, 0.0, 0.0}, 11.0, 30.0, 35.0));
    s.geometries.push_back(pawn);
    s.geometries.push_back(block);
    for (int i = 0; i < 32; ++i) {
        const int row = i < 16 ? i / 8 : 4 + i / 8, col = i % 8;
        Transform t;
        t.rotation = unit(glm::angleAxis(rng.uniform(0.0, 6.28), glm::dvec3(0.0, 1.0, 0.0)));
        t.translation = glm::dvec3(col - 3.5, 0.0, row - 3.5);
        s.objects.push_back(Object{fmt::format("piece{}", i), (row == 1 || row == 6) ? 1u : 2u, t});
    }
    return s;
}

// A flat 6 x 6 plate with 60 spheres blended into it by radii from 0.005 (a crease far below a
// voxel) to 0.3: steep and gentle blends side by side with plain flat faces.
Scene steep_blends(Rng& rng) {
    Geometry g;
    g.edits.push_back(make_edit(Primitive::Box, {3.0, 0.1, 3.0, 0}, {0.0, -0.1, 0.0}));
    for (int i = 0; i < 60; ++i) {
        const double r = rng.uniform(0.05, 0.3);
        const glm::dvec3 p{rng.uniform(-2.7, 2.7), rng.uniform(-0.5, 0.8) * r, rng.uniform(-2.7, 2.7)};
        Edit e = make_edit(Primitive::Sphere, {r, 0, 0, 0}, p);
        e.blend = r4(i % 3 == 0 ? 0.005 : rng.uniform(0.02, 0.3));
        g.edits.push_back(e);
    }
    return finish("steep_blends", 0.0, g, orbit({0.0, 0.0, 0.0}, 7.0, 25.0, 30.0));
}

}  // namespace

std::span<const std::string_view> generated_scene_names() { return kNames; }

Scene generate_scene(std::string_view name, std::uint64_t seed) {
    using Generator = Scene (*)(Rng&);
    static constexpr std::array<Generator, kNames.size()> kGenerators = {
        spheres, drops, cubes, rain, fractal, board, thin, sculpt, rubble, sculpt_dense, grazing_plane, grazing_cylinder, sub_voxel,
        blend_tiny, blend_huge, ellipsoid, menger6, instance_stack, far, camera_inside, camera_on_face, face_rays,
        edits_65536, instances_10000, ground_trees, engraved_slab, grooved_board, steep_blends};
    const auto it = std::find(kNames.begin(), kNames.end(), name);
    if (it == kNames.end())
        throw InputError(fmt::format("unknown scene \"{}\" (known: {})", name, fmt::join(kNames, ", ")));
    // Each scene gets its own stream, so adding a scene never changes the others.
    Rng rng(seed ^ Fnv1a64().add(name).value());
    return kGenerators[static_cast<std::size_t>(it - kNames.begin())](rng);
}

}  // namespace sdfbrick
