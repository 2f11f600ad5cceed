// The mesh edit: a scene mixing generated meshes (written to temporary files) with CSG edits, built
// on the device and checked against the double-precision host reference (brute-force mesh distance,
// not the grid); the device field's Lipschitz bound; the scene format's mesh fields.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "construct/brick_builder.h"
#include "construct/mesh_pool.h"
#include "core/errors.h"
#include "core/rng.h"
#include "exchange/host_bricks.h"
#include "reference/field_eval.h"
#include "reference/mesh_distance.h"
#include "reference/reference_field.h"
#include "scene/mesh.h"
#include "scene/mesh_orient.h"
#include "scene/scene_json.h"
#include "scene/to_device.h"
#include "test_support.h"

namespace sdfbrick {
namespace {

namespace fs = std::filesystem;

// Two meshes of a scene: an icosphere (OBJ) and a box with a hole (PLY), placed, rotated, scaled and
// combined with analytic edits by every rule, hard and smooth.
fs::path write_mixed_scene(const std::string& name) {
    const fs::path dir = test::temp_dir(name);
    write_obj(icosphere(0.5, 2), dir / "ball.obj");
    write_ply(box_with_hole(0.4, 0.15, 0.2), dir / "frame.ply");
    test::write_text(dir / "mixed.json", R"({"geometries": [{"name": "g", "edits": [
        {"primitive": "mesh", "file": "ball.obj", "resolution": 40, "rotation": [0, 0.3826834324, 0, 0.9238795325], "scale": 1.2},
        {"primitive": "mesh", "file": "frame.ply", "resolution": 32, "position": [0.75, 0.1, 0], "blend": 0.1,
         "rotation": [0.3826834324, 0, 0, 0.9238795325]},
        {"primitive": "box", "half_extents": [0.15, 0.15, 0.9], "op": "subtract", "blend": 0.05},
        {"primitive": "sphere", "radius": 0.3, "position": [-0.5, 0.35, 0.2], "blend": 0.15},
        {"primitive": "mesh", "file": "ball.obj", "resolution": 40, "position": [-0.3, -0.4, 0.4], "scale": 0.5, "op": "subtract"},
        {"primitive": "box", "half_extents": [1.3, 0.5, 1.3], "op": "intersect", "blend": 0.05}]}]})");
    return dir / "mixed.json";
}

construct::BuildSettings settings(double leaf) {
    construct::BuildSettings s;
    s.leaf_size = leaf;
    s.chunk = 32;
    s.eval_group = 64;
    return s;
}

double box_distance(const glm::dvec3& p, const glm::dvec3& lo, const glm::dvec3& hi) {
    return glm::length(glm::max(glm::max(lo - p, p - hi), glm::dvec3(0.0)));
}

// How far the device's value of the mesh edits may sit from the exact distances at p: the trilinear
// lookup of exact distances is within sqrt(3) cell of them (each corner value is within its
// distance), the continuation outside the grid within that plus twice the distance to the grid box;
// divided by L = sqrt(3) and scaled. Combining is 1-Lipschitz in each argument, so the geometry's
// error is at most its worst edit's.
double mesh_error_bound(const Geometry& g, const glm::dvec3& p) {
    double worst = 0.0;
    for (const Edit& e : g.edits) {
        if (e.primitive != Primitive::Mesh) continue;
        const GridFrame& f = e.mesh->frame;
        const double out = box_distance(e.transform.inverse_apply(p), f.origin, f.hi());
        worst = std::max(worst, e.transform.scale * (f.cell + 2.0 * out / std::sqrt(3.0)));
    }
    return worst;
}

