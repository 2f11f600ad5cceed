// The reference for the sparse brick hierarchy: which cells of each level the top-down
// construction keeps. Written to stay obviously correct: no edit culling (the whole edit list is
// evaluated at every tested centre, with reference::evaluate in double precision).
//
// Rule: the root cell (level 0, the domain's cube) is kept if |F(centre)| <= half its diagonal; each
// kept cell's B^3 children are tested the same way; the kept cells of the last level are the surface
// (leaf) cells. Because the field is 1-Lipschitz, a cell that passes the test has ancestors that all
// pass it too, so the kept set of a level is exactly { cells of that level that pass the test }
// (up to rounding at exact ties) and does not depend on B: the tests rely on this.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "scene/scene.h"

namespace sdfbrick::reference {

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
// origin reaches bounds.hi on every axis. Throws InputError on empty or non-finite bounds, leaf_size
// <= 0, a branching that is not a power of two in 2..16, or a leaf lattice beyond 2^30 cells per axis.
Domain make_domain(const Aabb& bounds, double leaf_size, int branching);

// Kept cells per level (size = domain.levels). Parallel over the parents of a level with std::thread
// (threads = 0: std::thread::hardware_concurrency()); the result does not depend on the thread count.
std::vector<std::uint64_t> count_surface_cells(const Geometry& g, const Domain& domain, unsigned threads = 0);

// The kept leaf cells' integer coordinates (in leaf cells from the origin), sorted by (x, y, z).
std::vector<glm::ivec3> surface_cells(const Geometry& g, const Domain& domain, unsigned threads = 0);

// The kept cells of every level, in construction order: level by level, children of each parent in
// the parent's order, and inside a parent in Morton order of the child's local coordinate (bit 3j of
// the child index = bit j of x, 3j+1 of y, 3j+2 of z). Coordinates are in cells of that level.
// Stores every level: meant for small scenes.
std::vector<std::vector<glm::ivec3>> surface_cells_by_level(const Geometry& g, const Domain& domain,
                                                            unsigned threads = 0);

// The local coordinate (each component in [0, B)) of the child with Morton index i inside its parent.
glm::ivec3 morton_child(int branching, int index);

}  // namespace sdfbrick::reference
