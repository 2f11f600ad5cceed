// The construction domain: the cube that encloses a geometry, cut into levels of cells (level 0 the
// cube, each level B^3 children per cell, the last level the leaf bricks), and the Morton order of
// the children inside a parent. Construction and its oracle (reference/surface_cells.h) share it.
#pragma once

#include <cstdint>

#include <glm/glm.hpp>

#include "scene/scene.h"

namespace sdfbrick::construct {

struct Domain {
    glm::dvec3 origin{0.0};  // the cube's low corner, on the leaf lattice
    double leaf_size = 1.0;  // side of a leaf cell
    int branching = 4;       // B: children per axis (a power of two, 2..16)
    int levels = 1;          // level 0 = the root cube, levels - 1 = the leaves

    // B^level: cells per axis at that level.
    std::int64_t cells_per_axis(int level) const;
    // leaf_size * B^(levels-1)
    double side() const;
    // leaf_size * B^(levels-1-level): level 0 = side(), levels-1 = leaf_size.
    double cell_size(int level) const;
    glm::dvec3 cell_centre(int level, const glm::ivec3& coord) const;
    // Lower corner of a cell.
    glm::dvec3 cell_lo(int level, const glm::ivec3& coord) const;
    // sqrt(3) / 2 * cell_size(level)
    double half_diagonal(int level) const;
};

// origin = floor(bounds.lo / leaf) * leaf; levels = the smallest count >= 1 whose cube from that
// origin reaches bounds.hi on every axis. Throws InputError on empty or non-finite bounds, and
// SettingError for leaf_size <= 0, a branching that is not a power of two in 2..16, or a leaf lattice
// beyond 2^30 cells per axis (setting leaf_size).
Domain make_domain(const Aabb& bounds, double leaf_size, int branching);

// The local coordinate (each component in [0, B)) of the child with Morton index i inside its parent.
glm::ivec3 morton_child(int branching, int index);

}  // namespace sdfbrick::construct
