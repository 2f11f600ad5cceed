// Level sets in (scene/level_set.h): `export --vdb` / `--nvdb` of a brick set, then a scene whose
// edits name those grids, gives a field within one quantisation step of the original bricks (an
// object placed without rotation: the file's voxels copied; a rotated and scaled one: resampled onto
// world axes, within 0.4 voxel more); the device field follows the host reference; the
// scene format writes the edits back; files and grids that are not level sets are refused.
#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <glm/gtc/quaternion.hpp>
#include <gtest/gtest.h>

#include "construct/brick_builder.h"
#include "construct/mesh_pool.h"
#include "core/errors.h"
#include "exchange/vdb.h"
#include "reference/field_eval.h"
#include "reference/reference_field.h"
#include "render/brick_tracer.h"
#include "scene/level_set.h"
#include "scene/scene_json.h"
#include "scene/to_device.h"
#include "test_support.h"

#if SDFBRICK_WITH_OPENVDB
#include <openvdb/openvdb.h>
#endif

namespace sdfbrick {
namespace {

namespace fs = std::filesystem;
using exchange::HostBricks;

// A blended box and sphere with a hole, placed twice: as it is, and rotated, scaled and moved.
Scene original() {
    Scene s;
    Geometry g{"blend", {}};
    Edit box, ball, hole;
    box.primitive = Primitive::Box;
    box.params = {0.4, 0.3, 0.3, 0};
    ball.primitive = Primitive::Sphere;
    ball.params = {0.35, 0, 0, 0};
    ball.transform.translation = {0.4, 0.1, 0};
    ball.blend = 0.1;
    hole.primitive = Primitive::Cylinder;
    hole.params = {0.5, 0.12, 0, 0};
    hole.op = Op::Subtract;
    g.edits = {box, ball, hole};
    s.geometries = {g};
    Object turned{"turned", 0, {}};
    turned.transform.translation = {1.6, 0.2, -0.3};
    turned.transform.rotation = glm::angleAxis(0.7, glm::normalize(glm::dvec3(1, 2, 0.5)));
    turned.transform.scale = 1.5;
    s.objects = {Object{"plain", 0, {}}, turned};
    return s;
}

construct::BuildSettings settings() {
    construct::BuildSettings s;
    s.leaf_size = 0.0625;
    s.format = construct::BrickFormat::int16;
    return s;
}

// The imported geometry's field at world points (device evaluation, times the grid edit's
// Lipschitz bound sqrt(3) that every sampled grid divides by).
std::vector<double> imported_field(const Scene& s, const std::vector<glm::dvec3>& points) {
    std::vector<float> xyz;
    for (const glm::dvec3& p : points) xyz.insert(xyz.end(), {float(p.x), float(p.y), float(p.z)});
    reference::FieldEvaluator evaluator(test::device());
    const std::vector<float> pool = construct::mesh_pool(s.geometries, test::device(), test::recorder());
    const std::vector<float> v = evaluator.evaluate(to_device(s.geometries[0]), xyz, pool).values;
    std::vector<double> out;
    for (float x : v) out.push_back(double(x) * std::sqrt(3.0));
    return out;
}

void round_trip(exchange::VdbFormat format, const char* file) {
    const Scene scene = original();
    const construct::BuildSettings b = settings();
    construct::BrickBuilder builder(test::device());
    const render::SceneBricks built = render::build_scene_bricks(builder, scene, b, test::recorder());
    const HostBricks bricks(built.builds[0], b);
    const fs::path dir = test::temp_dir(std::string("level_set_") + file);
    exchange::write_vdb(scene, {&bricks, 1}, dir / file, format);

    for (std::size_t o = 0; o < scene.objects.size(); ++o) {
        const Object& obj = scene.objects[o];
        const Scene imported = parse_scene(
            fmt::format(R"({{"geometries": [{{"name": "g", "edits": [{{"primitive": "vdb", "file": "{}", "grid": "{}"}}]}}]}})",
                        file, obj.name),
            "imported.json", dir);
        const Edit& e = imported.geometries[0].edits[0];
        ASSERT_TRUE(e.mesh && e.mesh->level_set());
        EXPECT_NE(format_scene(imported).find("\"primitive\": \"vdb\""), std::string::npos);
        std::vector<glm::dvec3> points;
        std::vector<double> want;
        for (const glm::dvec3& p : reference::near_surface_points(scene.geometries[0], 300, 7 + o, 2.0 * bricks.voxel())) {
            const auto at = bricks.at(p);
            if (!at) continue;
            points.push_back(obj.transform.apply(p));
            want.push_back(at->distance * obj.transform.scale);
        }
        ASSERT_GT(points.size(), 200u);
        const std::vector<double> got = imported_field(imported, points);
        const double s = obj.transform.scale;
        // Copied voxels: the bricks' own values. Resampled (rotated): trilinear of a trilinear field, which
        // rounds the kinks of the distance (edges, the medial axis) by up to about a quarter voxel.
        const double allowed = (bricks.quantum() + (o == 0 ? 1e-4 : 0.4) * bricks.voxel()) * s;
        std::size_t over = 0, reference_off = 0;
        for (std::size_t i = 0; i < points.size(); ++i) {
            over += std::abs(got[i] - want[i]) > allowed;
            const double ref = reference::evaluate(imported.geometries[0], points[i]) * std::sqrt(3.0);
            reference_off += std::abs(ref - got[i]) > 1e-4 * s;
        }
        EXPECT_EQ(over, 0u) << obj.name << ": of " << points.size() << " beyond " << allowed;
        EXPECT_EQ(reference_off, 0u) << obj.name;
    }
}

#if SDFBRICK_WITH_OPENVDB
TEST(SceneLevelSet, OpenVdbExportComesBackAsEdits) { round_trip(exchange::VdbFormat::openvdb, "scene.vdb"); }

TEST(SceneLevelSet, GridsThatAreNotLevelSetsAreRefused) {
    openvdb::initialize();
    const fs::path dir = test::temp_dir("level_set_bad");
    auto level = openvdb::FloatGrid::create(0.3f);
    level->setName("ok");
    level->setGridClass(openvdb::GRID_LEVEL_SET);
    level->tree().setValue(openvdb::Coord(0, 0, 0), -0.05f);
    level->setTransform(openvdb::math::Transform::createLinearTransform(0.1));
    auto fog = level->deepCopy();
    fog->setName("fog");
    fog->setGridClass(openvdb::GRID_FOG_VOLUME);
    auto stretched = level->deepCopy();
    stretched->setName("stretched");
    stretched->setTransform(openvdb::math::Transform::createLinearTransform(openvdb::Mat4R(
        0.1, 0.0, 0.0, 0.0, 0.0, 0.2, 0.0, 0.0, 0.0, 0.0, 0.1, 0.0, 0.0, 0.0, 0.0, 1.0)));
    auto vectors = openvdb::Vec3SGrid::create();
    vectors->setName("velocity");
    vectors->tree().setValue(openvdb::Coord(0, 0, 0), openvdb::Vec3s(1, 0, 0));
    auto empty = openvdb::FloatGrid::create(0.3f);
    empty->setName("empty");
    empty->setGridClass(openvdb::GRID_LEVEL_SET);
    openvdb::io::File(fs::path(dir / "many.vdb").string()).write({level, fog, stretched, vectors, empty});
    openvdb::io::File(fs::path(dir / "one.vdb").string()).write({level});
    test::write_text(dir / "junk.vdb", "not a vdb file at all");

    EXPECT_EQ(read_level_set(dir / "one.vdb", "").grid, "ok");  // the only grid needs no name
    EXPECT_EQ(read_level_set(dir / "many.vdb", "ok").frame.dims, glm::ivec3(3));  // one voxel and one around it
    const std::pair<const char*, const char*> cases[] = {
        {"", "holds 5 grids"},
        {"nothing", "no grid named \"nothing\""},
        {"fog", "not a level set"},
        {"stretched", "not a uniform scale"},
        {"velocity", "a level set holds float"},
        {"empty", "no active voxel"},
    };
    for (const auto& [grid, expected] : cases) {
        const std::string what = test::input_error_of([&] { read_level_set(dir / "many.vdb", grid); });
        EXPECT_NE(what.find("many.vdb"), std::string::npos) << grid << ": " << what;
        EXPECT_NE(what.find(expected), std::string::npos) << grid << ": " << what;
    }
    EXPECT_NE(test::input_error_of([&] { read_level_set(dir / "junk.vdb", ""); }).find("junk.vdb: cannot read level sets"),
              std::string::npos);
    // In a scene: the place, then the file and the grid.
    const std::string what = test::input_error_of([&] {
        parse_scene(R"({"geometries": [{"name": "g", "edits": [{"primitive": "vdb", "file": "many.vdb", "grid": "fog"}]}]})",
                    "s.json", dir);
    });
    EXPECT_NE(what.find("s.json: /geometries/0/edits/0/file: "), std::string::npos) << what;
    EXPECT_NE(what.find("\"fog\" is of class fog volume"), std::string::npos) << what;
}
#endif

#if SDFBRICK_WITH_NANOVDB
TEST(SceneLevelSet, NanoVdbExportComesBackAsEdits) { round_trip(exchange::VdbFormat::nanovdb, "scene.nvdb"); }
#endif

}  // namespace
}  // namespace sdfbrick
