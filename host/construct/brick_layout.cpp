#include "construct/brick_layout.h"

#include <algorithm>

#include <fmt/format.h>

namespace sdfbrick::construct {

std::string_view to_string(BrickFormat f) {
    switch (f) {
        case BrickFormat::int8: return "int8";
        case BrickFormat::int16: return "int16";
        case BrickFormat::float32: return "float";
    }
    return "?";
}

std::optional<BrickFormat> format_from_string(std::string_view s) {
    if (s == "int8") return BrickFormat::int8;
    if (s == "int16") return BrickFormat::int16;
    if (s == "float" || s == "float32") return BrickFormat::float32;
    return std::nullopt;
}

std::size_t BrickLayout::samples_per_brick() const {
    return static_cast<std::size_t>(samples) * static_cast<std::size_t>(samples) * static_cast<std::size_t>(samples);
}

std::array<std::size_t, 8> BrickLayout::owned_samples_by_octant(std::uint32_t mask) const {
    // length[h][c]: samples of one axis in half h (below or above S/2) with region code c (0: the
    // low apron, 1: the interior, 2: the high apron).
    const int half = samples / 2, bounds[4] = {0, apron(), samples - apron(), samples};
    std::size_t length[2][3];
    for (int h = 0; h < 2; ++h)
        for (int c = 0; c < 3; ++c)
            length[h][c] = static_cast<std::size_t>(
                std::max(0, std::min(bounds[c + 1], (h + 1) * half) - std::max(bounds[c], h * half)));
    std::array<std::size_t, 8> n{};
    for (int o = 0; o < 8; ++o)
        for (int r = 0; r < 27; ++r)
            if ((mask >> r) & 1u)
                n[static_cast<std::size_t>(o)] += length[o & 1][r % 3] * length[(o >> 1) & 1][r / 3 % 3] *
                                                  length[o >> 2][r / 9];
    return n;
}

std::size_t BrickLayout::sample_bytes() const {
    return format == BrickFormat::int8 ? 1 : format == BrickFormat::int16 ? 2 : 4;
}

double BrickLayout::levels() const {
    return format == BrickFormat::int8 ? 127.0 : format == BrickFormat::int16 ? 32767.0 : 1.0;
}

float BrickLayout::quantise_scale(float band) const {
    return format == BrickFormat::float32 ? 1.0f : static_cast<float>(levels() / band);
}

float BrickLayout::dequantise_scale(float band) const {
    return format == BrickFormat::float32 ? 1.0f : static_cast<float>(band / levels());
}

std::string BrickLayout::defines() const {
    return fmt::format("-DSAMPLES={} -DAPRON={} -DFORMAT={}", samples, apron(), format_code());
}

}  // namespace sdfbrick::construct
