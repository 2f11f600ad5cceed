// host/exchange/: the brick set read back to the host against the double-precision reference, the
// OpenVDB and NanoVDB files read back with their own libraries and sampled against the brick set
// (within one quantisation step), their metadata, and point sampling with its input errors.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>
#include <unordered_map>

#include <glm/gtc/quaternion.hpp>
#include <gtest/gtest.h>

#include "core/errors.h"
#include "core/rng.h"
#include "exchange/sample.h"
#include "exchange/vdb.h"
#include "reference/reference_field.h"
#include "render/brick_tracer.h"
#include "test_support.h"

#if SDFBRICK_WITH_OPENVDB
#include <openvdb/openvdb.h>
#include <openvdb/tools/Interpolation.h>
#endif
#if SDFBRICK_WITH_NANOVDB
#include <nanovdb/util/IO.h>
#include <nanovdb/util/SampleFromVoxels.h>
#endif

namespace sdfbrick {
namespace {

using exchange::HostBricks;

Edit edit(Primitive p, std::array<double, 4> params, glm::dvec3 at, Op op = Op::Add, double blend = 0.0) {
    Edit e;
    e.primitive = p;
    e.params = params;
    e.transform.translation = at;
    e.op = op;
    e.blend = blend;
    return e;
}

// Two geometries (a blended box and sphere with a hole; a torus) and three objects: the first
// geometry twice (once rotated and scaled), the torus once, moved.
Scene two_geometries() {
    Scene s;
    s.name = "exchange";
    Geometry a{"blend", {edit(Primitive::Box, {0.4, 0.3, 0.3, 0}, {0, 0, 0}),
                         edit(Primitive::Sphere, {0.35, 0, 0, 0}, {0.4, 0.1, 0}, Op::Add, 0.1),
                         edit(Primitive::Cylinder, {0.5, 0.12, 0, 0}, {-0.1, 0, 0}, Op::Subtract)}};
    Geometry b{"torus", {edit(Primitive::Torus, {0.4, 0.12, 0, 0}, {0, 0, 0})}};
    s.geometries = {a, b};
    Object o0{"plain", 0, {}};
    Object o1{"turned", 0, {}};
    o1.transform.translation = {1.6, 0.2, -0.3};
    o1.transform.rotation = glm::angleAxis(0.7, glm::normalize(glm::dvec3(1, 2, 0.5)));
    o1.transform.scale = 1.5;
    Object o2{"ring", 1, {}};
    o2.transform.translation = {-1.4, 0.0, 0.5};
    s.objects = {o0, o1, o2};
    return s;
}

construct::BuildSettings settings(construct::BrickFormat format) {
    construct::BuildSettings s;
    s.leaf_size = 0.0625;
    s.format = format;
    return s;
}

std::vector<HostBricks> host_bricks(const Scene& scene, const construct::BuildSettings& s) {
    static construct::BrickBuilder builder(test::device());
    const render::SceneBricks built = render::build_scene_bricks(builder, scene, s, test::recorder());
    std::vector<HostBricks> out;
    for (const construct::GeometryBuild& b : built.builds) out.emplace_back(b, s);
    return out;
}

// World points near the surface of each object, with the object they were drawn for.
std::vector<std::pair<glm::dvec3, std::size_t>> surface_points(const Scene& scene, double offset) {
    std::vector<std::pair<glm::dvec3, std::size_t>> out;
    for (std::size_t o = 0; o < scene.objects.size(); ++o) {
        const Object& obj = scene.objects[o];
        for (const glm::dvec3& p : reference::near_surface_points(scene.geometries[obj.geometry], 200, 11 + o, offset))
            out.emplace_back(obj.transform.apply(p), o);
    }
    return out;
}

// The geometry-frame position of sample (i, j, k) of a brick.
glm::dvec3 sample_position(const HostBricks& b, std::size_t brick, int i, int j, int k) {
    return b.origin() + (glm::dvec3(b.coord(brick) * b.interior() + glm::ivec3(i, j, k) - b.apron()) + 0.5) * b.voxel();
}

TEST(ExchangeHostBricks, SamplesAreTheReferenceFieldAndAtInterpolatesThem) {
    const Scene scene = two_geometries();
    for (construct::BrickFormat format : {construct::BrickFormat::int8, construct::BrickFormat::float32}) {
        const std::vector<HostBricks> bricks = host_bricks(scene, settings(format));
        const Geometry& g = scene.geometries[0];
        const HostBricks& b = bricks[0];
        ASSERT_GT(b.brick_count(), 100u);
        // Every 7th brick, every sample: the reference clamped to the band, within half a step.
        for (std::size_t brick = 0; brick < b.brick_count(); brick += 7)
            for (int k = 0; k < b.samples(); ++k)
                for (int j = 0; j < b.samples(); ++j)
                    for (int i = 0; i < b.samples(); ++i) {
                        const glm::dvec3 p = sample_position(b, brick, i, j, k);
                        const double ref = std::clamp(reference::evaluate(g, p), -b.band(), b.band());
                        ASSERT_NEAR(b.sample(brick, i, j, k), ref, 0.5 * b.quantum() + 1e-6) << to_string(format);
                    }
        // In a cell, at() is the trilinear of its corners: exact at a sample, its gradient the
        // difference quotient along each axis.
        const glm::dvec3 corner = sample_position(b, 3, 2, 3, 4);
        const std::optional<exchange::BrickSample> at_corner = b.at(corner);
        ASSERT_TRUE(at_corner);
        EXPECT_NEAR(at_corner->distance, b.sample(3, 2, 3, 4), 1e-6);
        const glm::dvec3 mid = corner + glm::dvec3(0.3, 0.6, 0.2) * b.voxel();
        const double h = 1e-3 * b.voxel();
        for (int axis = 0; axis < 3; ++axis) {
            glm::dvec3 e(0.0);
            e[axis] = h;
            const double quotient = (b.at(mid + e)->distance - b.at(mid - e)->distance) / (2.0 * h);
            EXPECT_NEAR(b.at(mid)->gradient[axis], quotient, 1e-3);
        }
        EXPECT_FALSE(b.at({5.0, 5.0, 5.0}));
    }
}

TEST(ExchangeVdb, LevelSetVoxelsAreUniqueAndCoverEveryInteriorSample) {
    const Scene scene = two_geometries();
    const std::vector<HostBricks> bricks = host_bricks(scene, settings(construct::BrickFormat::int8));
    const HostBricks& b = bricks[1];
    std::unordered_map<glm::ivec3, float, exchange::CoordHash> voxels;
    std::size_t visits = 0;
    exchange::for_each_level_set_voxel(b, 2.0, [&](const exchange::VdbVoxel& v) {
        ++visits;
        voxels.emplace(v.ijk, v.value);
    });
    EXPECT_EQ(visits, voxels.size()) << "a voxel visited twice";
    const int n = b.interior(), a = b.apron();
    EXPECT_GT(voxels.size(), b.brick_count() * static_cast<std::size_t>(n * n * n));  // aprons at the band's edge
    for (std::size_t brick = 0; brick < b.brick_count(); brick += 5)
        for (int k = a; k < a + n; ++k)
            for (int i = a; i < a + n; ++i) {
                const auto it = voxels.find(b.coord(brick) * n + glm::ivec3(i, 2, k) - a);
                ASSERT_NE(it, voxels.end());
                EXPECT_EQ(it->second, 2.0f * b.sample(brick, i, 2, k));
            }
}

// An adaptive build: its coarser leaves give voxels on the finest lattice, each the leaf's field at
// the voxel's centre (times the scale), within the finest band, and each voxel once; points near the
// surface are read from leaves of every level.
TEST(ExchangeVdb, AdaptiveLeavesGiveFinestVoxelsWithinTheBand) {
    const Scene scene = two_geometries();
    construct::BuildSettings s = settings(construct::BrickFormat::int8);
    s.tolerance = 0.01;
    const std::vector<HostBricks> bricks = host_bricks(scene, s);
    const HostBricks& b = bricks[0];
    std::size_t coarse = 0;
    for (std::size_t brick = 0; brick < b.brick_count(); ++brick) coarse += b.shift(brick) > 0;
    ASSERT_GT(coarse, 0u) << "no leaf coarser than the finest";
    std::unordered_map<glm::ivec3, float, exchange::CoordHash> voxels;
    std::size_t visits = 0, checked = 0;
    exchange::for_each_level_set_voxel(b, 2.0, [&](const exchange::VdbVoxel& v) {
        ++visits;
        voxels.emplace(v.ijk, v.value);
        const glm::dvec3 p = b.origin() + (glm::dvec3(v.ijk) + 0.5) * b.voxel();
        const glm::ivec3 cell(glm::floor((p - b.origin()) / (b.voxel() * b.interior())));
        const std::optional<std::size_t> leaf = b.covering(cell);
        if (!leaf || b.shift(*leaf) == 0 || checked > 20000) return;
        ++checked;
        ASSERT_LT(std::abs(v.value), 2.0 * b.band());
        EXPECT_EQ(v.value, static_cast<float>(b.at(p)->distance) * 2.0f);
    });
    EXPECT_EQ(visits, voxels.size()) << "a voxel visited twice";
    EXPECT_GT(checked, 100u);
    std::size_t from_coarse = 0;
    for (const auto& [p, o] : surface_points(scene, 0.0)) {
        if (o != 0) continue;
        const std::optional<exchange::BrickSample> at = b.at(scene.objects[o].transform.inverse_apply(p));
        ASSERT_TRUE(at) << "a surface point outside every leaf";
        EXPECT_LT(std::abs(at->distance), s.tolerance + b.quantum());
        from_coarse += at->band > b.band();
    }
    EXPECT_GT(from_coarse, 0u);
}

TEST(ExchangeVdb, WithoutTheLibraryTheErrorNamesThePackage) {
    for (exchange::VdbFormat f : {exchange::VdbFormat::openvdb, exchange::VdbFormat::nanovdb}) {
        if (exchange::vdb_available(f)) {
            EXPECT_NO_THROW(exchange::require_vdb(f));
            continue;
        }
        try {
            exchange::require_vdb(f);
            ADD_FAILURE() << "require_vdb did not throw";
        } catch (const InputError& e) {
            EXPECT_NE(std::string(e.what()).find(f == exchange::VdbFormat::openvdb ? "libopenvdb-dev" : "libnanovdb-dev"),
                      std::string::npos);
        }
    }
}

// Checks a grid read back against the brick set: metadata, then values at world points near each
// object's surface (within one quantisation step of the object), far outside (+background) and deep
// inside (-background, from the flood fill).
template <class Sampler>
void check_grid(const Scene& scene, const std::vector<HostBricks>& bricks, std::size_t object, const Sampler& sample,
                double voxel_size, double background) {
    const Object& obj = scene.objects[object];
    const HostBricks& b = bricks[obj.geometry];
    const double s = obj.transform.scale;
    EXPECT_NEAR(voxel_size, b.voxel() * s, 1e-9 * s);
    EXPECT_NEAR(background, b.band() * s, 1e-6 * s);
    std::size_t compared = 0;
    for (const auto& [p, o] : surface_points(scene, 2.0 * b.voxel())) {
        if (o != object) continue;
        const std::optional<exchange::BrickSample> at = b.at(obj.transform.inverse_apply(p));
        if (!at) continue;
        ++compared;
        EXPECT_NEAR(sample(p), at->distance * s, (b.quantum() + 1e-4 * b.voxel()) * s) << "object " << object;
    }
    EXPECT_GT(compared, 150u);
    EXPECT_FLOAT_EQ(static_cast<float>(sample(obj.transform.apply(glm::dvec3(30.0, 0.0, 0.0)))), static_cast<float>(background));
}

#if SDFBRICK_WITH_OPENVDB
TEST(ExchangeVdb, OpenVdbRoundTrip) {
    const Scene scene = two_geometries();
    const std::vector<HostBricks> bricks = host_bricks(scene, settings(construct::BrickFormat::int8));
    const auto path = test::temp_dir("exchange_openvdb") / "scene.vdb";
    const exchange::VdbExport e = exchange::write_vdb(scene, bricks, path, exchange::VdbFormat::openvdb);
    ASSERT_EQ(e.grids.size(), 3u);
    EXPECT_EQ(e.file_bytes, std::filesystem::file_size(path));

    openvdb::initialize();
    openvdb::io::File file(path.string());
    file.open();
    const openvdb::GridPtrVecPtr grids = file.getGrids();
    file.close();
    ASSERT_EQ(grids->size(), 3u);
    for (std::size_t o = 0; o < 3; ++o) {
        const auto grid = openvdb::gridPtrCast<openvdb::FloatGrid>(openvdb::findGridByName(*grids, scene.objects[o].name));
        ASSERT_TRUE(grid) << scene.objects[o].name;
        EXPECT_EQ(grid->getGridClass(), openvdb::GRID_LEVEL_SET);
        EXPECT_EQ(grid->metaValue<std::string>("sdfbrick_geometry"), scene.geometries[scene.objects[o].geometry].name);
        EXPECT_EQ(grid->activeVoxelCount(), e.grids[o].active_voxels);
        EXPECT_TRUE(grid->hasUniformVoxels());
        openvdb::tools::GridSampler<openvdb::FloatGrid, openvdb::tools::BoxSampler> sampler(*grid);
        const auto sample = [&](const glm::dvec3& p) { return static_cast<double>(sampler.wsSample(openvdb::Vec3d(p.x, p.y, p.z))); };
        check_grid(scene, bricks, o, sample, grid->voxelSize()[0], grid->background());
        // Inside the solid, below the band: the flood fill's negative background.
        const Object& obj = scene.objects[o];
        if (obj.geometry != 0) continue;
        const glm::dvec3 core(0.35, 0.05, 0.0);  // 0.25 inside the blended sphere and box
        ASSERT_FALSE(bricks[0].at(core));
        EXPECT_FLOAT_EQ(static_cast<float>(sample(obj.transform.apply(core))), -grid->background());
    }
}
#endif

#if SDFBRICK_WITH_NANOVDB
TEST(ExchangeVdb, NanoVdbRoundTrip) {
    const Scene scene = two_geometries();
    const std::vector<HostBricks> bricks = host_bricks(scene, settings(construct::BrickFormat::int16));
    const auto path = test::temp_dir("exchange_nanovdb") / "scene.nvdb";
    const exchange::VdbExport e = exchange::write_vdb(scene, bricks, path, exchange::VdbFormat::nanovdb);
    ASSERT_EQ(e.grids.size(), 3u);
    const auto handles = nanovdb::io::readGrids(path.string());
    ASSERT_EQ(handles.size(), 3u);
    for (std::size_t o = 0; o < 3; ++o) {
        const nanovdb::FloatGrid* grid = handles[o].grid<float>();
        ASSERT_NE(grid, nullptr);
        EXPECT_EQ(std::string(grid->gridName()), scene.objects[o].name);  // NanoVDB keeps the order
        EXPECT_TRUE(grid->isLevelSet());
        EXPECT_EQ(grid->activeVoxelCount(), e.grids[o].active_voxels);
        const auto acc = grid->getAccessor();
        const auto sampler = nanovdb::createSampler<1>(acc);
        const auto sample = [&](const glm::dvec3& p) {
            return static_cast<double>(sampler(grid->worldToIndex(nanovdb::Vec3d(p.x, p.y, p.z))));
        };
        // NanoVDB's voxelSize() is map(1, 1, 1) - map(0, 0, 0), not a length under rotation: use the map's
        // first column.
        const double voxel = grid->map().applyJacobian(nanovdb::Vec3d(1.0, 0.0, 0.0)).length();
        check_grid(scene, bricks, o, sample, voxel, grid->tree().background());
    }
}
#endif

TEST(ExchangeSample, TheNearestObjectsBrickFieldInWorldUnits) {
    const Scene scene = two_geometries();
    const std::vector<HostBricks> bricks = host_bricks(scene, settings(construct::BrickFormat::int16));
    std::vector<glm::dvec3> points;
    std::vector<std::size_t> drawn_for;
    for (const auto& [p, o] : surface_points(scene, 1.0 * bricks[0].voxel())) {
        points.push_back(p);
        drawn_for.push_back(o);
    }
    points.push_back({40.0, 0.0, 0.0});
    const std::vector<exchange::PointSample> samples = exchange::sample_points(scene, bricks, points);
    ASSERT_EQ(samples.size(), points.size());
    for (std::size_t n = 0; n + 1 < samples.size(); ++n) {
        const exchange::PointSample& s = samples[n];
        ASSERT_TRUE(s.distance) << "point " << n;
        EXPECT_EQ(static_cast<std::size_t>(s.object), drawn_for[n]) << "the objects lie apart";
        const Object& obj = scene.objects[drawn_for[n]];
        const exchange::BrickSample at = *bricks[obj.geometry].at(obj.transform.inverse_apply(s.point));
        EXPECT_DOUBLE_EQ(*s.distance, at.distance * obj.transform.scale);
        EXPECT_NEAR(glm::length(s.gradient - obj.transform.rotation * at.gradient), 0.0, 1e-12);
        EXPECT_FALSE(s.saturated);
        // Trilinear of a 1-Lipschitz field: within the half diagonal of a cell of the reference.
        const double voxel = bricks[obj.geometry].voxel() * obj.transform.scale;
        EXPECT_NEAR(*s.distance, s.reference, 0.87 * voxel) << "point " << n;
        EXPECT_DOUBLE_EQ(s.reference, reference::evaluate(scene, s.point));
    }
    EXPECT_FALSE(samples.back().distance);
    EXPECT_EQ(samples.back().object, -1);
    const std::string csv = exchange::samples_csv(samples);
    EXPECT_EQ(csv.substr(0, csv.find('\n')), "x,y,z,distance,gx,gy,gz,object,saturated,reference");
    EXPECT_NE(csv.find("\n40,0,0,,,,,-1,0,"), std::string::npos);
}

TEST(ExchangeSample, ReadsCsvAndBinaryPoints) {
    const auto dir = test::temp_dir("exchange_points");
    test::write_text(dir / "p.csv", "x,y,z\n1,2,3\n\n -0.5 , 1e-3,4\n");
    const std::vector<glm::dvec3> csv = exchange::read_points(dir / "p.csv");
    ASSERT_EQ(csv.size(), 2u);
    EXPECT_EQ(csv[1], glm::dvec3(-0.5, 1e-3, 4.0));
    const float xyz[6] = {1.0f, 2.0f, 3.0f, -4.0f, 0.5f, 0.25f};
    test::write_text(dir / "p.bin", std::string_view(reinterpret_cast<const char*>(xyz), sizeof xyz));
    const std::vector<glm::dvec3> bin = exchange::read_points(dir / "p.bin");
    ASSERT_EQ(bin.size(), 2u);
    EXPECT_EQ(bin[1], glm::dvec3(-4.0, 0.5, 0.25));
}

TEST(ExchangeSample, BadPointFilesNameTheFileAndThePlace) {
    const auto dir = test::temp_dir("exchange_bad_points");
    const float nan_point[3] = {1.0f, std::nanf(""), 0.0f};
    const std::pair<std::string, std::string> cases[] = {
        {"empty.csv", ""},
        {"header.csv", "x,y,z\n"},
        {"two.csv", "1,2,3\n1,2\n"},
        {"text.csv", "1,2,3\n1,b,3\n"},
        {"inf.csv", "1,2,inf\n"},
        {"short.bin", "12345678901"},
        {"nan.bin", std::string(reinterpret_cast<const char*>(nan_point), sizeof nan_point)},
    };
    const char* expected[] = {"no points", "no points", "line 2", "line 2", "line 1", "11 bytes", "point 0"};
    for (std::size_t n = 0; n < std::size(cases); ++n) {
        test::write_text(dir / cases[n].first, cases[n].second);
        try {
            exchange::read_points(dir / cases[n].first);
            ADD_FAILURE() << cases[n].first << " was accepted";
        } catch (const InputError& e) {
            const std::string what = e.what();
            EXPECT_NE(what.find(cases[n].first), std::string::npos) << what;
            EXPECT_NE(what.find(expected[n]), std::string::npos) << what;
        }
    }
    EXPECT_THROW(exchange::read_points(dir / "missing.csv"), InputError);
}

}  // namespace
}  // namespace sdfbrick
