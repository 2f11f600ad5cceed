// The device reference tracer (host/reference/device_tracer.h, kernels/reference_trace.cl) and its
// edit BVH (host/reference/edit_bvh.h), on the test device (PoCL in CI). Small images (at most 49 x 33)
// keep the suite fast on a CPU.
//
// Tolerances:
//   - analytic sphere: depth within 1e-5 relative (the bisection ends within one float step of t,
//     ~6e-8 relative; the field's float noise is ~1e-7 of the coordinates), normal within 2e-3 rad
//     (central differences with h = 2^-13 (1 + magnitude): noise / h and (h / r)^2 are both < 1e-3);
//   - culled fold (lo / hi bounds, any C) against the exact fold of every edit: the same hit mask,
//     depths within 4 float steps of t, identical normals where the depths are identical, else within
//     2e-3 rad (both sample the same exact F; they differ only where the march's steps differ,
//     lo < min(F, C), so the bisection may end on another pair of adjacent floats among the few
//     where float noise makes the sign of F flicker);
//   - instanced against baked into world space: the edits' float parameters and the ray's transform
//     round differently, which moves the surface by ~1e-7 of the coordinates: silhouette pixels may
//     flip (at most 2 of 1,617), depths within 2e-5 relative, normals within 5e-3 rad (h differs
//     between the two frames).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>
#include <string>

#include <gtest/gtest.h>

#include "core/errors.h"
#include "scene/to_device.h"
#include "reference/edit_bvh.h"
#include "reference/device_tracer.h"
#include "reference/host_tracer.h"
#include "scene/scene_json.h"
#include "test_support.h"

