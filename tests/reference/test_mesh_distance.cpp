// reference/mesh_distance.h: the brute-force distance and the winding number against the exact
// distance of the shapes the generated meshes approximate.
#include <gtest/gtest.h>

#include "core/rng.h"
#include "reference/mesh_distance.h"
#include "test_meshes.h"

namespace sdfbrick {
namespace {

TEST(ReferenceMeshDistance, SphereAndTorus) {
    const TriangleMesh sphere = icosphere(0.5, 4);
    const TriangleMesh torus = torus_mesh(0.4, 0.15, 96, 48);
    Rng rng(3);
    for (int n = 0; n < 200; ++n) {
        const glm::dvec3 p(rng.uniform(-0.8, 0.8), rng.uniform(-0.8, 0.8), rng.uniform(-0.8, 0.8));
        EXPECT_NEAR(reference::mesh_signed_distance(sphere, p), test::sphere_sdf(0.5, p), 1e-3);
        EXPECT_NEAR(reference::mesh_signed_distance(torus, p), test::torus_sdf(0.4, 0.15, p), 1.5e-3);
    }
}

TEST(ReferenceMeshDistance, WindingNumberCountsTheRing) {
    const TriangleMesh m = box_with_hole(0.5, 0.2, 0.15);
    EXPECT_NEAR(reference::winding_number(m, {0.35, 0.0, 0.0}), 1.0, 1e-9);  // in the ring
    EXPECT_NEAR(reference::winding_number(m, {0.0, 0.0, 0.0}), 0.0, 1e-9);   // in the hole
    EXPECT_NEAR(reference::winding_number(m, {2.0, 1.0, 0.5}), 0.0, 1e-9);
    EXPECT_NEAR(reference::mesh_signed_distance(m, {0.0, 0.0, 0.0}), 0.2, 1e-12);
    EXPECT_NEAR(reference::mesh_signed_distance(m, {0.35, 0.0, 0.1}), -0.05, 1e-12);
}

}  // namespace
}  // namespace sdfbrick
