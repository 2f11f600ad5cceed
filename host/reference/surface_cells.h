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

#include "construct/domain.h"
#include "scene/scene.h"

namespace sdfbrick::reference {


// Kept cells per level (size = domain.levels). Parallel over the parents of a level with std::thread
// (threads = 0: std::thread::hardware_concurrency()); the result does not depend on the thread count.
std::vector<std::uint64_t> count_surface_cells(const Geometry& g, const construct::Domain& domain, unsigned threads = 0);

// The kept leaf cells' integer coordinates (in leaf cells from the origin), sorted by (x, y, z).
std::vector<glm::ivec3> surface_cells(const Geometry& g, const construct::Domain& domain, unsigned threads = 0);

// The kept cells of every level, in construction order: level by level, children of each parent in
// the parent's order, and inside a parent in Morton order of the child's local coordinate (bit 3j of
// the child index = bit j of x, 3j+1 of y, 3j+2 of z). Coordinates are in cells of that level.
// Stores every level: meant for small scenes.
std::vector<std::vector<glm::ivec3>> surface_cells_by_level(const Geometry& g, const construct::Domain& domain,
                                                            unsigned threads = 0);

}  // namespace sdfbrick::reference
