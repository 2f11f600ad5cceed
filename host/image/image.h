// Images: float pixels in memory; files through OpenImageIO when the build has it (PNG, EXR, TIFF,
// JPEG, ...), and the built-in PPM (8-bit) / PFM (float) writers always. Writes never leave a
// partial file behind (core/files.h).
#pragma once

#include <filesystem>
#include <vector>

#include "core/files.h"

namespace sdfbrick {

struct Image {
    int width = 0;
    int height = 0;
    int channels = 3;
    std::vector<float> pixels;  // row-major, top row first, channels interleaved; colours in [0, 1]

    Image() = default;
    Image(int w, int h, int c) : width(w), height(h), channels(c), pixels(static_cast<std::size_t>(w) * h * c, 0.0f) {}
    float* at(int x, int y) { return &pixels[(static_cast<std::size_t>(y) * width + x) * channels]; }
};

// Picks the format by extension. 8-bit formats get the values clamped to [0, 1].
// Throws InputError for an extension this build cannot write.
void write_image(const Image& image, const std::filesystem::path& path);

// The same as an output of write_all (core/files.h), for commands that write several files as one.
Output image_output(Image image, const std::filesystem::path& path);

// True when this build writes PNG/EXR (OpenImageIO present).
bool image_io_has_oiio();

}  // namespace sdfbrick