TEST(ConstructMeshEdit, MixedSceneFollowsTheBruteForceReference) {
    const Scene scene = load_scene(write_mixed_scene("mesh_mixed"));
    const Geometry& g = scene.geometries.at(0);
    ASSERT_EQ(g.edits.size(), 6u);
    EXPECT_EQ(g.edits[0].mesh, g.edits[4].mesh);  // one file at one resolution: one mesh, one grid
    const construct::BuildSettings s = settings(0.125);
    construct::BrickBuilder builder(test::device());
    const construct::GeometryBuild b = builder.build(g, s, test::recorder());
    ASSERT_GT(b.leaf_count, 20u);
    const std::vector<SdfBrick> leaves = b.leaves->read();
    const std::vector<std::uint8_t> pool = b.pool->read();
    const int n = s.samples, a = s.layout().apron(), interior = s.layout().interior();
    const double step = b.band / 127.0 + 1e-5;  // int8 quantisation and float rounding
    std::size_t index = 0, over = 0, checked = 0, near = 0;
    double worst = 0.0;
    for (std::size_t l = 0; l < leaves.size(); l += 3) {  // a third of the leaves: the brute force is slow
        index = l * static_cast<std::size_t>(n * n * n);
        for (int k = 0; k < n; ++k)
            for (int j = 0; j < n; ++j)
                for (int i = 0; i < n; i += 2, index += 2) {
                    const int ijk[3] = {i, j, k};
                    glm::dvec3 p;
                    for (int ax = 0; ax < 3; ++ax)
                        p[ax] = b.origin[ax] + (leaves[l].coord[ax] * interior + ijk[ax] - a + 0.5) * s.voxel();
                    const double ref = std::clamp(reference::evaluate(g, p), -double(b.band), double(b.band));
                    const double got = static_cast<std::int8_t>(pool[index]) * (b.band / 127.0);
                    const double err = std::abs(got - ref), bound = mesh_error_bound(g, p) + step;
                    worst = std::max(worst, err);
                    over += err > bound;
                    near += std::abs(ref) < 0.5 * b.band;
                    ++checked;
                }
    }
    EXPECT_GT(near, checked / 4);
    EXPECT_EQ(over, 0u) << "of " << checked << " samples beyond the grid and quantisation bound; worst " << worst;
}

TEST(ConstructMeshEdit, CullingLanesAndRepeatsAreBitIdentical) {
    const Scene scene = load_scene(write_mixed_scene("mesh_cull"));
    construct::BrickBuilder builder(test::device());
    construct::BuildSettings on = settings(0.125), off = on;
    off.cull = false;
    const std::string a = construct::output_digest(builder.build(scene.geometries[0], on, test::recorder()), on);
    const std::string b = construct::output_digest(builder.build(scene.geometries[0], off, test::recorder()), off);
    const std::string c = construct::output_digest(builder.build(scene.geometries[0], on, test::recorder()), on);
    EXPECT_EQ(a, b);
    EXPECT_EQ(a, c);
    for (const int lanes : {1, 8}) {  // the mesh lookup lane by lane, and the float path
        construct::BuildSettings s = on;
        s.eval_lanes = lanes;
        EXPECT_EQ(construct::output_digest(builder.build(scene.geometries[0], s, test::recorder()), s), a) << lanes;
    }
}

// Adaptive leaves check coarse bricks against the field (brick_check): with mesh edits too.
TEST(ConstructMeshEdit, AdaptiveBuildChecksMeshEditsAndIsBitIdentical) {
    const Scene scene = load_scene(write_mixed_scene("mesh_adaptive"));
    construct::BrickBuilder builder(test::device());
    construct::BuildSettings on = settings(0.0625), off = on;
    on.tolerance = off.tolerance = 0.01;
    off.cull = false;
    const construct::GeometryBuild b = builder.build(scene.geometries[0], on, test::recorder());
    EXPECT_LT(b.coarsest_leaf_level, b.levels - 1);  // some leaves coarser than the finest
    EXPECT_LE(b.check_error_max, 0.01);
    const std::string a = construct::output_digest(b, on);
    EXPECT_EQ(a, construct::output_digest(builder.build(scene.geometries[0], off, test::recorder()), off));
}

