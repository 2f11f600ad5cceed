#include "render/pictures.h"

#include <algorithm>
#include <array>
#include <cstdint>

namespace sdfbrick::render {
namespace {

unsigned visits(const cl_uint2& a) { return a.s[1] & 0xFFFFu; }
unsigned steps(const cl_uint2& a) { return (a.s[1] >> 16) & 0x7FFFu; }

}  // namespace

Image steps_image(const RenderBuffer& b) {
    Image out(b.width, b.height, 3);
    unsigned most = 1;
    for (const cl_uint2& a : b.aux) most = std::max(most, visits(a) + steps(a));
    static constexpr std::array<std::array<float, 3>, 5> ramp{
        {{0.0f, 0.0f, 0.0f}, {0.1f, 0.2f, 0.9f}, {0.9f, 0.1f, 0.1f}, {1.0f, 0.9f, 0.1f}, {1.0f, 1.0f, 1.0f}}};
    for (std::size_t i = 0; i < b.pixels(); ++i) {
        const float x = static_cast<float>(visits(b.aux[i]) + steps(b.aux[i])) / static_cast<float>(most) * 4.0f;
        const auto k = std::min<std::size_t>(static_cast<std::size_t>(x), 3);
        const float f = x - static_cast<float>(k);
        for (int c = 0; c < 3; ++c) out.pixels[3 * i + c] = ramp[k][c] + (ramp[k + 1][c] - ramp[k][c]) * f;
    }
    return out;
}

Image brick_image(const RenderBuffer& b) {
    Image out(b.width, b.height, 3);
    for (std::size_t i = 0; i < b.pixels(); ++i) {
        if (b.aux[i].s[0] == SDF_NO_BRICK) continue;
        std::uint32_t h = b.aux[i].s[0] * 0x9E3779B9u;
        h ^= h >> 15;
        h *= 0x85EBCA6Bu;
        h ^= h >> 13;
        for (int c = 0; c < 3; ++c) out.pixels[3 * i + c] = 0.25f + 0.75f * static_cast<float>((h >> (8 * c)) & 0xFF) / 255.0f;
    }
    return out;
}

Image mask_image(const RenderBuffer& b) {
    Image out(b.width, b.height, 1);
    for (std::size_t i = 0; i < b.pixels(); ++i) out.pixels[i] = b.is_hit(i) ? 1.0f : 0.0f;
    return out;
}

WorkCounts work_counts(const RenderBuffer& b) {
    WorkCounts w;
    for (const cl_uint2& a : b.aux) {
        w.node_visits += visits(a);
        w.brick_steps += steps(a);
        w.capped_rays += (a.s[1] & SDF_TRACE_CAPPED) != 0u;
    }
    if (b.pixels() > 0) {
        w.node_visits /= static_cast<double>(b.pixels());
        w.brick_steps /= static_cast<double>(b.pixels());
    }
    return w;
}

WorkTotals& WorkTotals::operator+=(const WorkTotals& o) {
    node_visits += o.node_visits;
    brick_steps += o.brick_steps;
    capped_rays += o.capped_rays;
    return *this;
}

WorkCounts WorkTotals::per_pixel() const {
    WorkCounts w;
    w.capped_rays = capped_rays;
    if (pixels > 0) {
        w.node_visits = static_cast<double>(node_visits) / static_cast<double>(pixels);
        w.brick_steps = static_cast<double>(brick_steps) / static_cast<double>(pixels);
    }
    return w;
}

}  // namespace sdfbrick::render
