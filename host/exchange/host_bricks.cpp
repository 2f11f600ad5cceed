#include "exchange/host_bricks.h"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace sdfbrick::exchange {

namespace {

// The pool's samples as distances: stored value * the brick's dequantisation scale (the finest
// level's times 2^shift), in float as the tracer does.
template <class T>
std::vector<float> dequantise(const std::vector<std::uint8_t>& pool, const std::vector<std::uint8_t>& shifts,
                              std::size_t per_brick, float dequant) {
    std::vector<float> out(pool.size() / sizeof(T));
    for (std::size_t n = 0; n < out.size(); ++n) {
        T v;
        std::memcpy(&v, pool.data() + n * sizeof(T), sizeof(T));
        out[n] = static_cast<float>(v) * std::ldexp(dequant, shifts[n / per_brick]);
    }
    return out;
}

}  // namespace

std::size_t CoordHash::operator()(const glm::ivec3& c) const {
    const auto u = [](int v) { return static_cast<std::uint64_t>(static_cast<std::uint32_t>(v)); };
    return static_cast<std::size_t>((u(c.x) * 0x9E3779B97F4A7C15ull) ^ (u(c.y) * 0xC2B2AE3D27D4EB4Full) ^
                                    (u(c.z) * 0x165667B19E3779F9ull));
}

HostBricks::HostBricks(const construct::GeometryBuild& b, const construct::BuildSettings& settings) {
    const construct::BrickLayout layout = settings.layout();
    origin_ = glm::dvec3(b.origin);
    leaf_size_ = b.leaf_size;
    samples_ = layout.samples;
    apron_ = layout.apron();
    samples_per_brick_ = layout.samples_per_brick();
    voxel_ = static_cast<double>(static_cast<float>(settings.voxel()));  // the float the kernels use
    band_ = b.band;
    const float dequant = layout.dequantise_scale(b.band);
    quantum_ = layout.format == construct::BrickFormat::float32 ? 0.0 : static_cast<double>(dequant);
    if (b.leaf_count == 0) return;

    const std::vector<SdfBrick> leaves = b.leaves->read();
    const int log2b = b.branching == 2 ? 1 : 2;
    coords_.reserve(leaves.size());
    shifts_.reserve(leaves.size());
    for (const SdfBrick& leaf : leaves) {
        const int shift = (b.levels - 1 - static_cast<int>(leaf.level)) * log2b;
        auto level = std::find_if(index_.begin(), index_.end(), [&](const auto& l) { return l.first == shift; });
        if (level == index_.end()) level = index_.insert(index_.end(), {shift, {}});
        level->second.emplace(glm::ivec3(leaf.coord[0], leaf.coord[1], leaf.coord[2]),
                              static_cast<std::uint32_t>(coords_.size()));
        coords_.emplace_back(leaf.coord[0], leaf.coord[1], leaf.coord[2]);
        shifts_.push_back(static_cast<std::uint8_t>(shift));
    }
    std::sort(index_.begin(), index_.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
    const std::vector<std::uint8_t> pool = b.pool->read();
    const auto n = samples_per_brick_;
    switch (layout.format) {
        case construct::BrickFormat::int8: values_ = dequantise<std::int8_t>(pool, shifts_, n, dequant); break;
        case construct::BrickFormat::int16: values_ = dequantise<std::int16_t>(pool, shifts_, n, dequant); break;
        case construct::BrickFormat::float32: values_ = dequantise<float>(pool, shifts_, n, 1.0f); break;
    }
}

double HostBricks::bytes_per_brick(const construct::BrickLayout& layout) {
    return static_cast<double>(layout.samples_per_brick() * sizeof(float) + sizeof(glm::ivec3)) + 48.0;
}

std::optional<std::size_t> HostBricks::find(const glm::ivec3& coord) const {
    if (index_.empty() || index_.front().first != 0) return std::nullopt;
    const auto it = index_.front().second.find(coord);
    if (it == index_.front().second.end()) return std::nullopt;
    return it->second;
}

std::optional<std::size_t> HostBricks::covering(const glm::ivec3& coord) const {
    for (const auto& [shift, index] : index_) {
        // floor division by 2^shift (an arithmetic shift rounds towards minus infinity)
        const auto it = index.find(glm::ivec3(coord.x >> shift, coord.y >> shift, coord.z >> shift));
        if (it != index.end()) return it->second;
    }
    return std::nullopt;
}

std::optional<BrickSample> HostBricks::at(const glm::dvec3& p) const {
    const glm::dvec3 cell = (p - origin_) / leaf_size_;
    if (!(std::abs(cell.x) < 2e9 && std::abs(cell.y) < 2e9 && std::abs(cell.z) < 2e9)) return std::nullopt;
    const std::optional<std::size_t> brick = covering(glm::ivec3(glm::floor(cell)));
    if (!brick) return std::nullopt;
    return at(*brick, p);
}

BrickSample HostBricks::at(std::size_t brick, const glm::dvec3& p) const {
    // Sample space of the brick (sdf_trace.h): sample (i, j, k) at s = (i, j, k).
    const double scale = std::ldexp(1.0, shift(brick)), voxel = voxel_ * scale;
    const glm::dvec3 lo = origin_ + glm::dvec3(coords_[brick]) * (leaf_size_ * scale);
    const glm::dvec3 s = glm::clamp((p - lo) / voxel + (apron_ - 0.5), 0.0, samples_ - 1.0);
    const glm::ivec3 c = glm::min(glm::ivec3(glm::floor(s)), glm::ivec3(samples_ - 2));
    const glm::dvec3 f = s - glm::dvec3(c);
    double v[8];
    for (int n = 0; n < 8; ++n) v[n] = sample(brick, c.x + (n & 1), c.y + ((n >> 1) & 1), c.z + (n >> 2));
    // Trilinear value and its exact derivative, x first, then y, then z.
    const auto lerp = [](double a, double b, double t) { return a + (b - a) * t; };
    const double x00 = lerp(v[0], v[1], f.x), x10 = lerp(v[2], v[3], f.x);
    const double x01 = lerp(v[4], v[5], f.x), x11 = lerp(v[6], v[7], f.x);
    const double y0 = lerp(x00, x10, f.y), y1 = lerp(x01, x11, f.y);
    BrickSample out;
    out.distance = lerp(y0, y1, f.z);
    const double dx00 = v[1] - v[0], dx10 = v[3] - v[2], dx01 = v[5] - v[4], dx11 = v[7] - v[6];
    out.gradient.x = lerp(lerp(dx00, dx10, f.y), lerp(dx01, dx11, f.y), f.z);
    out.gradient.y = lerp(x10 - x00, x11 - x01, f.z);
    out.gradient.z = y1 - y0;
    out.gradient /= voxel;
    out.band = band_ * scale;
    return out;
}

}  // namespace sdfbrick::exchange