// The device value of a mesh edit is 1-Lipschitz (trilinear / sqrt(3)) inside and far outside its grid,
// which is what culling and sphere tracing rely on, and its sign follows the mesh.
TEST(ConstructMeshEdit, DeviceFieldIsOneLipschitzEverywhere) {
    const fs::path dir = test::temp_dir("mesh_lipschitz");
    write_obj(box_with_hole(0.4, 0.15, 0.2), dir / "frame.obj");
    test::write_text(dir / "s.json", R"({"geometries": [{"name": "g", "edits": [
        {"primitive": "mesh", "file": "frame.obj", "resolution": 16, "scale": 1.5, "rotation": [0.2, 0.4, 0.1, 0.8888194417]}]}]})");
    const Scene scene = load_scene(dir / "s.json");
    const Geometry& g = scene.geometries[0];
    Rng rng(17);
    std::vector<float> xyz;
    for (int i = 0; i < 4000; ++i) {
        const double r = i % 4 == 0 ? 5.0 : 1.0;  // a quarter far outside the grid
        const glm::dvec3 p(rng.uniform(-r, r), rng.uniform(-r, r), rng.uniform(-r, r));
        const glm::dvec3 q = p + 0.05 * glm::dvec3(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
        for (const glm::dvec3& x : {p, q}) xyz.insert(xyz.end(), {float(x.x), float(x.y), float(x.z)});
    }
    reference::FieldEvaluator evaluator(test::device());
    const std::vector<float> meshes = construct::mesh_pool(scene.geometries, test::device(), test::recorder());
    const std::vector<float> v = evaluator.evaluate(to_device(g), xyz, meshes).values;
    std::size_t steep = 0, sign = 0;
    for (std::size_t i = 0; i + 1 < v.size(); i += 2) {
        const glm::dvec3 p(xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]), q(xyz[3 * i + 3], xyz[3 * i + 4], xyz[3 * i + 5]);
        steep += std::abs(double(v[i]) - v[i + 1]) > glm::length(p - q) * (1.0 + 1e-4) + 1e-6;
        const double ref = reference::evaluate(g, p);
        sign += std::abs(ref) > mesh_error_bound(g, p) && (ref < 0.0) != (v[i] < 0.0f);
    }
    EXPECT_EQ(steep, 0u);
    EXPECT_EQ(sign, 0u);
}

TEST(ConstructMeshEdit, SceneFormatRoundTripsAndSharesMeshes) {
    const fs::path file = write_mixed_scene("mesh_format");
    const Scene a = load_scene(file);
    const std::string text = format_scene(a);
    EXPECT_NE(text.find("\"file\": \"frame.ply\""), std::string::npos) << text;
    EXPECT_NE(text.find("\"resolution\": 32"), std::string::npos) << text;
    const Scene b = parse_scene(text, "again.json", file.parent_path());
    EXPECT_EQ(format_scene(b), text);
    EXPECT_EQ(b.geometries[0].edits[1].params[3], 1.0);  // frame.ply is the scene's second mesh
    EXPECT_EQ(b.geometries[0].edits[4].params[3], 0.0);
    // Bounds hold the mesh: the ball's radius 0.5 scaled by 1.2.
    const Aabb box = bounds(b.geometries[0].edits[0]);
    EXPECT_LE(box.lo.x, -0.6);
    EXPECT_GE(box.hi.y, 0.6);
}

