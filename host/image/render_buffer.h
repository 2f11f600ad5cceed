// What a tracer writes for every pixel (RenderBuffer: hit = world normal and depth, aux = counters
// or flags; kernels/sdf_types.h), and the pictures every tracer's output has.
#pragma once

#include <CL/cl.h>

#include <cstddef>
#include <vector>

#include <glm/glm.hpp>

#include "image/image.h"
#include "sdf_types.h"

namespace sdfbrick {

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
    glm::dvec3 normal(std::size_t i) const {
        return {static_cast<double>(hit[i].s[0]), static_cast<double>(hit[i].s[1]), static_cast<double>(hit[i].s[2])};
    }
    // Throws std::invalid_argument naming `what` when the arrays do not match width x height.
    void check(const char* what) const;
};

// 3 channels: n * 0.5 + 0.5 (clamped to [0, 1]) on hits, black on misses; the source's normal view.
Image normal_image(const RenderBuffer& b);

// The colour of normal_image at pixel i, in double.
glm::dvec3 normal_colour(const RenderBuffer& b, std::size_t i);

// Sets pixel i of a 3-channel image.
void set_pixel(Image& im, std::size_t i, const glm::dvec3& c);

// 1 channel: the raw depth (world units along the ray) on hits, 0 on misses (a miss is told apart
// from a depth-0 hit only by the hit mask). Meant for float formats (EXR, PFM); 8-bit formats clamp.
Image depth_image(const RenderBuffer& b);

}  // namespace sdfbrick
