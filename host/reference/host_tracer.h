// The double-precision host reference tracer: sphere traces the scene's exact field
// (reference::evaluate(const Scene&, p): every edit of every object, no culling, no bricks) for small
// images. It is the yardstick of the device reference tracer and of the brick tracer; it is slow
// (every step evaluates the whole scene) and meant for images of a few thousand pixels on scenes of
// a few edits. docs/reference.md#host-reference-tracer gives the method step by step.
//
// Contract:
//   - Rays: the pinhole model of kernels/sdf_camera.h with make_camera's basis, in double (only the
//     rounding differs from the device).
//   - A ray is marched from the entry of the clip box (the objects' bounds, grown by
//     1e-6 (1 + extent)), or from t = 0 when the eye is inside it. A first point with F <= 0 is a hit
//     there (no refinement); F <= hit_epsilon (1 + extent) is a hit, refined to the zero crossing
//     when the ray crosses the surface (depth exact to ~1e-13 relative on smooth surfaces at
//     non-grazing incidence; else the first point within eps); past the box: a miss; max_steps
//     evaluations: a miss flagged unconverged. HostHit::steps counts the march's evaluations only
//     (not the refinement's or the normal's).
//   - Normal: central differences with h = 1e-6 (1 + extent), normalised; -dir when that gradient is
//     zero or not finite.
#pragma once

#include <cstdint>

#include <glm/glm.hpp>

#include "image/render_buffer.h"
#include "scene/scene.h"

namespace sdfbrick::reference {

struct HostTraceSettings {
    // Relative hit tolerance: a point is on the surface when F <= hit_epsilon * (1 + extent), extent =
    // the diagonal of the union of the objects' world bounds (so the tolerance is in world units
    // scaled with the scene). Must be > 0.
    double hit_epsilon = 1e-9;
    // Field evaluations of the march per ray (refinement and normal excluded); reaching it without a
    // hit or an exit makes the pixel a miss flagged SDF_REF_UNCONVERGED. Must be >= 1.
    int max_steps = 4096;
    // Worker threads over image rows; 0 = std::thread::hardware_concurrency(). The output does not
    // depend on it (every pixel is computed independently, in the same way).
    int threads = 0;
};

// The outcome of one ray.
struct HostHit {
    bool hit = false;
    bool unconverged = false;   // max_steps reached (then hit is false)
    double t = -1.0;            // distance along the unit ray from its origin; -1 on a miss
    glm::dvec3 normal{0.0};     // world unit normal on a hit, 0 on a miss
    std::uint32_t steps = 0;    // march evaluations (see the header comment)
};

// The per-scene state of the tracer (clip box, tolerances); cheap to build. The scene must outlive it.
class HostTracer {
public:
    // Throws std::invalid_argument for hit_epsilon <= 0 or max_steps < 1.
    HostTracer(const Scene& scene, const HostTraceSettings& settings = {});

    // Traces one ray; `dir` must be a unit vector.
    HostHit trace(const glm::dvec3& origin, const glm::dvec3& dir) const;

    double epsilon() const { return eps_; }           // hit tolerance, world units
    double extent() const { return extent_; }         // diagonal of the union of the object bounds
    const Aabb& clip_box() const { return clip_; }    // grown union (empty: nothing to hit)
    double gradient_step() const { return h_; }

private:
    glm::dvec3 normal_at(const glm::dvec3& p, const glm::dvec3& dir) const;
    double refine(double a, double fa, const glm::dvec3& origin, const glm::dvec3& dir) const;

    const Scene* scene_;
    HostTraceSettings settings_;
    Aabb clip_;
    double extent_ = 0.0;
    double eps_ = 0.0;
    double h_ = 0.0;
};

// The camera rays of a width x height image, in double (docs/reference.md#rays gives the formula).
struct HostCamera {
    glm::dvec3 eye{0.0};
    glm::dvec3 forward{0.0, 0.0, -1.0};
    glm::dvec3 right{0.0};  // scaled by tan(fov/2) * W/H
    glm::dvec3 up{0.0};     // scaled by tan(fov/2)
    int width = 0;
    int height = 0;

    glm::dvec3 direction(int x, int y) const;  // unit direction through the centre of pixel (x, y)
};
// Throws InputError for an image size outside validate_image_size's range.
HostCamera make_host_camera(const Camera& camera, int width, int height);

// Traces every pixel of a width x height image of scene.camera. The scene is taken as it is (apply
// scene_at first for animated scenes). Output per pixel (row-major, top row first):
//   hit[i] = (nx, ny, nz, depth) as floats: world unit normal and the distance along the unit ray
//            from the eye; a miss has depth SDF_MISS (-1) and normal 0.
//   aux[i] = (steps, flags): march evaluations, and SDF_REF_UNCONVERGED when max_steps was reached
//            (that pixel is written as a miss).
// Throws InputError for a bad image size, std::invalid_argument for bad settings.
RenderBuffer trace_host(const Scene& scene, int width, int height, const HostTraceSettings& s = {});

}  // namespace sdfbrick::reference
