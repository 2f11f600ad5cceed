// One geometry's brick set read back to the host: the leaf bricks, their samples as distances
// (geometry units), and the field the brick tracer sees (kernels/sdf_trace.h, tr_field): inside a
// leaf brick, the trilinear interpolation of that brick's own samples; no value outside the bricks.
// Adaptive builds' leaves of coarser levels have a voxel, band and quantisation step 2^shift times
// the finest (construct::BrickBuilder); each brick's samples are dequantised with its own step.
// What the exporters (exchange/vdb.h) and point sampling (exchange/sample.h) read.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <unordered_map>
#include <vector>

#include <glm/glm.hpp>

#include "construct/brick_builder.h"

namespace sdfbrick::exchange {

// Hash of a lattice coordinate (unordered containers keyed by brick or voxel coordinates).
struct CoordHash {
    std::size_t operator()(const glm::ivec3& c) const;
};

// The field and its gradient at a point (geometry units).
struct BrickSample {
    double distance = 0.0;
    glm::dvec3 gradient{0.0};
    double band = 0.0;  // the band of the brick that holds the point: |distance| >= band is saturated
};

class HostBricks {
public:
    // Reads the leaves and the pool of b (built with settings) back from the device.
    HostBricks(const construct::GeometryBuild& b, const construct::BuildSettings& settings);
    // About the host bytes one leaf brick of this layout takes here: its samples as floats, its
    // coordinate and its index entry.
    static double bytes_per_brick(const construct::BrickLayout& layout);

    std::size_t brick_count() const { return coords_.size(); }
    int samples() const { return samples_; }
    int apron() const { return apron_; }
    int interior() const { return samples_ - 2 * apron_; }
    double voxel() const { return voxel_; }      // of the finest level
    double band() const { return band_; }        // finest level: stored distances lie in [-band, band]
    double quantum() const { return quantum_; }  // finest level: one quantisation step (0 for float samples)
    const glm::dvec3& origin() const { return origin_; }
    // A brick's coordinate on its own level's lattice, and its shift: its voxel is voxel() * 2^shift.
    const glm::ivec3& coord(std::size_t brick) const { return coords_[brick]; }
    int shift(std::size_t brick) const { return shifts_[brick]; }
    // Sample (i, j, k) of a brick as a distance; it sits at
    // origin + (coord * interior + (i, j, k) - apron + 0.5) * voxel * 2^shift.
    float sample(std::size_t brick, int i, int j, int k) const {
        return values_[brick * samples_per_brick_ +
                       static_cast<std::size_t>(i + samples_ * (j + samples_ * k))];
    }
    // The finest-level brick holding the lattice cell coord, if there is one.
    std::optional<std::size_t> find(const glm::ivec3& coord) const;
    // The brick whose cell contains the finest-lattice cell coord, whatever its level.
    std::optional<std::size_t> covering(const glm::ivec3& coord) const;

    // The field at a geometry-frame point: the trilinear value and its gradient in the leaf brick
    // whose cell contains p; nullopt outside every brick.
    std::optional<BrickSample> at(const glm::dvec3& p) const;
    // The same in a given brick (p clamped to the span of its samples).
    BrickSample at(std::size_t brick, const glm::dvec3& p) const;

private:
    glm::dvec3 origin_{0.0};
    double leaf_size_ = 0.0, voxel_ = 0.0, band_ = 0.0, quantum_ = 0.0;
    int samples_ = 0, apron_ = 0;
    std::size_t samples_per_brick_ = 0;
    std::vector<glm::ivec3> coords_;
    std::vector<std::uint8_t> shifts_;
    std::vector<float> values_;
    // Per shift present, finest first: the bricks by coordinate.
    std::vector<std::pair<int, std::unordered_map<glm::ivec3, std::uint32_t, CoordHash>>> index_;
};

}  // namespace sdfbrick::exchange
