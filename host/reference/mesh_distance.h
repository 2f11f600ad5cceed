// The double-precision host reference of a mesh's signed distance, independent of the device
// conversion (construct/mesh_grid.h): brute force over every triangle for the distance (the
// nearest of the plane projection when it falls inside the triangle and the three edge segments),
// and the generalised winding number (the sum of the triangles' solid angles over 4 pi) for the
// sign, which needs no pseudo-normals and no nearest feature. Slow by design: O(triangles) a point.
#pragma once

#include <vector>

#include <glm/glm.hpp>

#include "scene/mesh.h"

namespace sdfbrick::reference {

// Unsigned distance from p to the nearest triangle.
double mesh_unsigned_distance(const TriangleMesh& mesh, const glm::dvec3& p);
// Winding number of the mesh around p: ~1 inside a closed, outward-oriented mesh, ~0 outside.
double winding_number(const TriangleMesh& mesh, const glm::dvec3& p);
// Negative inside (winding number above 1/2).
double mesh_signed_distance(const TriangleMesh& mesh, const glm::dvec3& p);

// A level set's distance, where the file's samples are the truth: the trilinear interpolant of the
// grid's values in double, and outside the grid's box the distance to the box plus the interpolant
// at its nearest point (the continuation every sampled grid uses).
double grid_distance(const GridFrame& frame, const std::vector<float>& values, const glm::dvec3& p);

}  // namespace sdfbrick::reference
