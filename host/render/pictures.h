// Pictures for people of the brick tracer's per-pixel counters (aux, see kernels/trace.cl).
#pragma once

#include <cstdint>

#include "image/image.h"
#include "image/render_buffer.h"

namespace sdfbrick::render {

// Heat map of the work per pixel: BVH node visits + in-brick steps, on a black-blue-red-yellow-white
// ramp scaled to the image's largest count. Misses are coloured by the work they took, too.
Image steps_image(const RenderBuffer& b);
// Each brick in its own colour (a hash of its global index); misses black.
Image brick_image(const RenderBuffer& b);
// 1 on hits, 0 on misses (one channel).
Image mask_image(const RenderBuffer& b);

// Mean BVH node visits and in-brick steps per pixel, and the rays whose search in some brick stopped
// at a kernel loop bound (SDF_TRACE_CAPPED: the answer there may be a miss that should be a hit).
struct WorkCounts {
    double node_visits = 0.0;
    double brick_steps = 0.0;
    std::uint64_t capped_rays = 0;
};
WorkCounts work_counts(const RenderBuffer& b);

// The same counters as sums over some pixels (a band of rows, or the whole image): what the tracer
// reduces on the device (kernels/trace_counts.cl). Sums of bands add up to the image's.
struct WorkTotals {
    std::uint64_t node_visits = 0, brick_steps = 0, capped_rays = 0;
    std::uint64_t pixels = 0;  // of the image the means are taken over
    WorkTotals& operator+=(const WorkTotals& o);
    WorkCounts per_pixel() const;
};

}  // namespace sdfbrick::render