namespace sdfbrick {
namespace {

using reference::ReferenceResult;
using reference::ReferenceSettings;
using reference::ReferenceTracer;

ReferenceTracer& tracer() {
    static ReferenceTracer t(test::device());
    return t;
}

Edit make_edit(Primitive prim, std::array<double, 4> params, glm::dvec3 pos, Op op = Op::Add, double blend = 0.0,
               double scale = 1.0, glm::dquat rot = glm::dquat(1.0, 0.0, 0.0, 0.0)) {
    Edit e;
    e.primitive = prim;
    e.params = params;
    e.transform.translation = pos;
    e.transform.rotation = glm::normalize(rot);
    e.transform.scale = scale;
    e.op = op;
    e.blend = blend;
    return e;
}

Camera look_at(glm::dvec3 eye, glm::dvec3 target, double fov = 45.0) {
    Camera c;
    c.kind = Camera::Kind::LookAt;
    c.eye = eye;
    c.target = target;
    c.up = glm::dvec3(0.0, 1.0, 0.0);
    c.fov_deg = fov;
    return c;
}

Scene single_geometry_scene(Geometry g, Camera cam) {
    Scene s;
    s.name = "test";
    s.geometries.push_back(std::move(g));
    Object o;
    o.name = "object";
    o.geometry = 0;
    s.objects.push_back(o);
    s.camera = cam;
    return s;
}

// Every primitive and every combine rule, hard and smooth, rotated and scaled (as
// tests/construct/test_brick_builder.cpp's).
Geometry mixed_geometry() {
    const glm::dquat rot = glm::dquat(0.9, 0.2, -0.3, 0.25);
    Geometry g;
    g.name = "mixed";
    g.edits = {
        make_edit(Primitive::Sphere, {0.55, 0, 0, 0}, {0.0, 0.0, 0.0}),
        make_edit(Primitive::RoundBox, {0.4, 0.25, 0.3, 0.08}, {0.55, 0.1, 0.0}, Op::Add, 0.15, 1.0, rot),
        make_edit(Primitive::Torus, {0.35, 0.08, 0, 0}, {-0.2, 0.45, 0.1}, Op::Add, 0.1),
        make_edit(Primitive::Capsule, {0.3, 0.12, 0, 0}, {-0.55, -0.2, 0.2}, Op::Add, 0.12, 1.2, rot),
        make_edit(Primitive::Cylinder, {0.25, 0.15, 0, 0}, {0.2, -0.5, -0.3}, Op::Add, 0.0),
        make_edit(Primitive::Cone, {0.3, 0.25, 0.05, 0}, {0.3, 0.5, -0.4}, Op::Add, 0.08),
        make_edit(Primitive::Ellipsoid, {0.3, 0.15, 0.2, 0}, {-0.4, 0.2, -0.5}, Op::Add, 0.1, 0.9, rot),
        make_edit(Primitive::Box, {0.3, 0.3, 0.3, 0}, {-0.7, 0.6, -0.5}, Op::Add, 0.0, 0.5),
        make_edit(Primitive::Sphere, {0.3, 0, 0, 0}, {0.1, 0.15, 0.5}, Op::Subtract, 0.1),
        make_edit(Primitive::Box, {0.12, 0.8, 0.12, 0}, {0.1, 0.0, 0.0}, Op::Subtract, 0.0, 0.2),
        make_edit(Primitive::Box, {1.05, 1.0, 1.0, 0}, {0.0, 0.0, 0.0}, Op::Intersect, 0.05),
        make_edit(Primitive::Sphere, {0.2, 0, 0, 0}, {0.0, -0.75, 0.4}, Op::Add, 0.1),
    };
    return g;
}

Scene shipped(const char* name) {
    const Scene s = load_scene(std::string(SDFBRICK_SOURCE_DIR) + "/scenes/" + name + ".json");
    return scene_at(s, s.time);
}

// The first n edits of drops (overlapping smooth spheres that chain), framed by a look-at camera.
Scene drops_corner(std::size_t n) {
    Scene s = shipped("drops");
    s.geometries.at(0).edits.resize(n);
    const Aabb b = bounds(s.geometries[0]);
    const glm::dvec3 c = b.centre();
    const double r = 0.5 * glm::length(b.extent());
    s.camera = look_at(c + glm::normalize(glm::dvec3(0.5, 0.35, 1.0)) * (2.6 * r), c);
    return s;
}

ReferenceResult render(const Scene& s, int w, int h, const ReferenceSettings& settings = {}, const char* what = nullptr) {
    const auto start = std::chrono::steady_clock::now();
    ReferenceResult r = tracer().render(s, make_camera(s.camera, w, h), settings);
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    if (what != nullptr)
        std::printf("[reference] %-34s %dx%d: %llu hits, %llu march samples (%.1f / pixel), %llu fallback, %llu overflow, "
                    "%llu unconverged; device %.1f ms, render %.1f ms\n",
                    what, w, h, static_cast<unsigned long long>(r.hit_pixels), static_cast<unsigned long long>(r.march_steps),
                    static_cast<double>(r.march_steps) / static_cast<double>(r.image.pixels()),
                    static_cast<unsigned long long>(r.fallback_points), static_cast<unsigned long long>(r.overflow_points),
                    static_cast<unsigned long long>(r.unconverged_pixels), r.device_ms, ms);
    return r;
}

glm::dvec3 normal_of(const RenderBuffer& b, std::size_t i) {
    return glm::dvec3(b.hit[i].s[0], b.hit[i].s[1], b.hit[i].s[2]);
}
double depth_of(const RenderBuffer& b, std::size_t i) { return b.hit[i].s[3]; }

// The ray of pixel (x, y) in double, from the float camera (the formula of kernels/sdf_camera.h).
glm::dvec3 ray_dir(const SdfCamera& c, int x, int y) {
    const double u = 2.0 * (x + 0.5) / c.width - 1.0, v = 1.0 - 2.0 * (y + 0.5) / c.height;
    glm::dvec3 d;
    for (int i = 0; i < 3; ++i) d[i] = c.forward[i] + u * c.right[i] + v * c.up[i];
    return glm::normalize(d);
}

double angle(const glm::dvec3& a, const glm::dvec3& b) {
    return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b));
}

struct ImageDiff {
    std::size_t mask_mismatches = 0;
    std::size_t both_hit = 0;
    std::size_t identical = 0;   // bit-identical hit records
    double max_depth_rel = 0.0;  // |depth a - depth b| / depth a over pixels both hit
    double max_depth_steps = 0.0;  // the same in float steps (ulps) of the depth
    double max_normal_angle = 0.0;
    double max_normal_angle_same_depth = 0.0;  // over pixels whose depths are bit-identical
};

