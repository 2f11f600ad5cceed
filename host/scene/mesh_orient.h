// Orienting a closed mesh as users have them: triangles wound inward (common in exported files), or
// inward in one part and outward in another, are turned to one consistent rule before the mesh's
// distance is computed (the device conversion and the host reference both read the oriented mesh).
#pragma once

#include <cstddef>
#include <string>

#include "scene/mesh.h"

namespace sdfbrick {

// What orient() changed.
struct MeshOrientation {
    std::size_t components = 0;          // connected by shared edges
    std::size_t against_neighbours = 0;  // triangles that disagreed with most of their component
    std::size_t turned_components = 0;   // components wound (mostly) inward, or cavities wound outward
    std::size_t cavities = 0;            // components inside an odd number of others (wound inward by the rule)
    std::size_t turned_triangles = 0;    // triangles whose winding changed, all causes
    bool changed() const { return turned_triangles > 0; }
    // One line: what was turned ("" when nothing was).
    std::string describe() const;
};

// Orients a closed, manifold mesh (every edge shared by exactly two triangles): within each
// connected component every shared edge is traversed once each way (the first triangle's winding
// spreads over the component), then each component faces outward (positive signed volume), except
// one lying inside an odd number of other components (its bounds within theirs, a vertex at winding
// number magnitude above 1/2), which is a cavity and faces inward. A mesh already wound that way is
// left bit for bit as it was. Throws InputError for a component that cannot be oriented
// consistently (a Moebius-like surface; naming a triangle) or that encloses no volume.
MeshOrientation orient(TriangleMesh& mesh);

// The triangles with their winding reversed (tests and generators: an inward-wound copy).
void reverse_winding(TriangleMesh& mesh);

}  // namespace sdfbrick
