// The double-precision host reference tracer: sphere tracing of the scene's exact field
// (reference::evaluate(const Scene&, p): every edit of every object, no culling, no bricks) for small
// images. It is the yardstick of the device reference tracer and of the brick tracer
// (DESIGN.md section 3, "Reference tracer"); it is slow (every step evaluates the whole scene) and
// meant for images of a few thousand pixels on scenes of a few edits.
//
// Rays: exactly the pinhole model of kernels/sdf_camera.h, in double. With the camera basis of
// make_camera (forward = normalize(target - eye); right = normalize(cross(forward, up_hint)),
// up_hint = +y for an orbit camera, Camera::up for look_at, cross(forward, +z) when looking straight
// along the hint; up = cross(right, forward)) the ray through the centre of pixel (x, y) is
//     u = 2 (x + 0.5) / W - 1,  v = 1 - 2 (y + 0.5) / H,
//     dir = normalize(forward + u * right * tan(fov/2) * W/H + v * up * tan(fov/2)),
// starting at the eye. Only the rounding differs from the device (double here, float there).
//
// Per ray (HostTracer::trace):
//   1. Clip box: the union of bounds(scene, object) over the objects, grown on every side by
//      1e-6 * (1 + extent). extent = the diagonal of the (ungrown) union; no object with bounds
//      (no objects, or only subtract/intersect edits) -> every ray misses. A ray that misses the box
//      is a miss with 0 steps. The march starts at the box entry, or at t = 0 when the eye is inside.
//   2. Sphere tracing: p = eye + t dir, F = reference::evaluate(scene, p) (one step = one evaluation,
//      counted in `steps`), t += F. The scene field is 1-Lipschitz (reference_field.h, scene.h), so a
//      step never crosses the surface.
//        - F <= 0 at the ray's first point: the ray starts inside the solid; hit at that t (depth 0
//          for a camera inside the solid, the box entry otherwise), no refinement.
//        - F <= eps: hit (then refined, 3.). eps = hit_epsilon * (1 + extent), world units.
//        - t > box exit: miss.
//        - `max_steps` evaluations without a decision: miss, flagged unconverged.
//   3. Refinement to the zero crossing: from the last point a (F(a) = fa in (0, eps]) a probe b is
//      placed past the surface using the field's slope along the ray, s = -dot(grad F, dir):
//      b = a + 2 fa / s + eps (when s > 1e-3; a ray that grazes the surface is not refined). When
//      F(b) <= 0 the bracket [a, b] is bisected until its width is below 1e-14 (1 + t) (at most 64
//      halvings) and the hit is the secant root of the final bracket; otherwise the hit stays at a
//      (the ray just touches the surface, within eps). On smooth surfaces at non-grazing incidence the
//      depth is exact to ~1e-13 relative; in the worst case (grazing, no crossing) it is the first
//      point within eps of the surface. Refinement evaluations are not counted in `steps`.
//   4. Normal at the hit point: central differences of the scene field, step
//      h = 1e-6 * (1 + extent) on each axis, normalised; when that gradient is zero or not finite
//      the normal is -dir.
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

// The camera rays of a width x height image, in double (the header comment gives the formula).
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