// Meshes wound inward, or part inward, give the bricks of the outward files, with a warning that
// names the place and the file; the reference reads the same oriented triangles.
TEST(ConstructMeshEdit, InwardAndMixedWindingsGiveTheOutwardBricks) {
    const fs::path file = write_mixed_scene("mesh_winding");
    const Scene outward = load_scene(file);
    EXPECT_TRUE(outward.warnings.empty());
    TriangleMesh ball = icosphere(0.5, 2), frame = box_with_hole(0.4, 0.15, 0.2);
    reverse_winding(ball);
    for (std::size_t t = 0; t < frame.triangles.size(); t += 3) std::swap(frame.triangles[t][1], frame.triangles[t][2]);
    write_obj(ball, file.parent_path() / "ball.obj");
    write_ply(frame, file.parent_path() / "frame.ply");
    const Scene turned = load_scene(file);
    ASSERT_EQ(turned.warnings.size(), 2u);
    EXPECT_NE(turned.warnings[0].find("/geometries/0/edits/0/file"), std::string::npos) << turned.warnings[0];
    EXPECT_NE(turned.warnings[0].find("ball.obj"), std::string::npos) << turned.warnings[0];
    EXPECT_NE(turned.warnings[1].find("agree with their neighbours"), std::string::npos) << turned.warnings[1];
    const auto corners = [](const TriangleMesh& m) {  // vertex numbers follow the file's order of first use
        std::vector<glm::dvec3> c;
        for (const auto& t : m.triangles)
            for (std::uint32_t v : t) c.push_back(m.vertices[v]);
        return c;
    };
    for (const std::size_t e : {0, 1})
        EXPECT_EQ(corners(turned.geometries[0].edits[e].mesh->mesh), corners(outward.geometries[0].edits[e].mesh->mesh)) << e;
    const construct::BuildSettings s = settings(0.125);
    construct::BrickBuilder builder(test::device());
    EXPECT_EQ(construct::output_digest(builder.build(turned.geometries[0], s, test::recorder()), s),
              construct::output_digest(builder.build(outward.geometries[0], s, test::recorder()), s));
}

