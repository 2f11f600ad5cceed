// The mesh formats users bring from sculpting and CAD, each written here from a generated mesh and
// read back through load_mesh: binary and ASCII STL (no shared vertices: welding restores the
// topology), binary PLY, glTF with an external buffer and GLB. Every one gives the generated
// triangles corner for corner, closed, and a scene over it gives the OBJ's bricks.
#include <algorithm>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "construct/brick_builder.h"
#include "scene/mesh.h"
#include "scene/scene_json.h"
#include "test_support.h"

namespace sdfbrick {
namespace {

namespace fs = std::filesystem;

template <class T>
void put(std::string& out, const T& v) {
    out.append(reinterpret_cast<const char*>(&v), sizeof v);
}

std::string binary_stl(const TriangleMesh& m) {
    std::string s(80, ' ');  // a header that does not start with "solid"
    s.replace(0, 9, "generated");
    put(s, static_cast<std::uint32_t>(m.triangles.size()));
    for (const auto& t : m.triangles) {
        for (int i = 0; i < 3; ++i) put(s, 0.0f);  // readers recompute normals
        for (std::uint32_t v : t)
            for (int i = 0; i < 3; ++i) put(s, static_cast<float>(m.vertices[v][i]));
        put(s, std::uint16_t{0});
    }
    return s;
}

std::string ascii_stl(const TriangleMesh& m) {
    std::string s = "solid generated\n";
    for (const auto& t : m.triangles) {
        s += "facet normal 0 0 0\nouter loop\n";
        for (std::uint32_t v : t)
            s += fmt::format("vertex {} {} {}\n", float(m.vertices[v].x), float(m.vertices[v].y), float(m.vertices[v].z));
        s += "endloop\nendfacet\n";
    }
    return s + "endsolid generated\n";
}

std::string binary_ply(const TriangleMesh& m) {
    std::string s = fmt::format("ply\nformat binary_little_endian 1.0\nelement vertex {}\nproperty float x\nproperty float y\n"
                                "property float z\nelement face {}\nproperty list uchar int vertex_indices\nend_header\n",
                                m.vertices.size(), m.triangles.size());
    for (const glm::dvec3& v : m.vertices)
        for (int i = 0; i < 3; ++i) put(s, static_cast<float>(v[i]));
    for (const auto& t : m.triangles) {
        put(s, std::uint8_t{3});
        for (std::uint32_t v : t) put(s, static_cast<std::int32_t>(v));
    }
    return s;
}

// The glTF buffer: positions (float VEC3) then indices (uint32), and the JSON that describes it.
struct Gltf {
    std::string json, bin;
};
Gltf gltf(const TriangleMesh& m, const std::string& buffer_uri) {
    Gltf g;
    const Aabb box = m.bounds();
    for (const glm::dvec3& v : m.vertices)
        for (int i = 0; i < 3; ++i) put(g.bin, static_cast<float>(v[i]));
    const std::size_t positions = g.bin.size();
    for (const auto& t : m.triangles)
        for (std::uint32_t v : t) put(g.bin, v);
    const std::string uri = buffer_uri.empty() ? "" : fmt::format(R"("uri": "{}", )", buffer_uri);
    g.json = fmt::format(
        R"({{"asset": {{"version": "2.0"}}, "scene": 0, "scenes": [{{"nodes": [0]}}], "nodes": [{{"mesh": 0}}],
"meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0}}, "indices": 1, "mode": 4}}]}}],
"buffers": [{{{}"byteLength": {}}}],
"bufferViews": [{{"buffer": 0, "byteOffset": 0, "byteLength": {}, "target": 34962}},
                {{"buffer": 0, "byteOffset": {}, "byteLength": {}, "target": 34963}}],
"accessors": [{{"bufferView": 0, "componentType": 5126, "count": {}, "type": "VEC3", "min": [{}, {}, {}], "max": [{}, {}, {}]}},
              {{"bufferView": 1, "componentType": 5125, "count": {}, "type": "SCALAR"}}]}})",
        uri, g.bin.size(), positions, positions, g.bin.size() - positions, m.vertices.size(), float(box.lo.x),
        float(box.lo.y), float(box.lo.z), float(box.hi.x), float(box.hi.y), float(box.hi.z), 3 * m.triangles.size());
    return g;
}

