// Mesh files as a hostile scene would name them: paths outside the scene's folder (absolute, `..`,
// a symbolic link leading out), glTF buffers outside the mesh's folder, an OBJ material library that
// is a FIFO, and a PLY header that promises more than its file holds. Each is refused with one line
// naming the file, without blocking and without allocating for what the file does not hold.
#include <sys/stat.h>

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "core/errors.h"
#include "core/files.h"
#include "scene/mesh.h"
#include "scene/scene_json.h"
#include "test_support.h"

namespace sdfbrick {
namespace {

namespace fs = std::filesystem;

std::string mesh_scene(const std::string& file) {
    return fmt::format(R"({{"geometries": [{{"name": "g", "edits": [{{"primitive": "mesh", "file": "{}", "resolution": 8}}]}}]}})",
                       file);
}

// The folders allowed outside a scene's own, restored when the test ends.
struct AllowedFolders {
    explicit AllowedFolders(std::vector<fs::path> folders) { allow_mesh_folders(std::move(folders)); }
    ~AllowedFolders() { allow_mesh_folders({}); }
};

TEST(SceneMeshFiles, MeshPathsOutsideTheScenesFolderAreRefused) {
    const fs::path dir = test::temp_dir("scene_mesh_outside");
    fs::create_directories(dir / "scene" / "inside");
    fs::create_directories(dir / "outside");
    write_obj(icosphere(0.5, 1), dir / "outside" / "m.obj");
    write_obj(icosphere(0.5, 1), dir / "scene" / "inside" / "m.obj");
    fs::create_symlink(dir / "outside" / "m.obj", dir / "scene" / "link.obj");
    const fs::path base = dir / "scene";
    for (const std::string& file : {std::string("../outside/m.obj"), (dir / "outside" / "m.obj").string(), std::string("link.obj"),
                                   std::string("inside/../../outside/m.obj"), std::string("/etc/passwd")}) {
        const std::string what = test::input_error_of([&] { parse_scene(mesh_scene(file), "s.json", base); });
        EXPECT_NE(what.find("s.json: /geometries/0/edits/0/file: "), std::string::npos) << file << ": " << what;
        EXPECT_NE(what.find("outside the scene's folder"), std::string::npos) << file << ": " << what;
    }
    EXPECT_EQ(parse_scene(mesh_scene("inside/m.obj"), "s.json", base).geometries[0].edits.size(), 1u);
    const AllowedFolders allowed({dir / "outside"});
    EXPECT_EQ(parse_scene(mesh_scene("../outside/m.obj"), "s.json", base).geometries[0].edits.size(), 1u);
    EXPECT_EQ(parse_scene(mesh_scene("link.obj"), "s.json", base).geometries[0].edits.size(), 1u);
    EXPECT_NE(test::input_error_of([&] { parse_scene(mesh_scene("/etc/passwd"), "s.json", base); }).find("outside"), std::string::npos);
}

// A glTF with one triangle whose vertices lie in the buffer `uri` names.
std::string gltf_triangle(const std::string& uri) {
    return fmt::format(
        R"({{"asset": {{"version": "2.0"}}, "scene": 0, "scenes": [{{"nodes": [0]}}], "nodes": [{{"mesh": 0}}],
"meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0}}}}]}}],
"buffers": [{{"uri": "{}", "byteLength": 36}}],
"bufferViews": [{{"buffer": 0, "byteOffset": 0, "byteLength": 36}}],
"accessors": [{{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]}}]}})",
        uri);
}