ImageDiff compare(const RenderBuffer& a, const RenderBuffer& b) {
    ImageDiff d;
    for (std::size_t i = 0; i < a.pixels(); ++i) {
        if (a.is_hit(i) != b.is_hit(i)) {
            ++d.mask_mismatches;
            continue;
        }
        d.identical += std::memcmp(&a.hit[i], &b.hit[i], sizeof(cl_float4)) == 0;
        if (!a.is_hit(i)) continue;
        ++d.both_hit;
        const double da = depth_of(a, i), db = depth_of(b, i);
        const double diff = std::abs(da - db);
        d.max_depth_rel = std::max(d.max_depth_rel, diff / std::max(da, 1e-30));
        const float fa = a.hit[i].s[3];
        const double ulp = std::nextafter(fa, std::numeric_limits<float>::infinity()) - fa;
        d.max_depth_steps = std::max(d.max_depth_steps, diff / ulp);
        const double na = angle(normal_of(a, i), normal_of(b, i));
        d.max_normal_angle = std::max(d.max_normal_angle, na);
        if (a.hit[i].s[3] == b.hit[i].s[3]) d.max_normal_angle_same_depth = std::max(d.max_normal_angle_same_depth, na);
    }
    return d;
}

void print(const char* what, const ImageDiff& d) {
    std::printf("[reference] %-34s mask mismatches %zu, both hit %zu, bit-identical pixels %zu, max depth diff %.3g "
                "relative (%.1f float steps), max normal angle %.3g rad (%.3g where the depths are equal)\n",
                what, d.mask_mismatches, d.both_hit, d.identical, d.max_depth_rel, d.max_depth_steps,
                d.max_normal_angle, d.max_normal_angle_same_depth);
}

// ---- the edit BVH ----

TEST(ReferenceDeviceTracer, EditBvhFindsTheSameBoxesAsBruteForce) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> pos(-4.0f, 4.0f), size(0.0f, 1.5f);
    for (const std::size_t n : {std::size_t{0}, std::size_t{1}, std::size_t{2}, std::size_t{3}, std::size_t{17},
                                std::size_t{1000}}) {
        std::vector<SdfBounds> boxes(n);
        for (SdfBounds& b : boxes)
            for (int a = 0; a < 3; ++a) {
                const float c = pos(rng), h = size(rng);
                b.lo[a] = c - h;
                b.hi[a] = c + h;
            }
        if (n >= 3) boxes[2] = boxes[1];  // duplicates are fine
        const reference::EditBvh bvh = reference::build_edit_bvh(boxes);
        EXPECT_EQ(bvh.nodes.size(), n == 0 ? 0 : std::max<std::size_t>(1, n - 1));
        const int bound = n <= 1 ? static_cast<int>(n) : static_cast<int>(std::ceil(std::log2(static_cast<double>(n)))) + 1;
        EXPECT_LE(bvh.depth, bound) << n << " boxes";
        const reference::EditBvh again = reference::build_edit_bvh(boxes);
        ASSERT_EQ(again.nodes.size(), bvh.nodes.size());
        if (n > 0) {  // memcmp of two empty vectors would be given null pointers
            EXPECT_EQ(std::memcmp(again.nodes.data(), bvh.nodes.data(), bvh.nodes.size() * sizeof(SdfBvhNode)), 0);
        }
        for (int k = 0; k < 500; ++k) {
            const glm::vec3 p(pos(rng), pos(rng), pos(rng));
            std::vector<std::uint32_t> brute;
            for (std::size_t i = 0; i < n; ++i)
                if (reference::contains(boxes[i], p)) brute.push_back(static_cast<std::uint32_t>(i));
            ASSERT_EQ(reference::boxes_containing(bvh, boxes, p), brute) << n << " boxes, point " << k;
        }
    }
    // Outward rounding: the float box holds the double box.
    const Aabb exact{glm::dvec3(0.1, -0.3, 1.0 / 3.0), glm::dvec3(0.7, 2.0 / 3.0, 1e-9 + 1.0)};
    const SdfBounds f = reference::to_float_box(exact);
    for (int a = 0; a < 3; ++a) {
        EXPECT_LE(static_cast<double>(f.lo[a]), exact.lo[a]);
        EXPECT_GE(static_cast<double>(f.hi[a]), exact.hi[a]);
    }
}

