// Tests of the double-precision host reference tracer (host/reference/host_tracer.h): analytic
// sphere depths and normals, misses, a camera inside the solid, grazing rays, the iteration limit,
// the camera rays against the kernel formula, and an image of scenes/spheres.json.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <string>

#include <glm/gtc/quaternion.hpp>

#include "reference/reference_field.h"
#include "reference/host_tracer.h"
#include "scene/to_device.h"
#include "scene/scene.h"
#include "scene/scene_json.h"

namespace sdfbrick::reference {
namespace {

Scene sphere_scene(double r, const glm::dvec3& centre = glm::dvec3(0.0)) {
    Scene s;
    s.name = "sphere";
    Geometry g;
    g.name = "sphere";
    Edit e;
    e.primitive = Primitive::Sphere;
    e.params = {r, 0.0, 0.0, 0.0};
    e.transform.translation = centre;
    g.edits.push_back(e);
    s.geometries.push_back(g);
    Object o;
    o.name = "sphere";
    o.geometry = 0;
    s.objects.push_back(o);
    return s;
}

Camera look_at(const glm::dvec3& eye, const glm::dvec3& target, double fov_deg = 45.0) {
    Camera c;
    c.kind = Camera::Kind::LookAt;
    c.eye = eye;
    c.target = target;
    c.up = glm::dvec3(0.0, 1.0, 0.0);
    c.fov_deg = fov_deg;
    return c;
}

// Analytic distance along a unit ray to a sphere of radius r at the origin; -1 when it misses.
double ray_sphere(const glm::dvec3& o, const glm::dvec3& d, double r) {
    const double b = glm::dot(o, d);
    const double c = glm::dot(o, o) - r * r;
    const double disc = b * b - c;
    if (disc < 0.0) return -1.0;
    return -b - std::sqrt(disc);
}

std::size_t idx(const RenderBuffer& b, int x, int y) {
    return static_cast<std::size_t>(y) * static_cast<std::size_t>(b.width) + static_cast<std::size_t>(x);
}

TEST(ReferenceHostTracer, CentrePixelOfSphereHasAnalyticDepthAndFacesTheEye) {
    const double r = 0.75;
    Scene s = sphere_scene(r);
    const glm::dvec3 eye(1.0, 2.0, 3.0);
    s.camera = look_at(eye, glm::dvec3(0.0));
    // Odd sizes: the centre pixel's ray is exactly `forward` (u = v = 0), straight at the centre.
    const RenderBuffer b = trace_host(s, 33, 25);
    const std::size_t i = idx(b, 16, 12);
    ASSERT_TRUE(b.is_hit(i));
    EXPECT_NEAR(b.hit[i].s[3], glm::length(eye) - r, 1e-6);  // stored as float
    const glm::dvec3 to_eye = glm::normalize(eye);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(b.hit[i].s[k], to_eye[k], 1e-6) << k;
    EXPECT_EQ(b.aux[i].s[1], 0u);
    EXPECT_GE(b.aux[i].s[0], 1u);

    // The same ray in double: depth to 1e-9.
    const HostCamera cam = make_host_camera(s.camera, 33, 25);
    const HostTracer tracer(s);
    const HostHit h = tracer.trace(cam.eye, cam.direction(16, 12));
    ASSERT_TRUE(h.hit);
    EXPECT_NEAR(h.t, glm::length(eye) - r, 1e-9);
    EXPECT_NEAR(glm::dot(h.normal, to_eye), 1.0, 1e-9);
}

TEST(ReferenceHostTracer, ObliqueHitIsRefinedToTheZeroCrossing) {
    // Sphere tracing alone stops somewhere within eps (~3e-9) of the surface; the refinement must
    // land on the analytic intersection far more closely.
    const double r = 1.0;
    const Scene s = sphere_scene(r);
    const HostTracer tracer(s);
    for (const glm::dvec3& o : {glm::dvec3(0.3, 0.4, 5.0), glm::dvec3(0.61, -0.52, 4.0), glm::dvec3(-0.9, 0.1, 3.0)}) {
        const glm::dvec3 d(0.0, 0.0, -1.0);
        const HostHit h = tracer.trace(o, d);
        ASSERT_TRUE(h.hit);
        EXPECT_NEAR(h.t, ray_sphere(o, d, r), 1e-12) << o.x;
        const glm::dvec3 p = o + h.t * d;
        EXPECT_NEAR(glm::length(h.normal - p / glm::length(p)), 0.0, 1e-8) << o.x;
    }
}

TEST(ReferenceHostTracer, InstanceTransformIsApplied) {
    // Geometry sphere of radius 0.5, object scaled by 2 and moved to (1, 0, 0): a world sphere of
    // radius 1 centred at (1, 0, 0).
    Scene s = sphere_scene(0.5);
    s.objects[0].transform.scale = 2.0;
    s.objects[0].transform.translation = glm::dvec3(1.0, 0.0, 0.0);
    s.objects[0].transform.rotation = glm::angleAxis(0.7, glm::normalize(glm::dvec3(1.0, 2.0, 3.0)));
    const HostTracer tracer(s);
    const glm::dvec3 o(1.2, 0.3, 6.0), d(0.0, 0.0, -1.0);
    const HostHit h = tracer.trace(o, d);
    ASSERT_TRUE(h.hit);
    EXPECT_NEAR(h.t, ray_sphere(o - glm::dvec3(1.0, 0.0, 0.0), d, 1.0), 1e-12);
}

TEST(ReferenceHostTracer, PixelsBesideTheSphereMiss) {
    Scene s = sphere_scene(0.5);
    s.camera = look_at(glm::dvec3(0.0, 0.0, 5.0), glm::dvec3(0.0), 60.0);
    const RenderBuffer b = trace_host(s, 32, 24);
    for (const auto& [x, y] : {std::pair{0, 0}, std::pair{31, 0}, std::pair{0, 23}, std::pair{31, 23}}) {
        const std::size_t i = idx(b, x, y);
        EXPECT_FALSE(b.is_hit(i)) << x << "," << y;
        EXPECT_EQ(b.hit[i].s[3], SDF_MISS);
        EXPECT_EQ(b.hit[i].s[0], 0.0f);
        EXPECT_EQ(b.hit[i].s[1], 0.0f);
        EXPECT_EQ(b.hit[i].s[2], 0.0f);
        EXPECT_EQ(b.aux[i].s[0], 0u);  // the corners miss the clip box entirely
        EXPECT_EQ(b.aux[i].s[1], 0u);
    }
    // Every pixel agrees with the analytic ray-sphere test (depth to float precision).
    const HostCamera cam = make_host_camera(s.camera, 32, 24);
    int hits = 0;
    for (int y = 0; y < 24; ++y) {
        for (int x = 0; x < 32; ++x) {
            const double t = ray_sphere(cam.eye, cam.direction(x, y), 0.5);
            const std::size_t i = idx(b, x, y);
            ASSERT_EQ(b.is_hit(i), t >= 0.0) << x << "," << y;
            if (t >= 0.0) {
                ++hits;
                EXPECT_NEAR(b.hit[i].s[3], t, 1e-6) << x << "," << y;
            }
        }
    }
    EXPECT_GT(hits, 0);
    // A ray pointing away from the sphere misses too.
    const HostTracer tracer(s);
    const HostHit h = tracer.trace(glm::dvec3(0.0, 0.0, 5.0), glm::dvec3(0.0, 0.0, 1.0));
    EXPECT_FALSE(h.hit);
    EXPECT_FALSE(h.unconverged);
    EXPECT_EQ(h.t, -1.0);
}

TEST(ReferenceHostTracer, CameraInsideTheSolidHitsAtDepthZero) {
    Scene s = sphere_scene(1.0);
    s.camera = look_at(glm::dvec3(0.1, 0.2, 0.3), glm::dvec3(0.1, 0.2, -1.0), 90.0);
    const RenderBuffer b = trace_host(s, 32, 24);
    for (std::size_t i = 0; i < b.pixels(); ++i) {
        ASSERT_TRUE(b.is_hit(i)) << i;
        EXPECT_EQ(b.hit[i].s[3], 0.0f) << i;
        EXPECT_EQ(b.aux[i].s[0], 1u) << i;
        EXPECT_EQ(b.aux[i].s[1], 0u) << i;
        // The normal is the field's gradient at the eye: the outward radial direction.
        const glm::dvec3 n(b.hit[i].s[0], b.hit[i].s[1], b.hit[i].s[2]);
        EXPECT_NEAR(glm::length(n - glm::normalize(glm::dvec3(0.1, 0.2, 0.3))), 0.0, 1e-6) << i;
    }
}

TEST(ReferenceHostTracer, GrazingRaysTerminate) {
    const double r = 1.0;
    const Scene s = sphere_scene(r);
    HostTraceSettings set;
    const HostTracer tracer(s, set);
    const glm::dvec3 d(1.0, 0.0, 0.0);
    for (double offset : {1e-6, 1e-7, 0.0, -1e-7, -1e-6}) {
        const glm::dvec3 o(-5.0, r + offset, 0.0);
        const HostHit h = tracer.trace(o, d);
        EXPECT_GE(h.steps, 1u) << offset;
        EXPECT_LE(h.steps, static_cast<std::uint32_t>(set.max_steps)) << offset;
        if (h.hit) {
            EXPECT_FALSE(h.unconverged);
            // Wherever it stopped, it is on the surface (within the hit tolerance) and near the
            // tangent point (at distance sqrt(2 r |offset|) or less along the ray from it).
            EXPECT_LE(std::abs(evaluate(s, o + h.t * d)), tracer.epsilon()) << offset;
            EXPECT_NEAR(h.t, 5.0, std::sqrt(2.0 * r * 1e-6) + 1e-6) << offset;
            EXPECT_NEAR(glm::length(h.normal), 1.0, 1e-9) << offset;
        } else {
            // A miss, possibly the iteration limit (sphere tracing converges only linearly, at the
            // rate of the incidence angle's cosine, along a near-tangent ray).
            EXPECT_EQ(h.t, -1.0) << offset;
            if (h.unconverged) {
                EXPECT_EQ(h.steps, static_cast<std::uint32_t>(set.max_steps)) << offset;
            }
        }
    }
    // A ray that cuts the sphere a little deeper (1e-5 below the tangent) converges to the analytic depth.
    {
        const glm::dvec3 o(-5.0, r - 1e-5, 0.0);
        const HostHit h = tracer.trace(o, d);
        EXPECT_TRUE(h.hit);
        EXPECT_FALSE(h.unconverged);
        EXPECT_NEAR(h.t, ray_sphere(o, d, r), 1e-9);
    }
    // With a generous limit the near-tangent rays are decided: 1e-6 above the tangent misses (leaves
    // the clip box), exactly tangent touches the surface within eps, 1e-6 below hits at the analytic depth.
    HostTraceSettings many;
    many.max_steps = 1 << 16;
    const HostTracer patient(s, many);
    const HostHit above = patient.trace(glm::dvec3(-5.0, r + 1e-6, 0.0), d);
    EXPECT_FALSE(above.hit);
    EXPECT_FALSE(above.unconverged);
    EXPECT_LT(above.steps, static_cast<std::uint32_t>(many.max_steps));
    const glm::dvec3 ot(-5.0, r, 0.0);
    const HostHit tangent = patient.trace(ot, d);
    ASSERT_TRUE(tangent.hit);
    EXPECT_LE(std::abs(evaluate(s, ot + tangent.t * d)), patient.epsilon());
    EXPECT_NEAR(tangent.t, 5.0, std::sqrt(2.0 * patient.epsilon()) * 1.01);
    const glm::dvec3 ob(-5.0, r - 1e-6, 0.0);
    const HostHit below = patient.trace(ob, d);
    ASSERT_TRUE(below.hit);
    EXPECT_NEAR(below.t, ray_sphere(ob, d, r), 1e-9);
    EXPECT_NEAR(glm::length(below.normal - glm::normalize(ob + below.t * d)), 0.0, 1e-6);
}

TEST(ReferenceHostTracer, IterationLimitGivesAFlaggedMiss) {
    Scene s = sphere_scene(0.5);
    s.camera = look_at(glm::dvec3(0.3, 0.4, 5.0), glm::dvec3(0.0), 20.0);
    HostTraceSettings set;
    set.max_steps = 2;
    const RenderBuffer b = trace_host(s, 9, 7, set);
    const std::size_t i = idx(b, 5, 3);  // hits the sphere off-centre: not reached in 2 steps
    EXPECT_FALSE(b.is_hit(i));
    EXPECT_EQ(b.hit[i].s[3], SDF_MISS);
    EXPECT_EQ(b.aux[i].s[0], 2u);
    EXPECT_EQ(b.aux[i].s[1], SDF_REF_UNCONVERGED);
    // With the default limit the same pixel converges to a hit.
    const RenderBuffer full = trace_host(s, 9, 7);
    EXPECT_TRUE(full.is_hit(i));
    EXPECT_EQ(full.aux[i].s[1], 0u);
    EXPECT_GT(full.aux[i].s[0], 2u);
}

TEST(ReferenceHostTracer, SceneWithoutBoundsMissesEverywhere) {
    Scene s = sphere_scene(1.0);
    s.objects.clear();
    s.camera = look_at(glm::dvec3(0.0, 0.0, 5.0), glm::dvec3(0.0));
    const RenderBuffer b = trace_host(s, 8, 6);
    for (std::size_t i = 0; i < b.pixels(); ++i) {
        EXPECT_FALSE(b.is_hit(i));
        EXPECT_EQ(b.aux[i].s[0], 0u);
        EXPECT_EQ(b.aux[i].s[1], 0u);
    }
}

TEST(ReferenceHostTracer, BadSettingsThrow) {
    const Scene s = sphere_scene(1.0);
    HostTraceSettings a;
    a.hit_epsilon = 0.0;
    EXPECT_THROW(HostTracer(s, a), std::invalid_argument);
    HostTraceSettings b;
    b.max_steps = 0;
    EXPECT_THROW(HostTracer(s, b), std::invalid_argument);
}

TEST(ReferenceHostTracer, CameraRaysFollowTheKernelFormula) {
    // make_host_camera must give the rays of kernels/sdf_camera.h on make_camera's SdfCamera,
    // up to float rounding. Both camera kinds, a non-square image.
    Camera orbit;
    orbit.target = glm::dvec3(0.2, -0.1, 0.3);
    orbit.distance = 4.0;
    orbit.yaw_deg = 37.0;
    orbit.pitch_deg = -12.0;
    orbit.fov_deg = 50.0;
    const Camera la = look_at(glm::dvec3(1.0, 3.0, -2.0), glm::dvec3(0.0, 0.5, 0.0), 35.0);
    for (const Camera& c : {orbit, la}) {
        const int w = 40, h = 25;
        const SdfCamera k = make_camera(c, w, h);
        const HostCamera hc = make_host_camera(c, w, h);
        for (int i = 0; i < 3; ++i) EXPECT_NEAR(hc.eye[i], k.eye[i], 1e-6);
        for (int y = 0; y < h; y += 6) {
            for (int x = 0; x < w; x += 7) {
                const float u = (2.0f * (static_cast<float>(x) + 0.5f)) / static_cast<float>(w) - 1.0f;
                const float v = 1.0f - (2.0f * (static_cast<float>(y) + 0.5f)) / static_cast<float>(h);
                glm::vec3 d;
                for (int i = 0; i < 3; ++i) d[i] = k.forward[i] + u * k.right[i] + v * k.up[i];
                d = glm::normalize(d);
                const glm::dvec3 dd = hc.direction(x, y);
                EXPECT_NEAR(glm::length(dd), 1.0, 1e-15);
                for (int i = 0; i < 3; ++i) EXPECT_NEAR(dd[i], d[i], 2e-6) << x << "," << y << "," << i;
            }
        }
    }
}

TEST(ReferenceHostTracer, SpheresSceneImageLiesOnTheSurface) {
    const Scene s = load_scene(std::string(SDFBRICK_SOURCE_DIR) + "/scenes/spheres.json");
    const int w = 48, h = 32;
    HostTraceSettings one;
    one.threads = 1;
    const RenderBuffer b = trace_host(s, w, h, one);
    HostTraceSettings two;
    two.threads = 2;
    const RenderBuffer b2 = trace_host(s, w, h, two);

    const HostCamera cam = make_host_camera(s.camera, w, h);
    const HostTracer tracer(s);
    int hits = 0, misses = 0;
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            const std::size_t i = idx(b, x, y);
            // Threading does not change a bit.
            for (int k = 0; k < 4; ++k) ASSERT_EQ(b.hit[i].s[k], b2.hit[i].s[k]);
            ASSERT_EQ(b.aux[i].s[0], b2.aux[i].s[0]);
            ASSERT_EQ(b.aux[i].s[1], b2.aux[i].s[1]);
            ASSERT_EQ(b.aux[i].s[1], 0u) << x << "," << y;  // nothing unconverged on this scene

            const glm::dvec3 d = cam.direction(x, y);
            const HostHit hh = tracer.trace(cam.eye, d);
            ASSERT_EQ(b.is_hit(i), hh.hit);
            if (!hh.hit) {
                ++misses;
                // A miss: the field stays positive all along the ray (sampled).
                for (double t = 0.0; t < 10.0; t += 0.01) ASSERT_GT(evaluate(s, cam.eye + t * d), 0.0) << x << "," << y;
                continue;
            }
            ++hits;
            EXPECT_EQ(b.hit[i].s[3], static_cast<float>(hh.t));
            // The depth is on the zero set: |F| ~ 0 there, and the field is positive just before.
            EXPECT_LE(std::abs(evaluate(s, cam.eye + hh.t * d)), tracer.epsilon()) << x << "," << y;
            EXPECT_GT(evaluate(s, cam.eye + (hh.t - 1e-4) * d), 0.0) << x << "," << y;
            // The float depth is the double one rounded.
            EXPECT_NEAR(b.hit[i].s[3], hh.t, 1e-6 * hh.t);
            // Unit normal facing the camera.
            const glm::dvec3 n(b.hit[i].s[0], b.hit[i].s[1], b.hit[i].s[2]);
            EXPECT_NEAR(glm::length(n), 1.0, 1e-6);
            EXPECT_LT(glm::dot(n, d), 0.0);
        }
    }
    EXPECT_GT(hits, 50);
    EXPECT_GT(misses, 50);
}

}  // namespace
}  // namespace sdfbrick::reference
