// Orienting meshes as users have them: inward, mixed and cavity windings turned to the one rule
// (outward, cavities inward), outward meshes left bit for bit, one-sided and flat meshes refused.
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/errors.h"
#include "core/rng.h"
#include "scene/mesh.h"
#include "scene/mesh_orient.h"
#include "test_support.h"

namespace sdfbrick {
namespace {

// Every mesh the project ships or generates, wound outward.
std::vector<std::pair<std::string, TriangleMesh>> outward_meshes() {
    return {{"icosphere", icosphere(0.5, 2)},
            {"torus", torus_mesh(0.4, 0.15, 24, 12)},
            {"box_with_hole", box_with_hole(0.4, 0.15, 0.2)},
            {"gear.obj", load_mesh(std::filesystem::path(SDFBRICK_SOURCE_DIR) / "scenes" / "gear.obj")}};
}

// Two meshes as one file: b's vertices after a's.
TriangleMesh joined(TriangleMesh a, const TriangleMesh& b) {
    const auto base = static_cast<std::uint32_t>(a.vertices.size());
    a.vertices.insert(a.vertices.end(), b.vertices.begin(), b.vertices.end());
    for (auto t : b.triangles) a.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
    return a;
}

TEST(SceneMeshOrient, OutwardMeshesAreLeftAsTheyAre) {
    for (auto [name, mesh] : outward_meshes()) {
        const TriangleMesh before = mesh;
        const MeshOrientation o = orient(mesh);
        EXPECT_FALSE(o.changed()) << name << ": " << o.describe();
        EXPECT_EQ(o.describe(), "") << name;
        EXPECT_EQ(mesh.triangles, before.triangles) << name;
    }
}

TEST(SceneMeshOrient, InwardAndMixedWindingsTurnBackToOutward) {
    Rng rng(5);
    for (auto [name, mesh] : outward_meshes()) {
        TriangleMesh inward = mesh;
        reverse_winding(inward);
        const MeshOrientation o = orient(inward);
        EXPECT_EQ(inward.triangles, mesh.triangles) << name;
        EXPECT_EQ(o.turned_components, o.components) << name;
        EXPECT_EQ(o.turned_triangles, mesh.triangles.size()) << name;
        EXPECT_NE(o.describe().find("turned"), std::string::npos) << name;

        TriangleMesh mixed = mesh;  // a random third of the triangles reversed, the first among them
        for (std::size_t t = 0; t < mixed.triangles.size(); ++t)
            if (t == 0 || rng.uniform(0.0, 1.0) < 0.33) std::swap(mixed.triangles[t][1], mixed.triangles[t][2]);
        const MeshOrientation m = orient(mixed);
        EXPECT_EQ(mixed.triangles, mesh.triangles) << name;
        EXPECT_GT(m.against_neighbours, 0u) << name;
    }
}

// A hollow ball: the inner shell is a cavity and faces inward, however the file winds either shell.
TEST(SceneMeshOrient, ACavityFacesInward) {
    TriangleMesh inner = icosphere(0.25, 1);
    reverse_winding(inner);
    const TriangleMesh hollow = joined(icosphere(0.5, 2), inner);
    for (const bool outer_in : {false, true})
        for (const bool inner_out : {false, true}) {
            TriangleMesh m = hollow;
            const std::size_t split = icosphere(0.5, 2).triangles.size();
            for (std::size_t t = 0; t < m.triangles.size(); ++t)
                if ((t < split && outer_in) || (t >= split && inner_out)) std::swap(m.triangles[t][1], m.triangles[t][2]);
            const MeshOrientation o = orient(m);
            EXPECT_EQ(m.triangles, hollow.triangles) << outer_in << inner_out;
            EXPECT_EQ(o.components, 2u);
            EXPECT_EQ(o.cavities, 1u);
            EXPECT_EQ(o.turned_components, std::size_t(outer_in) + std::size_t(inner_out));
        }
    // Two balls side by side are two solids, neither a cavity.
    TriangleMesh apart = icosphere(0.25, 1);
    for (auto& v : apart.vertices) v.x += 2.0;
    TriangleMesh two = joined(icosphere(0.5, 1), apart);
    EXPECT_EQ(orient(two).cavities, 0u);
}

// The real projective plane (6 vertices, 10 triangles, every edge shared by two): closed, but one-sided.
TEST(SceneMeshOrient, OneSidedAndFlatMeshesAreRefused) {
    TriangleMesh rp2;
    for (int i = 0; i < 6; ++i) rp2.vertices.push_back({std::cos(i * 1.1), std::sin(i * 0.7), 0.3 * i});
    rp2.triangles = {{0, 1, 2}, {0, 2, 3}, {0, 3, 4}, {0, 4, 5}, {0, 5, 1},
                     {1, 2, 4}, {2, 3, 5}, {3, 4, 1}, {4, 5, 2}, {5, 1, 3}};
    ASSERT_TRUE(topology(rp2).closed());
    const std::string one_sided = test::input_error_of([&] { orient(rp2); });
    EXPECT_NE(one_sided.find("cannot be oriented"), std::string::npos) << one_sided;
    TriangleMesh flat;  // one triangle, both sides
    flat.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    flat.triangles = {{0, 1, 2}, {0, 2, 1}};
    ASSERT_TRUE(topology(flat).closed());
    const std::string no_volume = test::input_error_of([&] { orient(flat); });
    EXPECT_NE(no_volume.find("encloses no volume"), std::string::npos) << no_volume;
}

}  // namespace
}  // namespace sdfbrick