TEST(SceneMeshFiles, GltfBuffersOutsideTheMeshFolderAreRefused) {
    const fs::path dir = test::temp_dir("scene_mesh_gltf");
    fs::create_directories(dir / "mesh");
    const float xyz[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    const std::string bytes(reinterpret_cast<const char*>(xyz), sizeof xyz);
    test::write_text(dir / "mesh" / "tri.bin", bytes);
    test::write_text(dir / "secret.bin", bytes);
    test::write_text(dir / "mesh" / "good.gltf", gltf_triangle("tri.bin"));
    EXPECT_EQ(load_mesh(dir / "mesh" / "good.gltf").triangles.size(), 1u);
    for (const std::string& uri : {std::string("../secret.bin"), (dir / "secret.bin").string(), std::string("file:///etc/passwd")}) {
        test::write_text(dir / "mesh" / "bad.gltf", gltf_triangle(uri));
        const std::string what = test::input_error_of([&] { load_mesh(dir / "mesh" / "bad.gltf"); });
        EXPECT_NE(what.find("bad.gltf: cannot read mesh"), std::string::npos) << uri << ": " << what;
        EXPECT_EQ(what.find("triangles"), std::string::npos) << uri << ": " << what;
    }
    test::write_text(dir / "mesh" / "bad.gltf", gltf_triangle("../secret.bin"));
    EXPECT_NE(test::input_error_of([&] { load_mesh(dir / "mesh" / "bad.gltf"); }).find("outside the mesh's folder"), std::string::npos);
}

TEST(SceneMeshFiles, AnObjMaterialLibraryThatIsAFifoIsRefusedWithoutBlocking) {
    const fs::path dir = test::temp_dir("scene_mesh_mtl_fifo");
    ASSERT_EQ(::mkfifo((dir / "m.mtl").c_str(), 0600), 0);
    test::write_text(dir / "m.obj", "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    const auto start = std::chrono::steady_clock::now();
    const std::string what = test::input_error_of([&] { load_mesh(dir / "m.obj"); });
    EXPECT_NE(what.find("a FIFO, not a regular file"), std::string::npos) << what;
    EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(10));
}

TEST(SceneMeshFiles, PlyCountsBeyondTheFilesSizeAreRefusedBeforeLoading) {
    const fs::path dir = test::temp_dir("scene_mesh_ply_counts");
    const std::string header =
        "ply\nformat binary_little_endian 1.0\nelement vertex 2000000000\nproperty float x\nproperty float y\n"
        "property float z\nelement face 2000000000\nproperty list uchar int vertex_indices\nend_header\n";
    test::write_text(dir / "huge.ply", header + std::string(64, '\0'));
    const auto start = std::chrono::steady_clock::now();
    const std::string what = test::input_error_of([&] { load_mesh(dir / "huge.ply"); });
    EXPECT_NE(what.find("huge.ply: cannot read mesh: the binary PLY header declares vertex 2000000000, face 2000000000"),
              std::string::npos) << what;
    EXPECT_NE(what.find("but 64 bytes follow it"), std::string::npos) << what;
    EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(10));
    // ASCII: two characters per property at least.
    test::write_text(dir / "ascii.ply", "ply\nformat ascii 1.0\nelement vertex 1000\nproperty float x\nend_header\n0\n1\n");
    EXPECT_NE(test::input_error_of([&] { load_mesh(dir / "ascii.ply"); }).find("the ASCII PLY header declares vertex 1000"), std::string::npos);
    // A PLY whose counts its body can hold is read as before.
    write_ply(icosphere(0.5, 1), dir / "fine.ply");
    EXPECT_EQ(load_mesh(dir / "fine.ply").triangles.size(), 80u);
}

// The mesh fuzz target's regressions (tests/fuzz/regressions/mesh_reader/: files on which Assimp
// aborts, crashes or never returns): each is refused with one line, and the program lives on.
TEST(SceneMeshFiles, FuzzRegressionsAreRefusedAndTheProgramLivesOn) {
    const fs::path dir = test::temp_dir("scene_mesh_fuzz_regressions");
    std::size_t count = 0;
    for (const auto& entry : fs::directory_iterator(fs::path(SDFBRICK_SOURCE_DIR) / "tests" / "fuzz" / "regressions" / "mesh_reader")) {
        const std::string bytes = read_file(entry.path());
        ASSERT_FALSE(bytes.empty());
        const char* extension = bytes[0] == 'p' ? ".ply" : bytes[0] == 'o' ? ".obj" : bytes[0] == 's' ? ".stl" : ".gltf";
        const fs::path file = dir / (entry.path().stem().string() + extension);
        test::write_text(file, bytes.substr(1));
        const std::string what = test::input_error_of([&] { load_mesh(file, 3); });
        EXPECT_NE(what.find(file.string() + ": "), std::string::npos) << entry.path() << ": " << what;
        EXPECT_EQ(what.find('\n'), std::string::npos) << what;
        ++count;
    }
    EXPECT_GE(count, 4u);
}

}  // namespace
}  // namespace sdfbrick
