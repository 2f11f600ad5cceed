#include "scene/generate.h"

#include <array>
#include <cmath>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "core/errors.h"
#include "core/hash.h"

namespace sdfbrick {

namespace {

constexpr std::array<std::string_view, 8> kNames = {"spheres", "drops", "cubes", "rain", "fractal", "board", "thin", "sculpt"};

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

// A sculpted ball: 1024 brush strokes of 8 smoothly blended capsule segments each (8,193 edits),
// walking over a sphere of radius 2; a quarter of the strokes carve. Every sample near the
// surface sees tens of small edits: the heavy edit-list case.
Scene sculpt(Rng& rng) {
    Geometry g;
    const double ball = 2.0;
    g.edits.push_back(make_edit(Primitive::Sphere, {ball, 0, 0, 0}, {0.0, 0.0, 0.0}));
    for (int stroke = 0; stroke < 1024; ++stroke) {
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
    return finish("sculpt", 0.0, g, orbit({0.0, 0.0, 0.0}, 7.0, 30.0, 20.0));
}

}  // namespace

std::span<const std::string_view> generated_scene_names() { return kNames; }

Scene generate_scene(std::string_view name, std::uint64_t seed) {
    // Each scene gets its own stream, so adding a scene never changes the others.
    Rng rng(seed ^ Fnv1a64().add(name).value());
    if (name == "spheres") return spheres(rng);
    if (name == "drops") return drops(rng);
    if (name == "cubes") return cubes(rng);
    if (name == "rain") return rain(rng);
    if (name == "fractal") return fractal(rng);
    if (name == "board") return board(rng);
    if (name == "thin") return thin(rng);
    if (name == "sculpt") return sculpt(rng);
    throw InputError(fmt::format("unknown scene \"{}\" (known: {})", name, fmt::join(kNames, ", ")));
}

}  // namespace sdfbrick
