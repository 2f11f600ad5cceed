// Mesh edits as a user meets them: a scene mixing a mesh with CSG edits renders against the reference
// tracer with a small mismatch; bad mesh files are refused in one line naming the file and the
// place in the scene, exit 2, nothing written.
#include <algorithm>
#include <filesystem>
#include <string>
#include <utility>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli/cli_run.h"
#include "core/files.h"
#include "scene/mesh.h"
#include "test_support.h"

namespace sdfbrick {
namespace {

namespace fs = std::filesystem;

test::CliRun sdfbrick(const std::string& args) {
    return test::sdfbrick(args, "SDFBRICK_DEVICE=" + test::test_device_spec());
}

// A scene of one mesh edit naming `file`, beside it.
fs::path scene_naming(const fs::path& dir, const std::string& file) {
    test::write_text(dir / "s.json", R"({"geometries": [{"name": "g", "edits": [
        {"primitive": "box", "half_extents": [0.3, 0.3, 0.3]},
        {"primitive": "mesh", "file": ")" + file + R"(", "blend": 0.1}]}]})");
    return dir / "s.json";
}

TEST(CliMesh, MixedSceneRendersCloseToTheReference) {
    const fs::path dir = test::temp_dir("cli_mesh_render");
    write_obj(torus_mesh(0.45, 0.15, 48, 24), dir / "ring.obj");
    test::write_text(dir / "s.json", R"({"geometries": [{"name": "g", "edits": [
        {"primitive": "mesh", "file": "ring.obj", "resolution": 48, "rotation": [0.3826834324, 0, 0, 0.9238795325]},
        {"primitive": "sphere", "radius": 0.25, "position": [0.45, 0, 0], "blend": 0.1},
        {"primitive": "box", "half_extents": [0.12, 0.6, 0.12], "position": [-0.45, 0, 0], "op": "subtract", "blend": 0.04}]}],
        "camera": {"orbit": {"target": [0, 0, 0], "distance": 2.2, "yaw_deg": 30, "pitch_deg": 35}}})");
    const test::CliRun r = sdfbrick("render " + (dir / "s.json").string() + " --brick-size 0.0625 --width 96 --height 72 "
                                    "--compare --out " + (dir / "m.ppm").string() + " --json " + (dir / "r.json").string());
    ASSERT_EQ(r.status, 0) << r.err;
    const auto j = nlohmann::json::parse(read_file(dir / "r.json"));
    const auto& a = j["accuracy"];
    EXPECT_GT(a["both_hit"].get<int>(), 96 * 72 / 8);
    EXPECT_LT(a["mismatch_fraction"].get<double>(), 0.01) << a.dump();
    EXPECT_LT(a["depth_error_p99"].get<double>(), 1.0) << a.dump();  // voxels
}

// The shipped mesh scene: three gear meshes (one file) with CSG edits, two objects.
TEST(CliMesh, GearsSceneRendersCloseToTheReference) {
    const fs::path dir = test::temp_dir("cli_mesh_gears");
    const test::CliRun r = sdfbrick("render " + test::scene_path("gears") + " --width 128 --height 96 --compare --out " +
                                    (dir / "g.ppm").string() + " --json " + (dir / "r.json").string());
    ASSERT_EQ(r.status, 0) << r.err;
    const auto a = nlohmann::json::parse(read_file(dir / "r.json"))["accuracy"];
    EXPECT_GT(a["both_hit"].get<int>(), 128 * 96 / 8);
    EXPECT_LT(a["mismatch_fraction"].get<double>(), 0.01) << a.dump();
    EXPECT_LT(a["depth_error_p99"].get<double>(), 1.0) << a.dump();
    const test::CliRun info = sdfbrick("scene info " + test::scene_path("gears") + " --json");
    ASSERT_EQ(info.status, 0) << info.err;
    EXPECT_EQ(nlohmann::json::parse(info.out)["geometries"][0]["primitives"]["mesh"].get<int>(), 3) << info.out;
}

TEST(CliMesh, BadMeshFilesAreRefusedNamingFileAndPlace) {
    const fs::path dir = test::temp_dir("cli_mesh_bad");
    TriangleMesh open = icosphere(0.5, 1);
    open.triangles.pop_back();
    write_obj(open, dir / "open.obj");
    test::write_text(dir / "empty.obj", "");
    test::write_text(dir / "garbage.ply", "ply\nformat ascii 1.0\nelement vertex banana\n");
    test::write_text(dir / "nan.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n");
    test::write_text(dir / "huge.obj", "v 0 0 0\nv 1e9 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n");
    const std::pair<const char*, const char*> cases[] = {
        {"missing.obj", "missing.obj"}, {"empty.obj", "empty.obj"},     {"garbage.ply", "garbage.ply"},
        {"nan.obj", "vertex 1"},        {"open.obj", "3 open edges"},   {"huge.obj", "out of range"}};
    for (const auto& [file, detail] : cases) {
        const fs::path scene = scene_naming(dir, file);
        const fs::path out = dir / "out.ppm";
        const test::CliRun r = sdfbrick("render " + scene.string() + " --out " + out.string());
        EXPECT_EQ(r.status, 2) << file << ": " << r.err;
        EXPECT_NE(r.err.find(std::string(file)), std::string::npos) << r.err;
        EXPECT_NE(r.err.find("/geometries/0/edits/1/file"), std::string::npos) << r.err;
        EXPECT_NE(r.err.find(detail), std::string::npos) << r.err;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
        EXPECT_FALSE(fs::exists(out)) << file;
    }
    write_obj(icosphere(0.5, 1), dir / "ball.obj");
    test::write_text(dir / "r.json", R"({"geometries": [{"name": "g", "edits": [
        {"primitive": "mesh", "file": "ball.obj", "resolution": 5000}]}]})");
    const test::CliRun fine = sdfbrick("render " + (dir / "r.json").string() + " --out " + (dir / "out.ppm").string());
    EXPECT_EQ(fine.status, 2);
    EXPECT_NE(fine.err.find("/geometries/0/edits/0/resolution"), std::string::npos) << fine.err;
    EXPECT_FALSE(fs::exists(dir / "out.ppm"));
}

}  // namespace
}  // namespace sdfbrick
