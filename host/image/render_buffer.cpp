#include "image/render_buffer.h"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace sdfbrick {

void RenderBuffer::check(const char* what) const {
    const std::size_t n = static_cast<std::size_t>(std::max(width, 0)) * static_cast<std::size_t>(std::max(height, 0));
    if (width < 0 || height < 0 || hit.size() != n || aux.size() != n)
        throw std::invalid_argument(std::string("the ") + what + " render buffer's arrays do not match its size " +
                                    std::to_string(width) + " x " + std::to_string(height));
}

glm::dvec3 normal_colour(const RenderBuffer& b, std::size_t i) {
    if (!b.is_hit(i)) return glm::dvec3(0.0);
    return glm::clamp(b.normal(i) * 0.5 + 0.5, 0.0, 1.0);
}

void set_pixel(Image& im, std::size_t i, const glm::dvec3& c) {
    for (int k = 0; k < 3; ++k) im.pixels[i * 3 + static_cast<std::size_t>(k)] = static_cast<float>(c[k]);
}

Image normal_image(const RenderBuffer& b) {
    b.check("input");
    Image im(b.width, b.height, 3);
    for (std::size_t i = 0; i < b.pixels(); ++i) set_pixel(im, i, normal_colour(b, i));
    return im;
}

Image depth_image(const RenderBuffer& b) {
    b.check("input");
    Image im(b.width, b.height, 1);
    for (std::size_t i = 0; i < b.pixels(); ++i) im.pixels[i] = b.is_hit(i) ? b.hit[i].s[3] : 0.0f;
    return im;
}

}  // namespace sdfbrick
