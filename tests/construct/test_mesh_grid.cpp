// construct/mesh_grid.h: meshes generated in the test converted on the test device, against the
// exact distance of the shape they approximate (sphere, torus) and against the independent
// double-precision brute-force reference (reference/mesh_distance.h) for a box with a hole.
#include <cmath>

#include <gtest/gtest.h>

#include "construct/mesh_grid.h"
#include "reference/mesh_distance.h"
#include "test_meshes.h"
#include "test_support.h"

namespace sdfbrick {
namespace {

construct::MeshGrid convert(const TriangleMesh& m, int resolution) {
    static construct::MeshGridBuilder builder(test::device());
    return builder.build(m, {construct::cell_for_resolution(m, resolution), 2}, test::recorder());
}

// Largest |grid - f| over every grid point.
template <class F>
double max_error(const construct::MeshGrid& g, F f) {
    double worst = 0.0;
    for (int k = 0; k < g.dims.z; ++k)
        for (int j = 0; j < g.dims.y; ++j)
            for (int i = 0; i < g.dims.x; ++i)
                worst = std::max(worst, std::abs(g.at(i, j, k) - f(g.origin + g.cell * glm::dvec3(i, j, k))));
    return worst;
}

TEST(ConstructMeshGrid, IcosphereIsTheSphere) {
    const TriangleMesh m = icosphere(0.5, 4);  // 5120 triangles, chord error below 4e-4
    const construct::MeshGrid g = convert(m, 40);
    EXPECT_EQ(g.dims, glm::ivec3(45));
    EXPECT_LT(max_error(g, [](const glm::dvec3& p) { return test::sphere_sdf(0.5, p); }), 1e-3);
}

TEST(ConstructMeshGrid, TorusIsTheTorus) {
    const TriangleMesh m = torus_mesh(0.4, 0.15, 96, 48);  // chord errors below 4e-4
    const construct::MeshGrid g = convert(m, 48);
    EXPECT_LT(max_error(g, [](const glm::dvec3& p) { return test::torus_sdf(0.4, 0.15, p); }), 1.5e-3);
}

TEST(ConstructMeshGrid, BoxWithHoleIsTheBruteForceReference) {
    const TriangleMesh m = box_with_hole(0.5, 0.2, 0.15);
    const construct::MeshGrid g = convert(m, 24);
    EXPECT_LT(max_error(g, [&](const glm::dvec3& p) { return reference::mesh_signed_distance(m, p); }), 2e-6);
    // The hole is outside, the ring inside.
    const glm::dvec3 centre = (glm::dvec3(0.0) - g.origin) / g.cell;
    EXPECT_GT(g.at(int(std::lround(centre.x)), int(std::lround(centre.y)), int(std::lround(centre.z))), 0.15f);
}

TEST(ConstructMeshGrid, TreeIsShallowAndConversionRepeatable) {
    const TriangleMesh m = torus_mesh(0.4, 0.15, 64, 32);
    const construct::MeshBvh bvh = construct::build_mesh_bvh(m);
    EXPECT_EQ(bvh.nodes.size(), m.triangles.size() - 1);
    EXPECT_LE(bvh.depth, static_cast<int>(std::ceil(std::log2(m.triangles.size()))));
    const construct::MeshGrid a = convert(m, 20), b = convert(m, 20);
    EXPECT_EQ(a.values, b.values);
}

}  // namespace
}  // namespace sdfbrick
