// The exact signed distances of the smooth shapes that the generated meshes of scene/mesh.h
// approach (icosphere, torus_mesh).
#pragma once

#include <glm/glm.hpp>

namespace sdfbrick::test {

inline double sphere_sdf(double r, const glm::dvec3& p) { return glm::length(p) - r; }

inline double torus_sdf(double R, double r, const glm::dvec3& p) {
    return glm::length(glm::dvec2(glm::length(glm::dvec2(p.x, p.z)) - R, p.y)) - r;
}

}  // namespace sdfbrick::test