// A sparse grid is the dense grid within its band of the surface (same bits), and beyond it a lower
// bound of the distance with the right sign; it holds a fraction of the dense grid's values; and
// builds over either give the same bricks.
TEST(ConstructMeshEdit, SparseGridIsTheDenseOneNearTheSurfaceAndALowerBoundBeyond) {
    const fs::path dir = test::temp_dir("mesh_sparse");
    write_obj(torus_mesh(0.4, 0.15, 48, 24), dir / "ring.obj");
    const auto scene_of = [&](const char* grid) {
        return parse_scene(fmt::format(R"({{"geometries": [{{"name": "g", "edits": [
            {{"primitive": "mesh", "file": "ring.obj", "resolution": 160, "grid": "{}"}},
            {{"primitive": "sphere", "radius": 0.2, "position": [0.4, 0.1, 0], "blend": 0.05}}]}}]}})", grid),
                           "s.json", dir);
    };
    const Scene sparse = scene_of("sparse"), dense = scene_of("dense");
    const MeshSource& src = *sparse.geometries[0].edits[0].mesh;
    ASSERT_TRUE(src.sparse);
    EXPECT_FALSE(dense.geometries[0].edits[0].mesh->sparse);
    EXPECT_NE(format_scene(dense).find("\"grid\": \"dense\""), std::string::npos);
    EXPECT_EQ(format_scene(sparse).find("\"grid\""), std::string::npos);  // the default is not written
    const std::string unknown = test::input_error_of([&] { scene_of("cubic"); });
    EXPECT_NE(unknown.find("/geometries/0/edits/0/grid: unknown grid \"cubic\""), std::string::npos) << unknown;
    const std::vector<float> pool_s = construct::mesh_pool(sparse.geometries, test::device(), test::recorder());
    const std::vector<float> pool_d = construct::mesh_pool(dense.geometries, test::device(), test::recorder());
    EXPECT_LT(pool_s.size(), pool_d.size());

    Geometry mesh_only = sparse.geometries[0], mesh_only_dense = dense.geometries[0];
    mesh_only.edits.resize(1);
    mesh_only_dense.edits.resize(1);
    Rng rng(3);
    std::vector<float> xyz;
    for (int i = 0; i < 6000; ++i)  // within the grid's box (beyond it both grids add the distance to the box)
        for (int a = 0; a < 3; ++a) xyz.push_back(float(rng.uniform(src.frame.origin[a], src.frame.hi()[a])));
    reference::FieldEvaluator evaluator(test::device());
    const std::vector<float> vs = evaluator.evaluate(to_device(mesh_only), xyz, pool_s).values;
    const std::vector<float> vd = evaluator.evaluate(to_device(mesh_only_dense), xyz, pool_d).values;
    std::size_t near = 0, far = 0, differ = 0, above = 0, sign = 0;
    const double l = std::sqrt(3.0);
    for (std::size_t i = 0; i < vs.size(); ++i) {
        const glm::dvec3 p(xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]);
        const double exact = reference::mesh_signed_distance(src.mesh, p);
        if (std::abs(exact) <= src.band) {
            ++near;
            differ += vs[i] != vd[i];
        } else if (vs[i] != vd[i]) {  // a tile far from the surface (the others hold the dense values)
            ++far;
            above += std::abs(double(vs[i])) * l > std::abs(exact) + 1e-5;
            sign += (vs[i] < 0.0f) != (exact < 0.0);
        }
    }
    EXPECT_GT(near, 500u);
    EXPECT_GT(far, 500u);
    EXPECT_EQ(differ, 0u) << "of " << near << " points within the band";
    EXPECT_EQ(above, 0u) << "of " << far << " points beyond the band";
    EXPECT_EQ(sign, 0u);

    // Builds of the mesh alone: the sparse grid's lower bounds keep a few more leaves (nothing culls
    // them), and every leaf of the dense build is there with the same samples wherever the field is
    // within the band. (With other edits blended in, a value beyond the band may change theirs.)
    construct::BrickBuilder builder(test::device());
    for (const construct::BrickFormat format : {construct::BrickFormat::int8, construct::BrickFormat::float32}) {
        construct::BuildSettings s = settings(0.0625);
        s.format = format;
        const exchange::HostBricks a(builder.build(mesh_only, s, test::recorder()), s);
        const exchange::HostBricks b(builder.build(mesh_only_dense, s, test::recorder()), s);
        EXPECT_GE(a.brick_count(), b.brick_count());
        EXPECT_LE(a.brick_count(), b.brick_count() * 11 / 10);
        std::size_t missing = 0, differ = 0, compared = 0;
        const int n = b.samples();
        for (std::size_t brick = 0; brick < b.brick_count(); ++brick) {
            const auto match = a.find(b.coord(brick));
            if (!match) {
                ++missing;
                continue;
            }
            for (int k = 0; k < n; ++k)
                for (int j = 0; j < n; ++j)
                    for (int i = 0; i < n; ++i) {
                        if (std::abs(b.sample(brick, i, j, k)) * l >= src.band) continue;
                        ++compared;
                        differ += a.sample(*match, i, j, k) != b.sample(brick, i, j, k);
                    }
        }
        EXPECT_EQ(missing, 0u) << to_string(format);
        EXPECT_GT(compared, 100000u) << to_string(format);
        EXPECT_EQ(differ, 0u) << to_string(format) << ": of " << compared;
    }
}

// An open mesh has no inside: the scene is refused, naming the file, the place and the count.
TEST(ConstructMeshEdit, OpenMeshIsRefused) {
    const fs::path dir = test::temp_dir("mesh_open");
    TriangleMesh m = icosphere(0.5, 1);
    m.triangles.pop_back();
    write_obj(m, dir / "open.obj");
    test::write_text(dir / "s.json", R"({"geometries": [{"name": "g", "edits": [{"primitive": "mesh", "file": "open.obj"}]}]})");
    try {
        load_scene(dir / "s.json");
        FAIL() << "an open mesh was accepted";
    } catch (const InputError& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("/geometries/0/edits/0/file"), std::string::npos) << what;
        EXPECT_NE(what.find("open.obj"), std::string::npos) << what;
        EXPECT_NE(what.find("3 open edges"), std::string::npos) << what;
    }
}

}  // namespace
}  // namespace sdfbrick
