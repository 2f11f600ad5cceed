#include "image/image.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <ostream>
#include <string>

#include <fmt/format.h>

#ifdef SDFBRICK_WITH_OIIO
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>
#endif

#include "core/errors.h"
#include "core/files.h"

namespace sdfbrick {

namespace {

std::uint8_t to_byte(float v) { return static_cast<std::uint8_t>(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f)); }

void write_ppm(const Image& img, const std::filesystem::path& path, std::ostream& out) {
    if (img.channels != 3 && img.channels != 1) throw InputError(path.string() + ": PPM/PGM needs 1 or 3 channels");
    out << (img.channels == 3 ? "P6\n" : "P5\n") << img.width << ' ' << img.height << "\n255\n";
    std::vector<std::uint8_t> bytes(img.pixels.size());
    std::transform(img.pixels.begin(), img.pixels.end(), bytes.begin(), to_byte);
    out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
}

void write_pfm(const Image& img, const std::filesystem::path& path, std::ostream& out) {
    if (img.channels != 3 && img.channels != 1) throw InputError(path.string() + ": PFM needs 1 or 3 channels");
    // Little-endian (negative scale); PFM stores the bottom row first.
    out << (img.channels == 3 ? "PF\n" : "Pf\n") << img.width << ' ' << img.height << "\n-1.0\n";
    const std::size_t row = static_cast<std::size_t>(img.width) * img.channels;
    for (int y = img.height - 1; y >= 0; --y)
        out.write(reinterpret_cast<const char*>(&img.pixels[static_cast<std::size_t>(y) * row]),
                  static_cast<std::streamsize>(row * sizeof(float)));
}

#ifdef SDFBRICK_WITH_OIIO
// Encodes through OpenImageIO into memory (its I/O proxy), so that the bytes reach the file through
// the caller's checked writes: a short write is an error, never a truncated picture.
void write_oiio(const Image& img, const std::filesystem::path& path, std::ostream& os) {
    auto out = OIIO::ImageOutput::create(path.string());
    if (!out) throw InputError(fmt::format("{}: cannot write this format: {}", path.string(), OIIO::geterror()));
    if (!out->supports("ioproxy"))
        throw InputError(fmt::format("{}: OpenImageIO cannot write {} to memory; write .png, .exr, .tif or .jpg", path.string(),
                                     out->format_name()));
    std::vector<unsigned char> encoded;
    OIIO::Filesystem::IOVecOutput memory(encoded);
    out->set_ioproxy(&memory);
    const std::string ext = path.extension().string();
    const bool is_float = out->supports("channelformat:float") && (ext == ".exr" || ext == ".tif" || ext == ".tiff");
    OIIO::ImageSpec spec(img.width, img.height, img.channels, is_float ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::UINT8);
    if (!out->open(path.string(), spec)) throw InputError(fmt::format("{}: {}", path.string(), out->geterror()));
    bool ok;
    if (is_float) {
        ok = out->write_image(OIIO::TypeDesc::FLOAT, img.pixels.data());
    } else {
        std::vector<std::uint8_t> bytes(img.pixels.size());
        std::transform(img.pixels.begin(), img.pixels.end(), bytes.begin(), to_byte);
        ok = out->write_image(OIIO::TypeDesc::UINT8, bytes.data());
    }
    if (!ok || !out->close()) throw InputError(fmt::format("{}: {}", path.string(), out->geterror()));
    os.write(reinterpret_cast<const char*>(encoded.data()), static_cast<std::streamsize>(encoded.size()));
}
#endif

}  // namespace

bool image_io_has_oiio() {
#ifdef SDFBRICK_WITH_OIIO
    return true;
#else
    return false;
#endif
}

Output image_output(Image image, const std::filesystem::path& path) {
    std::string ext = path.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return {path, [image = std::move(image), ext, path](std::ostream& out) {
                if (ext == ".ppm" || ext == ".pgm") return write_ppm(image, path, out);
                if (ext == ".pfm") return write_pfm(image, path, out);
#ifdef SDFBRICK_WITH_OIIO
                write_oiio(image, path, out);
#else
                throw InputError(fmt::format("{}: this build has no OpenImageIO (configured with SDFBRICK_WITH_OIIO=OFF): "
                                             "write .ppm or .pfm instead", path.string()));
#endif
            }};
}

void write_image(const Image& image, const std::filesystem::path& path) { write_all({image_output(image, path)}); }

}  // namespace sdfbrick
