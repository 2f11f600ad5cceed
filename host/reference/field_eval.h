// Evaluates a geometry's field on the device at a batch of points (kernels/eval_points.cl), and
// the main job built on it: a slice through a scene, checked against the host reference.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include <nlohmann/json.hpp>

#include "cl/device.h"
#include "cl/program.h"
#include "image/image.h"
#include "scene/scene.h"

namespace sdfbrick::reference {

struct FieldEvalResult {
    std::vector<float> values;
    double device_ms = 0.0;  // kernel start -> end (profiling events)
    double queue_ms = 0.0;   // queued -> start
};

class FieldEvaluator {
public:
    explicit FieldEvaluator(ocl::Device& device);

    // The field of `edits` (geometry frame, in order) at points given as packed x, y, z floats;
    // `meshes` is the mesh pool of mesh edits (construct/mesh_pool.h), empty when there are none.
    FieldEvalResult evaluate(std::span<const SdfEdit> edits, std::span<const float> xyz,
                             std::span<const float> meshes = {});

    ocl::Device& device() const { return device_; }
    const ocl::BuildRecord& build() const { return program_.record(); }

private:
    ocl::Device& device_;
    ocl::Program program_;
    ocl::Kernel kernel_;
};

// A planar slice through the scene's world bounds (padded by 5%), perpendicular to `axis`.
struct SliceSpec {
    int axis = 2;                   // 0 = x, 1 = y, 2 = z
    std::optional<double> offset;   // plane position along the axis; default: the bounds' centre
    int resolution = 512;           // pixels along the longer side
};

struct Slice {
    int width = 0, height = 0;
    int axis = 2;
    double offset = 0.0;
    glm::dvec3 origin{0.0};  // centre of pixel (0, 0) (the top-left pixel), world units
    glm::dvec3 du{0.0};      // one pixel to the right
    glm::dvec3 dv{0.0};      // one pixel down
    double pixel_size = 0.0;
    std::vector<float> values;  // width * height, row-major from the top
    double device_ms = 0.0;     // sum over the objects' kernel launches
    double queue_ms = 0.0;
    std::uint64_t edit_evaluations = 0;

    glm::dvec3 point(int x, int y) const { return origin + static_cast<double>(x) * du + static_cast<double>(y) * dv; }
};

// `scene` must already be at the wanted time (scene_at). Throws InputError for an empty scene.
Slice evaluate_slice(FieldEvaluator& evaluator, const Scene& scene, const SliceSpec& spec);

// Distance slice as a picture: orange outside, blue inside, contour bands every `band` world
// units (default: 1/20 of the slice width), a white line on the surface.
Image slice_image(const Slice& slice);

// The double-precision host reference at up to `max_samples` pixels spread evenly over a slice.
// It depends only on the slice's geometry, so one set serves every device's slice.
struct ReferenceSamples {
    std::vector<std::size_t> pixels;  // indices into Slice::values
    std::vector<double> values;
    double seconds = 0.0;  // host time taken
};
ReferenceSamples reference_samples(const Slice& slice, const Scene& scene, std::size_t max_samples);

// A slice from the kernel against the reference samples.
struct ReferenceCheck {
    std::size_t samples = 0;
    double max_abs_error = 0.0;
    double mean_abs_error = 0.0;
    std::size_t sign_mismatches = 0;  // pixels where the kernel and the reference disagree on inside/outside
};
ReferenceCheck check_against_reference(const Slice& slice, const ReferenceSamples& reference);

}  // namespace sdfbrick::reference