std::string glb(const TriangleMesh& m) {
    Gltf g = gltf(m, "");
    while (g.json.size() % 4) g.json += ' ';
    while (g.bin.size() % 4) g.bin += '\0';
    std::string s;
    put(s, std::uint32_t{0x46546C67});  // "glTF"
    put(s, std::uint32_t{2});
    put(s, static_cast<std::uint32_t>(12 + 8 + g.json.size() + 8 + g.bin.size()));
    put(s, static_cast<std::uint32_t>(g.json.size()));
    put(s, std::uint32_t{0x4E4F534A});  // JSON
    s += g.json;
    put(s, static_cast<std::uint32_t>(g.bin.size()));
    put(s, std::uint32_t{0x004E4942});  // BIN
    return s + g.bin;
}

// A torus with float coordinates (every format here stores floats), as the files should give it.
TriangleMesh float_torus() {
    TriangleMesh m = torus_mesh(0.4, 0.15, 20, 10);
    for (glm::dvec3& v : m.vertices)
        for (int i = 0; i < 3; ++i) v[i] = static_cast<float>(v[i]);
    return m;
}

std::vector<glm::dvec3> corners(const TriangleMesh& m) {
    std::vector<glm::dvec3> c;
    for (const auto& t : m.triangles)
        for (std::uint32_t v : t) c.push_back(m.vertices[v]);
    return c;
}

// Each format's files, written into `dir`, and the name of the one a scene names.
struct Format {
    const char* name;
    std::function<std::string(const fs::path&, const TriangleMesh&)> write;
};
const Format kFormats[] = {
    {"binary STL", [](const fs::path& d, const TriangleMesh& m) { test::write_text(d / "m.stl", binary_stl(m)); return std::string("m.stl"); }},
    {"ASCII STL", [](const fs::path& d, const TriangleMesh& m) { test::write_text(d / "a.stl", ascii_stl(m)); return std::string("a.stl"); }},
    {"binary PLY", [](const fs::path& d, const TriangleMesh& m) { test::write_text(d / "m.ply", binary_ply(m)); return std::string("m.ply"); }},
    {"glTF", [](const fs::path& d, const TriangleMesh& m) {
         const Gltf g = gltf(m, "m.bin");
         test::write_text(d / "m.bin", g.bin);
         test::write_text(d / "m.gltf", g.json);
         return std::string("m.gltf");
     }},
    {"GLB", [](const fs::path& d, const TriangleMesh& m) { test::write_text(d / "m.glb", glb(m)); return std::string("m.glb"); }},
};

TEST(SceneMeshFormats, EveryFormatGivesTheGeneratedTriangles) {
    const fs::path dir = test::temp_dir("scene_mesh_formats");
    const TriangleMesh m = float_torus();
    for (const Format& f : kFormats) {
        const TriangleMesh r = load_mesh(dir / f.write(dir, m));
        const std::vector<glm::dvec3> got = corners(r), want = corners(m);
        ASSERT_EQ(got.size(), want.size()) << f.name;
        // Text is parsed by Assimp's own fast number reader, within a few float steps; binary is exact.
        const double tolerance = f.name == std::string("ASCII STL") ? 1e-6 : 0.0;
        const auto near = [&](const glm::dvec3& a, const glm::dvec3& b) { return glm::length(a - b) <= tolerance; };
        EXPECT_EQ(std::mismatch(got.begin(), got.end(), want.begin(), near).first - got.begin(), std::ptrdiff_t(got.size()))
            << f.name << ": the first corner that differs";
        EXPECT_EQ(r.vertices.size(), m.vertices.size()) << f.name;  // welded
        EXPECT_TRUE(topology(r).closed()) << f.name;
    }
}

TEST(SceneMeshFormats, ScenesOverEveryFormatGiveTheObjsBricks) {
    const fs::path dir = test::temp_dir("scene_mesh_format_bricks");
    const TriangleMesh m = float_torus();
    write_obj(m, dir / "m.obj");
    const auto digest = [&](const std::string& file) {
        test::write_text(dir / "s.json", fmt::format(R"({{"geometries": [{{"name": "g", "edits": [
            {{"primitive": "mesh", "file": "{}", "resolution": 24}},
            {{"primitive": "sphere", "radius": 0.2, "position": [0.4, 0, 0], "blend": 0.05}}]}}]}})", file));
        const Scene s = load_scene(dir / "s.json");
        construct::BuildSettings b;
        b.leaf_size = 0.125;
        construct::BrickBuilder builder(test::device());
        return construct::output_digest(builder.build(s.geometries[0], b, test::recorder()), b);
    };
    const std::string obj = digest("m.obj");
    for (const Format& f : kFormats) EXPECT_EQ(digest(f.write(dir, m)), obj) << f.name;
}

}  // namespace
}  // namespace sdfbrick
