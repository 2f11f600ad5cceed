#include "construct/domain.h"

#include <algorithm>
#include <cmath>
#include <string>

#include <fmt/format.h>

#include "core/errors.h"

namespace sdfbrick::construct {
namespace {

int log2_exact(int b) {
    int bits = 0;
    while ((1 << bits) < b) ++bits;
    return bits;
}

bool valid_branching(int b) { return b >= 2 && b <= 16 && (b & (b - 1)) == 0; }

}  // namespace

std::int64_t Domain::cells_per_axis(int level) const {
    std::int64_t n = 1;
    for (int i = 0; i < level; ++i) n *= branching;
    return n;
}

double Domain::side() const { return leaf_size * static_cast<double>(cells_per_axis(levels - 1)); }

double Domain::cell_size(int level) const {
    return leaf_size * static_cast<double>(cells_per_axis(levels - 1 - level));
}

glm::dvec3 Domain::cell_lo(int level, const glm::ivec3& c) const {
    return origin + glm::dvec3(c) * cell_size(level);
}

glm::dvec3 Domain::cell_centre(int level, const glm::ivec3& c) const {
    return origin + (glm::dvec3(c) + 0.5) * cell_size(level);
}

double Domain::half_diagonal(int level) const { return 0.5 * std::sqrt(3.0) * cell_size(level); }

glm::ivec3 morton_child(int branching, int index) {
    const int bits = log2_exact(branching);
    glm::ivec3 c(0);
    for (int j = 0; j < bits; ++j) {
        c.x |= ((index >> (3 * j)) & 1) << j;
        c.y |= ((index >> (3 * j + 1)) & 1) << j;
        c.z |= ((index >> (3 * j + 2)) & 1) << j;
    }
    return c;
}

Domain make_domain(const Aabb& bounds, double leaf_size, int branching) {
    if (bounds.empty()) throw InputError("make_domain: the bounds are empty");
    for (int a = 0; a < 3; ++a)
        if (!std::isfinite(bounds.lo[a]) || !std::isfinite(bounds.hi[a]))
            throw InputError("make_domain: the bounds are not finite");
    if (!(leaf_size > 0.0) || !std::isfinite(leaf_size))
        throw SettingError("leaf_size", fmt::format("leaf_size must be > 0, got {}", leaf_size));
    if (!valid_branching(branching))
        throw SettingError("branching", "branching must be a power of two in 2..16, got " + std::to_string(branching));
    Domain d;
    d.leaf_size = leaf_size;
    d.branching = branching;
    d.origin = glm::floor(bounds.lo / leaf_size) * leaf_size;
    const glm::dvec3 need = bounds.hi - d.origin;
    const double reach = std::max(need.x, std::max(need.y, need.z));
    d.levels = 1;
    while (d.side() < reach) {
        if (d.cells_per_axis(d.levels) > (std::int64_t{1} << 30))
            throw SettingError("leaf_size", fmt::format("leaf_size {} is too small for the bounds: more than 2^30 "
                                                        "leaf cells per axis",
                                                        leaf_size));
        ++d.levels;
    }
    return d;
}

}  // namespace sdfbrick::construct
