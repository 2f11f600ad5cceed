// The scene's camera and objects as the tracers read them (kernels/sdf_types.h: SdfCamera,
// SdfInstance), and the per-pixel output both tracers write.
#pragma once

#include <CL/cl.h>

#include <cstddef>
#include <vector>

#include "scene/scene.h"
#include "sdf_types.h"

namespace sdfbrick::render {

// Largest image the tracers accept (DESIGN.md section 3: up to 3840 x 2160).
inline constexpr int kMaxWidth = 3840;
inline constexpr int kMaxHeight = 2160;

// Throws InputError ("--width") for a size outside 1..kMax*.
void validate_image_size(int width, int height);

// Camera basis computed in double, stored as floats (see SdfCamera).
SdfCamera make_camera(const Camera& camera, int width, int height);

// One SdfInstance per scene object, in the scene's order.
std::vector<SdfInstance> make_instances(const Scene& scene);

// What a tracer wrote for every pixel (row-major, top row first); see sdf_types.h for hit and aux.
struct RenderBuffer {
    int width = 0;
    int height = 0;
    std::vector<cl_float4> hit;
    std::vector<cl_uint2> aux;

    RenderBuffer() = default;
    RenderBuffer(int w, int h)
        : width(w), height(h), hit(static_cast<std::size_t>(w) * h), aux(static_cast<std::size_t>(w) * h) {}
    std::size_t pixels() const { return hit.size(); }
    bool is_hit(std::size_t i) const { return hit[i].s[3] >= 0.0f; }
};

}  // namespace sdfbrick::render
