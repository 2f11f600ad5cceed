#include "reference/host_tracer.h"

#include "scene/to_device.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <exception>
#include <limits>
#include <mutex>
#include <stdexcept>
#include <thread>
#include <vector>

#include "reference/reference_field.h"

namespace sdfbrick::reference {

namespace {

// Parametric interval [t0, t1] of the ray inside the box; false when it misses the box (or the box is
// behind the origin). Axes the ray is parallel to are tested by the origin's coordinate alone.
bool clip_ray(const Aabb& box, const glm::dvec3& o, const glm::dvec3& d, double& t0, double& t1) {
    if (box.empty()) return false;
    t0 = -std::numeric_limits<double>::infinity();
    t1 = std::numeric_limits<double>::infinity();
    for (int i = 0; i < 3; ++i) {
        if (d[i] == 0.0) {
            if (o[i] < box.lo[i] || o[i] > box.hi[i]) return false;
            continue;
        }
        double a = (box.lo[i] - o[i]) / d[i];
        double b = (box.hi[i] - o[i]) / d[i];
        if (a > b) std::swap(a, b);
        t0 = std::max(t0, a);
        t1 = std::min(t1, b);
    }
    return t0 <= t1 && t1 >= 0.0;
}

}  // namespace

HostTracer::HostTracer(const Scene& scene, const HostTraceSettings& settings) : scene_(&scene), settings_(settings) {
    if (!(settings.hit_epsilon > 0.0) || !std::isfinite(settings.hit_epsilon))
        throw std::invalid_argument("HostTraceSettings::hit_epsilon must be a finite value > 0");
    if (settings.max_steps < 1) throw std::invalid_argument("HostTraceSettings::max_steps must be >= 1");
    Aabb u;
    for (const Object& o : scene.objects) u.grow(bounds(scene, o));
    extent_ = u.empty() ? 0.0 : glm::length(u.extent());
    eps_ = settings.hit_epsilon * (1.0 + extent_);
    h_ = 1e-6 * (1.0 + extent_);
    clip_ = u.inflated(1e-6 * (1.0 + extent_));
}

glm::dvec3 HostTracer::normal_at(const glm::dvec3& p, const glm::dvec3& dir) const {
    glm::dvec3 g;
    for (int i = 0; i < 3; ++i) {
        glm::dvec3 a = p, b = p;
        a[i] += h_;
        b[i] -= h_;
        g[i] = (evaluate(*scene_, a) - evaluate(*scene_, b)) / (2.0 * h_);
    }
    const double len = glm::length(g);
    if (!(len > 0.0) || !std::isfinite(len)) return -dir;
    return g / len;
}

double HostTracer::refine(double a, double fa, const glm::dvec3& origin, const glm::dvec3& dir) const {
    if (!(fa > 0.0)) return a;
    const glm::dvec3 pa = origin + a * dir;
    // Slope of F along the ray at a (unnormalised central-difference gradient).
    glm::dvec3 g;
    for (int i = 0; i < 3; ++i) {
        glm::dvec3 p = pa, q = pa;
        p[i] += h_;
        q[i] -= h_;
        g[i] = (evaluate(*scene_, p) - evaluate(*scene_, q)) / (2.0 * h_);
    }
    const double s = -glm::dot(g, dir);
    if (!(s > 1e-3) || !std::isfinite(s)) return a;  // grazing: the hit stays at a
    double lo = a, flo = fa;
    double hi = a + 2.0 * fa / s + eps_;
    double fhi = evaluate(*scene_, origin + hi * dir);
    if (fhi > 0.0) return a;  // no crossing found next to a: the ray touches the surface within eps
    const double tol = 1e-14 * (1.0 + std::abs(a));
    for (int i = 0; i < 64 && hi - lo > tol; ++i) {
        const double mid = 0.5 * (lo + hi);
        if (mid <= lo || mid >= hi) break;
        const double fm = evaluate(*scene_, origin + mid * dir);
        if (fm > 0.0) {
            lo = mid;
            flo = fm;
        } else {
            hi = mid;
            fhi = fm;
        }
    }
    // flo > 0 >= fhi: the secant root lies in (lo, hi].
    return lo + (hi - lo) * (flo / (flo - fhi));
}

HostHit HostTracer::trace(const glm::dvec3& origin, const glm::dvec3& dir) const {
    HostHit r;
    double t0 = 0.0, t1 = 0.0;
    if (!clip_ray(clip_, origin, dir, t0, t1)) return r;
    double t = std::max(t0, 0.0);
    const double t_exit = t1;
    bool first = true;
    while (r.steps < static_cast<std::uint32_t>(settings_.max_steps)) {
        const glm::dvec3 p = origin + t * dir;
        const double f = evaluate(*scene_, p);
        ++r.steps;
        if (first && f <= 0.0) {  // the ray starts inside the solid
            r.hit = true;
            r.t = t;
            r.normal = normal_at(p, dir);
            return r;
        }
        first = false;
        if (f <= eps_) {
            r.hit = true;
            r.t = refine(t, f, origin, dir);
            r.normal = normal_at(origin + r.t * dir, dir);
            return r;
        }
        t += f;
        if (t > t_exit) return r;
    }
    r.unconverged = true;
    return r;
}

glm::dvec3 HostCamera::direction(int x, int y) const {
    const double u = (2.0 * (static_cast<double>(x) + 0.5)) / static_cast<double>(width) - 1.0;
    const double v = 1.0 - (2.0 * (static_cast<double>(y) + 0.5)) / static_cast<double>(height);
    return glm::normalize(forward + u * right + v * up);
}

HostCamera make_host_camera(const Camera& camera, int width, int height) {
    validate_image_size(width, height);
    // As make_camera, kept in double.
    HostCamera c;
    c.eye = camera.eye_position();
    c.forward = glm::normalize(camera.target - c.eye);
    const glm::dvec3 up_hint = camera.kind == Camera::Kind::Orbit ? glm::dvec3(0.0, 1.0, 0.0) : camera.up;
    glm::dvec3 right = glm::cross(c.forward, up_hint);
    if (glm::length(right) < 1e-12) right = glm::cross(c.forward, glm::dvec3(0.0, 0.0, 1.0));
    right = glm::normalize(right);
    const glm::dvec3 up = glm::cross(right, c.forward);
    const double tan_half = std::tan(glm::radians(camera.fov_deg) * 0.5);
    const double aspect = static_cast<double>(width) / height;
    c.right = right * (tan_half * aspect);
    c.up = up * tan_half;
    c.width = width;
    c.height = height;
    return c;
}

RenderBuffer trace_host(const Scene& scene, int width, int height, const HostTraceSettings& s) {
    const HostCamera cam = make_host_camera(scene.camera, width, height);
    const HostTracer tracer(scene, s);
    RenderBuffer out(width, height);

    auto trace_row = [&](int y) {
        for (int x = 0; x < width; ++x) {
            const std::size_t i = static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x);
            const HostHit h = tracer.trace(cam.eye, cam.direction(x, y));
            cl_float4 v{};
            if (h.hit) {
                for (int k = 0; k < 3; ++k) v.s[k] = static_cast<float>(h.normal[k]);
                v.s[3] = static_cast<float>(h.t);
            } else {
                v.s[3] = SDF_MISS;
            }
            out.hit[i] = v;
            cl_uint2 a{};
            a.s[0] = h.steps;
            a.s[1] = h.unconverged ? SDF_REF_UNCONVERGED : 0u;
            out.aux[i] = a;
        }
    };

    int threads = s.threads > 0 ? s.threads : static_cast<int>(std::thread::hardware_concurrency());
    threads = std::clamp(threads, 1, height);
    if (threads == 1) {
        for (int y = 0; y < height; ++y) trace_row(y);
        return out;
    }
    std::atomic<int> next_row{0};
    std::exception_ptr error;
    std::mutex error_mutex;
    auto worker = [&] {
        try {
            for (int y = next_row.fetch_add(1); y < height; y = next_row.fetch_add(1)) trace_row(y);
        } catch (...) {
            const std::lock_guard<std::mutex> lock(error_mutex);
            if (!error) error = std::current_exception();
            next_row.store(height);
        }
    };
    std::vector<std::thread> pool;
    pool.reserve(static_cast<std::size_t>(threads));
    for (int k = 0; k < threads; ++k) pool.emplace_back(worker);
    for (std::thread& th : pool) th.join();
    if (error) std::rethrow_exception(error);
    return out;
}

}  // namespace sdfbrick::reference
