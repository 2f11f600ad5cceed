// scene/mesh.h: meshes read through Assimp (OBJ, PLY) welded into the generated shapes they were
// written from, their topology, and bad files refused with one line naming the file.
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "core/errors.h"
#include "scene/mesh.h"
#include "test_support.h"

namespace sdfbrick {
namespace {

TEST(SceneMesh, GeneratedShapesAreClosed) {
    for (const TriangleMesh& m : {icosphere(0.5, 2), torus_mesh(0.4, 0.15, 24, 12), box_with_hole(0.5, 0.2, 0.15)}) {
        const MeshTopology t = topology(m);
        EXPECT_TRUE(t.closed()) << t.open_edges << " open, " << t.non_manifold_edges << " non-manifold";
        // Euler: V - E + F = 2 - 2 genus.
        const auto euler = static_cast<long>(m.vertices.size()) - static_cast<long>(t.edges) + static_cast<long>(m.triangles.size());
        EXPECT_TRUE(euler == 2 || euler == 0) << euler;
    }
    EXPECT_EQ(icosphere(1.0, 3).triangles.size(), 1280u);
    EXPECT_EQ(torus_mesh(1.0, 0.2, 44, 28).triangles.size(), 2464u);
}

TEST(SceneMesh, ObjAndPlyReadBackWelded) {
    const auto dir = test::temp_dir("scene_mesh");
    const TriangleMesh m = torus_mesh(0.4, 0.15, 16, 8);
    write_obj(m, dir / "t.obj");
    write_ply(m, dir / "t.ply");
    for (const char* name : {"t.obj", "t.ply"}) {
        const TriangleMesh r = load_mesh(dir / name);
        EXPECT_EQ(r.vertices.size(), m.vertices.size()) << name;
        EXPECT_EQ(r.triangles.size(), m.triangles.size()) << name;
        EXPECT_TRUE(topology(r).closed()) << name;
        const Aabb a = m.bounds(), b = r.bounds();
        EXPECT_NEAR(glm::length(a.lo - b.lo) + glm::length(a.hi - b.hi), 0.0, 1e-6) << name;
    }
    TriangleMesh open = m;
    open.triangles.pop_back();
    EXPECT_EQ(topology(open).open_edges, 3u);
}

TEST(SceneMesh, BadFilesNameTheFile) {
    const auto dir = test::temp_dir("scene_mesh_bad");
    const std::pair<const char*, const char*> cases[] = {
        {"empty.obj", ""},
        {"garbage.ply", "ply\nformat ascii 1.0\nelement vertex banana\n"},
        {"points.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n"},
        {"nan.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n"},
    };
    // A binary PLY whose second vertex is NaN.
    std::string nan_ply = "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                          "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
    const float xyz[9] = {0.0f, 0.0f, 0.0f, std::nanf(""), 0.0f, 0.0f, 0.0f, 1.0f, 0.0f};
    const std::int32_t face[3] = {0, 1, 2};
    nan_ply += std::string(reinterpret_cast<const char*>(xyz), sizeof xyz) + '\x03' +
               std::string(reinterpret_cast<const char*>(face), sizeof face);
    test::write_text(dir / "nan.ply", nan_ply);
    try {
        load_mesh(dir / "nan.ply");
        ADD_FAILURE() << "nan.ply was accepted";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("nan.ply: vertex "), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("is not finite"), std::string::npos) << e.what();
    }
    for (const auto& [name, text] : cases) {
        test::write_text(dir / name, text);
        try {
            const TriangleMesh m = load_mesh(dir / name);
            ADD_FAILURE() << name << " was accepted with " << m.triangles.size() << " triangles";
        } catch (const InputError& e) {
            const std::string what = e.what();
            EXPECT_NE(what.find((dir / name).string()), std::string::npos) << what;
            EXPECT_EQ(what.find('\n'), std::string::npos) << what;
        }
    }
    EXPECT_THROW(load_mesh(dir / "missing.obj"), InputError);
}

}  // namespace
}  // namespace sdfbrick