// ---- single sphere: analytic answers ----

TEST(ReferenceDeviceTracer, SphereDepthAndNormalsMatchTheAnalyticSphere) {
    const glm::dvec3 centre(0.3, -0.2, 0.1);
    const double radius = 0.8;
    Geometry g;
    g.name = "sphere";
    g.edits = {make_edit(Primitive::Sphere, {radius, 0, 0, 0}, centre)};
    const glm::dvec3 eye(1.1, 0.9, 3.7);
    const Scene s = single_geometry_scene(g, look_at(eye, centre, 40.0));
    const int w = 49, h = 33;  // odd: the centre pixel's ray is the forward axis
    const SdfCamera cam = make_camera(s.camera, w, h);
    const ReferenceResult r = render(s, w, h, {}, "sphere");
    ASSERT_EQ(r.image.width, w);
    ASSERT_EQ(r.image.height, h);
    EXPECT_EQ(r.unconverged_pixels, 0u);
    EXPECT_EQ(r.fallback_points, 0u);  // one hard edit: lo == hi wherever F < C

    const std::size_t centre_px = static_cast<std::size_t>(h / 2) * w + w / 2;
    ASSERT_TRUE(r.image.is_hit(centre_px));
    const double expected = glm::length(eye - centre) - radius;
    EXPECT_NEAR(depth_of(r.image, centre_px), expected, 1e-5 * expected);
    EXPECT_GT(glm::dot(normal_of(r.image, centre_px), glm::normalize(eye - centre)), 0.99999);

    // Every pixel against the analytic ray-sphere intersection (double, from the float camera).
    const glm::dvec3 o(cam.eye[0], cam.eye[1], cam.eye[2]);
    std::size_t hits = 0, misses = 0;
    double worst_depth = 0.0, worst_angle = 0.0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const std::size_t i = static_cast<std::size_t>(y) * w + x;
            const glm::dvec3 d = ray_dir(cam, x, y);
            const glm::dvec3 oc = o - centre;
            const double b = glm::dot(oc, d), c = glm::dot(oc, oc) - radius * radius, disc = b * b - c;
            // Rays within 1e-4 of tangency may go either way (float noise); skip them.
            if (std::abs(disc) < 1e-4) continue;
            if (disc < 0.0) {
                ++misses;
                EXPECT_FALSE(r.image.is_hit(i)) << "pixel " << x << ", " << y;
                EXPECT_EQ(r.image.hit[i].s[3], SDF_MISS);
                EXPECT_EQ(normal_of(r.image, i), glm::dvec3(0.0));
                continue;
            }
            ++hits;
            ASSERT_TRUE(r.image.is_hit(i)) << "pixel " << x << ", " << y;
            const double t = -b - std::sqrt(disc);
            worst_depth = std::max(worst_depth, std::abs(depth_of(r.image, i) - t) / t);
            const glm::dvec3 n = glm::normalize(o + t * d - centre);
            worst_angle = std::max(worst_angle, angle(normal_of(r.image, i), n));
            EXPECT_LT(glm::dot(normal_of(r.image, i), d), 0.0);  // toward the eye
            EXPECT_EQ(r.image.aux[i].s[1] & reference::kRefFlagInside, 0u);
        }
    std::printf("[reference] sphere: %zu hits, %zu misses checked; max depth error %.3g relative, max normal error %.3g rad\n",
                hits, misses, worst_depth, worst_angle);
    EXPECT_GT(hits, 100u);
    EXPECT_GT(misses, 100u);
    EXPECT_LE(worst_depth, 1e-5);
    EXPECT_LE(worst_angle, 2e-3);
}

// ---- the culled fold against the exact field ----

