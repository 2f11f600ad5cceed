#include "reference/field_eval.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>

#include "cl/buffer.h"
#include "cl/launch.h"
#include "measure/scheduler.h"
#include "construct/mesh_pool.h"
#include "core/errors.h"
#include "reference/reference_field.h"
#include "scene/to_device.h"

namespace sdfbrick::reference {

FieldEvaluator::FieldEvaluator(ocl::Device& device)
    : device_(device), program_(ocl::build_program(device, "eval_points.cl")),
      kernel_(ocl::make_kernel(program_, "eval_points")) {}

FieldEvalResult FieldEvaluator::evaluate(std::span<const SdfEdit> edits, std::span<const float> xyz,
                                         std::span<const float> meshes) {
    if (xyz.size() % 3 != 0) throw std::invalid_argument("FieldEvaluator::evaluate: points must be x, y, z triples");
    const std::size_t n = xyz.size() / 3;
    if (n > std::numeric_limits<std::uint32_t>::max()) throw InputError(fmt::format("{} points is more than one batch can hold", n));
    const std::uint64_t point_bytes = xyz.size() * sizeof(float);
    if (point_bytes > device_.info().max_alloc_bytes)
        throw InputError(fmt::format("{} points need {} bytes in one buffer; {} allocates at most {} bytes at once: "
                                     "evaluate fewer points (a lower slice resolution)",
                                     n, point_bytes, device_.info().name, device_.info().max_alloc_bytes));
    constexpr std::size_t header_floats = sizeof(SdfMeshGrid) / sizeof(float);
    for (const SdfEdit& e : edits)
        if (e.primitive == SDF_PRIM_MESH && (static_cast<std::size_t>(e.params[3]) + 1) * header_floats > meshes.size())
            throw std::invalid_argument("FieldEvaluator::evaluate: a mesh edit whose grid is not in the mesh pool");
    FieldEvalResult result;
    result.values.resize(n);
    if (n == 0) return result;
    ocl::Buffer<SdfEdit> edit_buf(device_, edits.size(), CL_MEM_READ_ONLY);
    ocl::Buffer<float> point_buf(device_, xyz.size(), CL_MEM_READ_ONLY);
    ocl::Buffer<float> out_buf(device_, n, CL_MEM_WRITE_ONLY);
    const float no_meshes = 0.0f;
    ocl::Buffer<float> mesh_buf(device_, meshes.empty() ? std::span<const float>(&no_meshes, 1) : meshes, CL_MEM_READ_ONLY);
    edit_buf.write(edits);
    point_buf.write(xyz);
    ocl::set_args(kernel_.get(), edit_buf, static_cast<cl_uint>(edits.size()), mesh_buf, point_buf,
                  static_cast<cl_uint>(n), out_buf);
    const std::size_t local = 64;
    const std::size_t global = (n + local - 1) / local * local;
    measure::Scheduler scheduler(device_);
    scheduler.launch(measure::Stage::eval, -1, kernel_.get(), global, local);
    out_buf.read_into(result.values);
    const measure::Launch& launch = scheduler.resolve().front();
    result.device_ms = launch.device_ms;
    result.queue_ms = launch.queue_ms;
    return result;
}

namespace {

Aabb world_bounds(const Scene& scene) {
    Aabb all;
    for (const Object& o : scene.objects) all.grow(bounds(scene, o));
    return all;
}

}  // namespace

Slice evaluate_slice(FieldEvaluator& evaluator, const Scene& scene, const SliceSpec& spec) {
    if (spec.axis < 0 || spec.axis > 2) throw InputError(fmt::format("slice axis must be 0, 1 or 2, got {}", spec.axis));
    if (spec.resolution < 2 || spec.resolution > 8192)
        throw InputError(fmt::format("slice resolution must lie in [2, 8192], got {}", spec.resolution));
    Aabb region = world_bounds(scene);
    if (region.empty()) throw InputError(fmt::format("scene \"{}\" is empty: no object has an add edit", scene.name));
    region = region.inflated(0.05 * glm::length(region.extent()));

    const int a = spec.axis, u = (a + 1) % 3, v = (a + 2) % 3;
    // Axes of the picture: for a z slice, x to the right and y up; for y, z right and x up; for x, y right and z up.
    const int right = a == 2 ? 0 : u, up = a == 2 ? 1 : v;
    Slice s;
    s.axis = a;
    s.offset = spec.offset.value_or(region.centre()[a]);
    const double w = region.extent()[right], h = region.extent()[up];
    s.pixel_size = std::max(w, h) / spec.resolution;
    s.width = std::max(1, static_cast<int>(std::ceil(w / s.pixel_size)));
    s.height = std::max(1, static_cast<int>(std::ceil(h / s.pixel_size)));
    s.du[right] = s.pixel_size;
    s.dv[up] = -s.pixel_size;
    s.origin[a] = s.offset;
    s.origin[right] = region.centre()[right] - 0.5 * (s.width - 1) * s.pixel_size;
    s.origin[up] = region.centre()[up] + 0.5 * (s.height - 1) * s.pixel_size;

    const std::size_t count = static_cast<std::size_t>(s.width) * s.height;
    s.values.assign(count, SDF_FAR);
    std::vector<float> xyz(3 * count);
    for (const Object& o : scene.objects) {
        const Geometry& g = scene.geometries[o.geometry];
        for (int y = 0; y < s.height; ++y)
            for (int x = 0; x < s.width; ++x) {
                const glm::dvec3 p = o.transform.inverse_apply(s.point(x, y));
                const std::size_t i = 3 * (static_cast<std::size_t>(y) * s.width + x);
                xyz[i] = static_cast<float>(p.x);
                xyz[i + 1] = static_cast<float>(p.y);
                xyz[i + 2] = static_cast<float>(p.z);
            }
        const std::vector<SdfEdit> edits = to_device(g);
        measure::Scheduler conversion(evaluator.device());
        const std::vector<float> meshes = construct::mesh_pool(std::span<const Geometry>(&g, 1), evaluator.device(), conversion);
        const FieldEvalResult r = evaluator.evaluate(edits, xyz, meshes);
        const float scale = static_cast<float>(o.transform.scale);
        for (std::size_t i = 0; i < count; ++i) s.values[i] = std::min(s.values[i], r.values[i] * scale);
        s.device_ms += r.device_ms;
        s.queue_ms += r.queue_ms;
        s.edit_evaluations += static_cast<std::uint64_t>(count) * edits.size();
    }
    return s;
}

Image slice_image(const Slice& s) {
    Image img(s.width, s.height, 3);
    const double band = 0.05 * s.pixel_size * std::max(s.width, s.height);
    for (int y = 0; y < s.height; ++y)
        for (int x = 0; x < s.width; ++x) {
            const double d = s.values[static_cast<std::size_t>(y) * s.width + x];
            glm::dvec3 c = d > 0.0 ? glm::dvec3(0.90, 0.60, 0.30) : glm::dvec3(0.40, 0.65, 0.90);
            const double ad = std::min(std::abs(d), 1e6);
            c *= 1.0 - 0.7 * std::exp(-3.0 * ad / band);                      // darker near the surface
            c *= 0.85 + 0.15 * std::cos(2.0 * M_PI * ad / band);              // contour bands
            const double line = std::clamp(1.0 - ad / (1.5 * s.pixel_size), 0.0, 1.0);
            c = c + (glm::dvec3(1.0) - c) * line;                             // the zero set in white
            float* px = img.at(x, y);
            for (int k = 0; k < 3; ++k) px[k] = static_cast<float>(c[k]);
        }
    return img;
}

ReferenceSamples reference_samples(const Slice& s, const Scene& scene, std::size_t max_samples) {
    ReferenceSamples r;
    const std::size_t count = s.values.size();
    if (count == 0 || max_samples == 0) return r;
    const std::size_t stride = std::max<std::size_t>(1, count / max_samples);
    const auto start = std::chrono::steady_clock::now();
    for (std::size_t i = 0; i < count; i += stride) {
        const int x = static_cast<int>(i % s.width), y = static_cast<int>(i / s.width);
        r.pixels.push_back(i);
        r.values.push_back(reference::evaluate(scene, s.point(x, y)));
    }
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return r;
}

ReferenceCheck check_against_reference(const Slice& s, const ReferenceSamples& reference) {
    ReferenceCheck r;
    double sum = 0.0;
    for (std::size_t k = 0; k < reference.pixels.size(); ++k) {
        const float v = s.values.at(reference.pixels[k]);
        const double ref = reference.values[k];
        const double err = std::abs(static_cast<double>(v) - ref);
        r.max_abs_error = std::max(r.max_abs_error, err);
        sum += err;
        r.sign_mismatches += (v < 0.0f) != (ref < 0.0);
        ++r.samples;
    }
    if (r.samples > 0) r.mean_abs_error = sum / static_cast<double>(r.samples);
    return r;
}

}  // namespace sdfbrick::reference
