// The brick layout: how a leaf brick's samples are stored in the brick pool. One owner for the sample
// count and apron, the storage format and its quantisation, and the kernel defines that tell the
// construction and tracing kernels the same (kernels/sdf_format.h, brick_evaluate.cl, sdf_trace.h).
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

namespace sdfbrick::construct {

enum class BrickFormat { int8, int16, float32 };  // int8 / int16: snorm over +-band; float32: the value
std::string_view to_string(BrickFormat f);         // "int8", "int16", "float"
std::optional<BrickFormat> format_from_string(std::string_view s);

struct BrickLayout {
    int samples = 8;  // per axis: 8 (one-voxel apron) or 10 (two-voxel apron)
    BrickFormat format = BrickFormat::int8;

    int apron() const { return samples == 10 ? 2 : 1; }
    int interior() const { return samples - 2 * apron(); }  // voxels per brick side: 6 in both layouts
    std::size_t samples_per_brick() const;                  // samples^3
    // Samples a brick evaluates itself when it owns the apron regions of mask: bit r = (dx + 1) +
    // 3 (dy + 1) + 9 (dz + 1) for the region towards direction d, bit 13 the interior (kernels/sdf_apron.h).
    std::size_t owned_samples(std::uint32_t mask) const;
    std::size_t sample_bytes() const;                       // 1, 2 or 4
    std::size_t brick_bytes() const { return samples_per_brick() * sample_bytes(); }
    // The snorm range: a stored s means s * band / levels(); 127, 32767, or 1 for float (not scaled).
    double levels() const;
    // Stored value per distance unit for a band (the evaluation kernel's scale): levels / band, 1 for float.
    float quantise_scale(float band) const;
    // Distance per stored unit (the tracer's): band / levels, 1 for float.
    float dequantise_scale(float band) const;
    // The FORMAT value of the kernels: 0 int8, 1 int16, 2 float32.
    int format_code() const { return static_cast<int>(format); }
    // "-DSAMPLES=S -DAPRON=A -DFORMAT=F": the build options every kernel that reads or writes the pool takes.
    std::string defines() const;
};

}  // namespace sdfbrick::construct