void expect_matches_exact(const Scene& s, const char* what) {
    const int w = 48, h = 32;
    ReferenceSettings exact;
    exact.exact_field = true;
    const ReferenceResult ref = render(s, w, h, exact, (std::string(what) + " exact fold").c_str());
    ASSERT_GT(ref.hit_pixels, 50u) << what;
    ASSERT_EQ(ref.unconverged_pixels, 0u) << what;
    struct Case {
        const char* name;
        double guard, extent;
    };
    // default C; a small C (many undecided samples: the fallback path); a large C (8 k_max + extent / 64).
    for (const Case c : {Case{"default C", 2.0, 1.0 / 64}, Case{"C = k / 4 + extent / 256", 0.25, 1.0 / 256},
                         Case{"C = 8 k + extent / 64", 8.0, 1.0 / 64}}) {
        ReferenceSettings st;
        st.clamp_guard = c.guard;
        st.clamp_extent = c.extent;
        const std::string name = std::string(what) + ", " + c.name;
        const ReferenceResult r = render(s, w, h, st, name.c_str());
        const ImageDiff d = compare(ref.image, r.image);
        print(name.c_str(), d);
        EXPECT_EQ(r.unconverged_pixels, 0u) << name;
        EXPECT_EQ(d.mask_mismatches, 0u) << name;
        EXPECT_LE(d.max_depth_steps, 4.0) << name;
        EXPECT_EQ(d.max_normal_angle_same_depth, 0.0) << name;
        // A hit point a few float steps away moves the taps by 1e-7 of h; at a crease of the field
        // (hard edits) that turns the normal by up to ~(shift / h): 2e-3.
        EXPECT_LE(d.max_normal_angle, 2e-3) << name;
        if (c.guard < 1.0) {
            EXPECT_GT(r.fallback_points, 0u) << name << ": the small C should exercise the fallback";
        }
    }
}

TEST(ReferenceDeviceTracer, CulledFoldMatchesTheExactFieldOnDropsCorner) { expect_matches_exact(drops_corner(48), "drops[0:48]"); }

TEST(ReferenceDeviceTracer, CulledFoldMatchesTheExactFieldOnMixedEdits) {
    expect_matches_exact(single_geometry_scene(mixed_geometry(), look_at({1.6, 1.3, 2.4}, {0.0, 0.0, 0.0})), "mixed");
}

// ---- shipped scene ----

TEST(ReferenceDeviceTracer, SpheresSceneHasHitsAndMisses) {
    const Scene s = shipped("spheres");
    const int w = 48, h = 32;
    const SdfCamera cam = make_camera(s.camera, w, h);
    const ReferenceResult r = render(s, w, h, {}, "spheres.json");
    EXPECT_GT(r.hit_pixels, 100u);
    EXPECT_LT(r.hit_pixels, static_cast<std::uint64_t>(w * h - 100));
    EXPECT_EQ(r.unconverged_pixels, 0u);
    EXPECT_EQ(r.overflow_points, 0u);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const std::size_t i = static_cast<std::size_t>(y) * w + x;
            if (!r.image.is_hit(i)) {
                EXPECT_EQ(r.image.hit[i].s[3], SDF_MISS);
                continue;
            }
            const glm::dvec3 n = normal_of(r.image, i);
            EXPECT_NEAR(glm::length(n), 1.0, 1e-6);
            EXPECT_LT(glm::dot(n, ray_dir(cam, x, y)), 0.0) << "pixel " << x << ", " << y;
            EXPECT_GT(depth_of(r.image, i), 0.0);
        }
    EXPECT_FALSE(r.memory.empty());
    EXPECT_EQ(r.memory.at("edits"), 2 * sizeof(SdfEdit));
    ASSERT_EQ(r.geometries.size(), 1u);
    EXPECT_GT(r.geometries[0].clamp_c, 1.0);  // 2 k_max + extent / 64, k_max = 0.5
}

// The double-precision host tracer (host/reference/host_tracer.h) on the same scene and camera:
// an independent implementation (double, every edit, no culling), rays from the double camera. Near a
// silhouette the float and double rays may fall on either side; elsewhere the depth agrees to the
// float noise (~1e-7 relative, tolerance 1e-5) and the normals to the float tolerance of the device
// normal (2e-3 rad).
TEST(ReferenceDeviceTracer, SpheresSceneMatchesTheHostDoubleTracer) {
    const Scene s = shipped("spheres");
    const int w = 48, h = 32;
    const ReferenceResult r = render(s, w, h, {}, "spheres.json (vs host double)");
    const auto start = std::chrono::steady_clock::now();
    const RenderBuffer host = reference::trace_host(s, w, h);
    const double host_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    ASSERT_EQ(host.pixels(), r.image.pixels());
    const ImageDiff d = compare(host, r.image);
    print("device vs host double tracer", d);
    std::printf("[reference] host double tracer %dx%d: %.1f ms\n", w, h, host_ms);
    EXPECT_GT(d.both_hit, 250u);
    EXPECT_LE(d.mask_mismatches, 3u);
    EXPECT_LE(d.max_depth_rel, 1e-5);
    EXPECT_LE(d.max_normal_angle, 2e-3);
}

