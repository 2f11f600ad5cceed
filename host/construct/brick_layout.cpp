#include "construct/brick_layout.h"

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

std::size_t BrickLayout::owned_samples(std::uint32_t mask) const {
    std::size_t n = 0;
    for (int r = 0; r < 27; ++r) {
        if (((mask >> r) & 1u) == 0) continue;
        std::size_t size = 1;
        for (int axis = 0, code = r; axis < 3; ++axis, code /= 3)
            size *= static_cast<std::size_t>(code % 3 == 1 ? interior() : apron());
        n += size;
    }
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