// ---- cameras inside the solid ----

TEST(ReferenceDeviceTracer, CameraInsideTheSolidHitsAtTheEye) {
    Geometry g;
    g.name = "ball";
    g.edits = {make_edit(Primitive::Sphere, {1.0, 0, 0, 0}, {0.0, 0.0, 0.0})};
    const Scene s = single_geometry_scene(g, look_at({0.1, 0.2, 0.3}, {1.0, 0.0, 0.0}));
    const ReferenceResult r = render(s, 24, 16, {}, "eye inside a sphere");
    EXPECT_EQ(r.hit_pixels, r.image.pixels());
    for (std::size_t i = 0; i < r.image.pixels(); ++i) {
        EXPECT_EQ(depth_of(r.image, i), 0.0);
        EXPECT_NE(r.image.aux[i].s[1] & reference::kRefFlagInside, 0u);
        EXPECT_EQ(r.image.aux[i].s[0], 1u);  // one sample
        EXPECT_NEAR(glm::length(normal_of(r.image, i)), 1.0, 1e-6);
    }
}

TEST(ReferenceDeviceTracer, CameraInsideACavitySeesItsWall) {
    Geometry g;
    g.name = "shell";
    g.edits = {make_edit(Primitive::Sphere, {2.0, 0, 0, 0}, {0.0, 0.0, 0.0}),
               make_edit(Primitive::Sphere, {1.0, 0, 0, 0}, {0.0, 0.0, 0.0}, Op::Subtract)};
    const Scene s = single_geometry_scene(g, look_at({0.0, 0.0, 0.0}, {0.3, -0.2, 1.0}));
    const int w = 24, h = 16;
    const SdfCamera cam = make_camera(s.camera, w, h);
    const ReferenceResult r = render(s, w, h, {}, "eye in a cavity");
    EXPECT_EQ(r.hit_pixels, r.image.pixels());
    EXPECT_EQ(r.unconverged_pixels, 0u);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const std::size_t i = static_cast<std::size_t>(y) * w + x;
            EXPECT_NEAR(depth_of(r.image, i), 1.0, 1e-5);
            // The wall's outward normal (out of the solid) points back at the eye.
            EXPECT_LT(angle(normal_of(r.image, i), -ray_dir(cam, x, y)), 2e-3);
        }
}

// ---- limits and bad input ----

TEST(ReferenceDeviceTracer, StepLimitGivesFlaggedMisses) {
    const Scene s = shipped("spheres");
    ReferenceSettings st;
    st.max_steps = 3;
    const ReferenceResult r = render(s, 48, 32, st, "spheres.json, max_steps 3");
    EXPECT_GT(r.unconverged_pixels, 0u);
    for (std::size_t i = 0; i < r.image.pixels(); ++i) {
        const bool unconverged = (r.image.aux[i].s[1] & reference::kRefFlagUnconverged) != 0;
        if (unconverged) {
            EXPECT_FALSE(r.image.is_hit(i));
        }
        EXPECT_LE(r.image.aux[i].s[0], 3u);
    }
}

TEST(ReferenceDeviceTracer, EmptyScenesMissAndBadScenesAreRefused) {
    Scene s = single_geometry_scene(mixed_geometry(), look_at({1.6, 1.3, 2.4}, {0.0, 0.0, 0.0}));
    Scene none = s;
    none.objects.clear();
    ReferenceResult r = render(none, 16, 8);
    EXPECT_EQ(r.hit_pixels, 0u);
    for (std::size_t i = 0; i < r.image.pixels(); ++i) EXPECT_EQ(r.image.hit[i].s[3], SDF_MISS);

    Scene carve = s;  // subtract edits only: no surface
    carve.geometries[0].edits = {make_edit(Primitive::Sphere, {1.0, 0, 0, 0}, {0.0, 0.0, 0.0}, Op::Subtract)};
    r = render(carve, 16, 8);
    EXPECT_EQ(r.hit_pixels, 0u);
    EXPECT_FALSE(r.geometries.at(0).traceable);

    Scene bad = s;
    bad.objects[0].geometry = 3;
    EXPECT_THROW(tracer().render(bad, make_camera(bad.camera, 16, 8)), InputError);
    bad = s;
    bad.objects[0].transform.scale = 0.0;
    EXPECT_THROW(tracer().render(bad, make_camera(bad.camera, 16, 8)), InputError);
    SdfCamera cam = make_camera(s.camera, 16, 8);
    cam.width = 0;
    EXPECT_THROW(tracer().render(s, cam), InputError);
    ReferenceSettings st;
    st.max_steps = 0;
    EXPECT_THROW(tracer().render(s, make_camera(s.camera, 16, 8), st), InputError);
}

// ---- determinism ----

TEST(ReferenceDeviceTracer, RepeatedRunsAreBitIdentical) {
    const Scene s = single_geometry_scene(mixed_geometry(), look_at({1.6, 1.3, 2.4}, {0.0, 0.0, 0.0}));
    const ReferenceResult a = render(s, 48, 32, {}, "mixed");
    const ReferenceResult b = render(s, 48, 32);
    ASSERT_EQ(a.image.pixels(), b.image.pixels());
    EXPECT_GT(a.hit_pixels, 100u);
    EXPECT_EQ(std::memcmp(a.image.hit.data(), b.image.hit.data(), a.image.pixels() * sizeof(cl_float4)), 0);
    EXPECT_EQ(std::memcmp(a.image.aux.data(), b.image.aux.data(), a.image.pixels() * sizeof(cl_uint2)), 0);
    EXPECT_EQ(a.fallback_points, b.fallback_points);
    EXPECT_EQ(a.march_steps, b.march_steps);
}

// ---- instancing ----

// The geometry's edits moved into the world by the object's transform (blend radii scale with it).
Geometry baked(const Geometry& g, const Transform& t) {
    Geometry out = g;
    out.name = g.name + " baked";
    for (Edit& e : out.edits) {
        e.transform.translation = t.apply(e.transform.translation);
        e.transform.rotation = glm::normalize(t.rotation * e.transform.rotation);
        e.transform.scale = t.scale * e.transform.scale;
        e.blend = t.scale * e.blend;
    }
    return out;
}

TEST(ReferenceDeviceTracer, InstancesMatchEditsBakedIntoTheWorld) {
    const Geometry g = mixed_geometry();
    Transform a;
    a.translation = glm::dvec3(-0.9, 0.1, 0.0);
    Transform b;
    b.translation = glm::dvec3(0.9, -0.1, -0.3);
    b.rotation = glm::normalize(glm::dquat(0.8, 0.1, 0.5, -0.2));
    b.scale = 0.6;
    Scene inst;
    inst.name = "instanced";
    inst.geometries = {g};
    inst.objects = {Object{"a", 0, a}, Object{"b", 0, b}};
    inst.camera = look_at({0.6, 1.4, 3.6}, {0.0, 0.0, -0.1});
    Scene flat = inst;
    flat.name = "baked";
    flat.geometries = {baked(g, a), baked(g, b)};
    flat.objects = {Object{"a", 0, Transform{}}, Object{"b", 1, Transform{}}};

    const int w = 49, h = 33;
    const ReferenceResult ri = render(inst, w, h, {}, "two instances");
    const ReferenceResult rb = render(flat, w, h, {}, "baked into the world");
    const ImageDiff d = compare(ri.image, rb.image);
    print("instanced vs baked", d);
    EXPECT_GT(d.both_hit, 200u);
    EXPECT_LE(d.mask_mismatches, 2u);
    EXPECT_LE(d.max_depth_rel, 2e-5);
    EXPECT_LE(d.max_normal_angle, 5e-3);
    EXPECT_EQ(ri.unconverged_pixels, 0u);
    EXPECT_EQ(rb.unconverged_pixels, 0u);
}

}  // namespace
}  // namespace sdfbrick
