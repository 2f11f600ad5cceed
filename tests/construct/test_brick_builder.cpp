// Sparse brick construction (host/construct/brick_builder.h on the test device) against the
// double-precision host reference (host/reference/): no surface cell without a brick, every stored
// sample within one quantisation step of the reference, and the determinism contract: culling on and
// off, dependencies on and off, repeated runs, and branching 2 and 4 all give bit-identical outputs.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <set>
#include <tuple>

#include <fmt/format.h>
#include <glm/gtc/quaternion.hpp>
#include <gtest/gtest.h>

#include "cl/launch.h"
#include "cl/program.h"
#include "construct/brick_builder.h"
#include "core/errors.h"
#include "reference/reference_field.h"
#include "reference/surface_cells.h"
#include "scene/scene_json.h"
#include "test_support.h"

namespace sdfbrick {
namespace {

using construct::BrickFormat;
using construct::BuildSettings;
using construct::GeometryBuild;

construct::BrickBuilder& builder() {
    static construct::BrickBuilder b(test::device());
    return b;
}

Edit make_edit(Primitive prim, std::array<double, 4> params, glm::dvec3 at, Op op = Op::Add, double blend = 0.0,
               double angle = 0.0, double scale = 1.0) {
    Edit e;
    e.primitive = prim;
    e.params = params;
    e.transform.translation = at;
    e.transform.rotation = glm::angleAxis(angle, glm::normalize(glm::dvec3(1.0, 2.0, 0.5)));
    e.transform.scale = scale;
    e.op = op;
    e.blend = blend;
    return e;
}

// Every primitive and every combine rule, hard and smooth, rotated and scaled.
Geometry mixed_geometry() {
    Geometry g;
    g.name = "mixed";
    g.edits = {
        make_edit(Primitive::Sphere, {0.6, 0, 0, 0}, {0.0, 0.0, 0.0}),
        make_edit(Primitive::Box, {0.4, 0.3, 0.5, 0}, {0.7, 0.1, 0.0}, Op::Add, 0.2, 0.7),
        make_edit(Primitive::Torus, {0.45, 0.12, 0, 0}, {-0.5, 0.35, 0.2}, Op::Add, 0.15, 1.1),
        make_edit(Primitive::Sphere, {0.3, 0, 0, 0}, {0.2, 0.45, 0.3}, Op::Subtract, 0.1),
        make_edit(Primitive::Capsule, {0.35, 0.15, 0, 0}, {0.0, -0.55, 0.1}, Op::Add, 0.0, 0.4),
        make_edit(Primitive::RoundBox, {0.25, 0.2, 0.3, 0.08}, {-0.2, -0.3, -0.6}, Op::Add, 0.1, 2.0, 1.2),
        make_edit(Primitive::Cylinder, {0.3, 0.2, 0, 0}, {0.6, -0.4, 0.5}, Op::Add, 0.05),
        make_edit(Primitive::Cone, {0.3, 0.25, 0.1, 0}, {-0.8, -0.2, 0.3}, Op::Add, 0.0, 0.3),
        make_edit(Primitive::Ellipsoid, {0.3, 0.15, 0.2, 0}, {0.3, 0.7, -0.3}, Op::Add, 0.12, 0.9),
        make_edit(Primitive::Menger, {0.3, 2, 0, 0}, {-0.7, 0.6, -0.5}, Op::Add, 0.0, 0.5),
        make_edit(Primitive::Box, {0.12, 0.8, 0.12, 0}, {0.1, 0.0, 0.0}, Op::Subtract, 0.0, 0.2),
        make_edit(Primitive::Box, {1.05, 1.0, 1.0, 0}, {0.0, 0.0, 0.0}, Op::Intersect, 0.05),
    };
    return g;
}

// A block carved by smooth and hard subtractions, then cut by an intersection: long lists in which
// every edit after the first raises the fold.
Geometry carved_geometry() {
    Geometry g;
    g.name = "carved";
    g.edits = {make_edit(Primitive::Box, {0.9, 0.7, 0.8, 0}, {0.0, 0.0, 0.0}, Op::Add, 0.0, 0.3)};
    for (int i = 0; i < 24; ++i) {
        const double a = 0.7 * i, r = 0.15 + 0.02 * (i % 5);
        g.edits.push_back(make_edit(i % 3 == 0 ? Primitive::Box : Primitive::Sphere, {r, 0.8 * r, r, 0},
                                    {0.8 * std::cos(a), 0.6 * std::sin(1.3 * a), 0.7 * std::cos(0.9 * a)}, Op::Subtract,
                                    i % 2 == 0 ? 0.12 : 0.0, a));
    }
    g.edits.push_back(make_edit(Primitive::Sphere, {1.05, 0, 0, 0}, {0.0, 0.0, 0.0}, Op::Intersect, 0.1));
    return g;
}

// Rotated, scaled capsules and spheres, added and then carved by smooth and hard subtractions, all
// within reach of each other: long lists, with most of their edits far from most samples.
Geometry capsules_geometry() {
    Geometry g;
    g.name = "capsules";
    for (int i = 0; i < 40; ++i) {
        const double a = 0.9 * i, r = 0.06 + 0.015 * (i % 4);
        const glm::dvec3 at{0.6 * std::cos(a), 0.5 * std::sin(1.7 * a), 0.6 * std::sin(0.8 * a)};
        const Op op = i < 28 ? Op::Add : Op::Subtract;
        const double blend = i % 3 == 2 ? 0.0 : 0.2 + 0.05 * (i % 2);
        g.edits.push_back(i % 5 == 4 ? make_edit(Primitive::Sphere, {1.5 * r, 0, 0, 0}, at, op, blend)
                                     : make_edit(Primitive::Capsule, {0.1 + 0.05 * (i % 5), r, 0, 0}, at, op, blend, a,
                                                 0.8 + 0.1 * (i % 6)));
    }
    return g;
}

// Every primitive but spheres, capsules and meshes, rotated and scaled, added and then carved by
// smooth and hard subtractions within reach of each other (long lists): the work-item's skip test
// for any primitive.
Geometry assorted_geometry() {
    static constexpr Primitive kinds[] = {Primitive::Box,      Primitive::RoundBox, Primitive::Torus, Primitive::Cylinder,
                                          Primitive::Cone,     Primitive::Ellipsoid, Primitive::Menger};
    Geometry g;
    g.name = "assorted";
    for (int i = 0; i < 42; ++i) {
        const double a = 0.8 * i, r = 0.08 + 0.02 * (i % 3);
        const glm::dvec3 at{0.45 * std::cos(a), 0.4 * std::sin(1.3 * a), 0.45 * std::sin(0.7 * a)};
        const Primitive kind = kinds[i % 7];
        const std::array<double, 4> params = kind == Primitive::Menger ? std::array<double, 4>{2 * r, 2, 0, 0}
                                             : kind == Primitive::Torus ? std::array<double, 4>{1.5 * r, 0.5 * r, 0, 0}
                                             : kind == Primitive::RoundBox ? std::array<double, 4>{r, 1.2 * r, 0.8 * r, 0.3 * r}
                                                                          : std::array<double, 4>{r, 0.8 * r, 1.4 * r, 0};
        g.edits.push_back(make_edit(kind, params, at, i < 30 ? Op::Add : Op::Subtract, i % 4 == 3 ? 0.0 : 0.15, a,
                                    0.8 + 0.1 * (i % 5)));
    }
    return g;
}

Geometry shipped_geometry(const char* name) {
    const Scene s = load_scene(std::string(SDFBRICK_SOURCE_DIR) + "/scenes/" + name + ".json");
    return scene_at(s, s.time).geometries.at(0);
}

// A corner of the drops scene: its first n edits (smooth spheres that overlap and chain).
Geometry drops_subset(std::size_t n) {
    Geometry g = shipped_geometry("drops");
    g.edits.resize(std::min(n, g.edits.size()));
    return g;
}

BuildSettings settings(double leaf, BrickFormat format = BrickFormat::int8, int samples = 8) {
    BuildSettings s;
    s.leaf_size = leaf;
    s.format = format;
    s.samples = samples;
    s.chunk = 32;
    s.eval_group = 64;
    return s;
}

double stored_value(const std::vector<std::uint8_t>& pool, BrickFormat f, std::size_t i, float band) {
    switch (f) {
        case BrickFormat::int8: return static_cast<std::int8_t>(pool[i]) * (band / 127.0);
        case BrickFormat::int16: {
            std::int16_t v;
            std::memcpy(&v, &pool[2 * i], 2);
            return v * (band / 32767.0);
        }
        case BrickFormat::float32: {
            float v;
            std::memcpy(&v, &pool[4 * i], 4);
            return v;
        }
    }
    return 0.0;
}

// Leaves cover every reference surface cell; stored samples match the reference within one step.
void check_against_reference(const Geometry& g, const BuildSettings& s) {
    const GeometryBuild b = builder().build(g, s, test::recorder());
    ASSERT_GT(b.leaf_count, 0u);
    const construct::Domain domain = construct::make_domain(bounds(g), s.leaf_size, s.branching);
    ASSERT_EQ(b.levels, domain.levels);
    const std::vector<SdfBrick> leaves = b.leaves->read();
    std::set<std::tuple<int, int, int>> have;
    for (const SdfBrick& l : leaves) have.emplace(l.coord[0], l.coord[1], l.coord[2]);
    ASSERT_EQ(have.size(), leaves.size()) << "duplicate leaf bricks";
    std::size_t missing = 0;
    const std::vector<glm::ivec3> cells = reference::surface_cells(g, domain);
    for (const glm::ivec3& c : cells) missing += !have.count({c.x, c.y, c.z});
    EXPECT_EQ(missing, 0u) << "of " << cells.size() << " reference surface cells";
    // Not far more bricks than the reference needs (the margins are small).
    EXPECT_LE(leaves.size(), cells.size() + cells.size() / 50 + 8);

    const std::vector<std::uint8_t> pool = b.pool->read();
    const int n = s.samples, a = s.layout().apron(), interior = s.layout().interior();
    const auto voxel = static_cast<float>(s.voxel());
    const double step = s.format == BrickFormat::int8    ? b.band / 127.0
                        : s.format == BrickFormat::int16 ? b.band / 32767.0
                                                         : 0.0;
    // One quantisation step, plus the float evaluation's own rounding (test_field_eval's bound).
    const double m = std::max({1.0, std::abs(double(b.origin.x)), std::abs(double(b.origin.y)), std::abs(double(b.origin.z))}) + 4.0;
    const double tolerance = step + 32.0 * std::ldexp(1.0, -24) * m;
    double worst = 0.0;
    std::size_t over = 0, index = 0;
    for (const SdfBrick& l : leaves) {
        for (int k = 0; k < n; ++k)
            for (int j = 0; j < n; ++j)
                for (int i = 0; i < n; ++i, ++index) {
                    const int ijk[3] = {i, j, k};
                    glm::dvec3 p;
                    for (int ax = 0; ax < 3; ++ax)  // the kernel's float arithmetic, step by step
                        p[ax] = b.origin[ax] + (static_cast<float>(l.coord[ax] * interior + ijk[ax] - a) + 0.5f) * voxel;
                    const double ref = std::clamp(reference::evaluate(g, p), -double(b.band), double(b.band));
                    const double err = std::abs(stored_value(pool, s.format, index, b.band) - ref);
                    worst = std::max(worst, err);
                    over += err > tolerance;
                }
    }
    EXPECT_EQ(over, 0u) << "samples beyond one step; worst error " << worst << ", tolerance " << tolerance;
}

TEST(ConstructBuild, MixedGeometryMatchesReferenceInt8) { check_against_reference(mixed_geometry(), settings(0.125)); }
TEST(ConstructBuild, MixedGeometryMatchesReferenceInt16TwoVoxelApron) {
    check_against_reference(mixed_geometry(), settings(0.125, BrickFormat::int16, 10));
}
TEST(ConstructBuild, MixedGeometryMatchesReferenceFloatOctree) {
    BuildSettings s = settings(0.125, BrickFormat::float32);
    s.branching = 2;
    check_against_reference(mixed_geometry(), s);
}
// Every primitive and operation in lists long enough to branch once per edit, where the kernel
// compiles only the folds of the primitives and operations the geometry uses: three shifted copies
// of the mixed geometry, with one lane (the GPUs' path, far edits skipped) and the device's lanes.
TEST(ConstructBuild, LongMixedListsMatchReference) {
    Geometry g = mixed_geometry();
    const std::vector<Edit> one = g.edits;
    for (const double shift : {0.03, -0.05})
        for (Edit e : one) {
            e.transform.translation += glm::dvec3(shift, 0.0, -shift);
            g.edits.push_back(e);
        }
    BuildSettings s = settings(0.125);
    check_against_reference(g, s);
    s.eval_lanes = 1;
    check_against_reference(g, s);
}
TEST(ConstructBuild, SpheresMatchReference) { check_against_reference(shipped_geometry("spheres"), settings(0.0625)); }
TEST(ConstructBuild, DropsCornerMatchesReference) { check_against_reference(drops_subset(48), settings(0.125)); }

std::string digest(const Geometry& g, const BuildSettings& s) {
    const GeometryBuild b = builder().build(g, s, test::recorder());
    return construct::output_digest(b, s);
}

// Culling changes no bit: on, off (every edit at every sample) and with dependencies, in both sample
// layouts.
TEST(ConstructBuild, CullingOnAndOffAreBitIdentical) {
    for (const Geometry& g : {mixed_geometry(), drops_subset(64), shipped_geometry("spheres"), carved_geometry()}) {
        for (BuildSettings on : {settings(0.125), settings(0.125, BrickFormat::float32),
                                 settings(0.125, BrickFormat::int16, 10)}) {
            BuildSettings off = on, deps = on;
            off.cull = false;
            deps.dependencies = true;
            const GeometryBuild culled = builder().build(g, on, test::recorder());
            const GeometryBuild full = builder().build(g, off, test::recorder());
            const std::string where = fmt::format("{}, {} samples, format {}", g.name, on.samples, to_string(on.format));
            EXPECT_EQ(construct::output_digest(culled, on), construct::output_digest(full, off)) << where;
            EXPECT_EQ(digest(g, deps), construct::output_digest(full, off)) << where << " with dependencies";
            EXPECT_EQ(culled.leaf_count, full.leaf_count);
            if (g.edits.size() > 4) {
                EXPECT_LT(culled.edits_per_leaf_mean, 0.7 * full.edits_per_leaf_mean) << where;
            }
        }
    }
}

// With dependencies on, a leaf's list is the list without them plus dependencies: every extra entry
// is an edit earlier than a smooth edit of the list without them (a smooth edit depends on earlier
// edits only), and some leaves get extra entries (drops' smooth spheres chain).
TEST(ConstructBuild, DependenciesAddEarlierEditsToTheLists) {
    const Geometry g = drops_subset(128);
    BuildSettings plain = settings(0.125), dependent = plain;
    dependent.dependencies = true;
    const GeometryBuild a = builder().build(g, plain, test::recorder());
    const GeometryBuild b = builder().build(g, dependent, test::recorder());
    ASSERT_EQ(a.leaf_count, b.leaf_count);
    const std::vector<SdfBrick> la = a.leaves->read(), lb = b.leaves->read();
    const std::vector<cl_uint> ia = a.leaf_edit_indices->read(), ib = b.leaf_edit_indices->read();
    std::size_t added = 0;
    for (std::size_t i = 0; i < la.size(); ++i) {
        const auto first_a = ia.begin() + la[i].edit_offset, first_b = ib.begin() + lb[i].edit_offset;
        const std::vector<cl_uint> sa(first_a, first_a + la[i].edit_count), sb(first_b, first_b + lb[i].edit_count);
        ASSERT_TRUE(std::includes(sb.begin(), sb.end(), sa.begin(), sa.end())) << "leaf " << i;
        cl_uint last_smooth = 0;
        for (cl_uint e : sa)
            if (g.edits[e].blend > 0.0f) last_smooth = std::max(last_smooth, e);
        for (cl_uint e : sb) {
            if (std::binary_search(sa.begin(), sa.end(), e)) continue;
            ++added;
            EXPECT_LT(e, last_smooth) << "leaf " << i << ": edit " << e << " is no earlier than a smooth edit";
        }
    }
    EXPECT_GT(added, 0u);
}

TEST(ConstructBuild, RepeatedRunsAreBitIdentical) {
    const Geometry g = drops_subset(64);
    const BuildSettings s = settings(0.125);
    const GeometryBuild a = builder().build(g, s, test::recorder()), b = builder().build(g, s, test::recorder());
    EXPECT_EQ(construct::output_digest(a, s), construct::output_digest(b, s));
    EXPECT_EQ(construct::list_digest(a), construct::list_digest(b));
}

TEST(ConstructBuild, BranchingTwoAndFourGiveTheSameLeaves) {
    // Domains coincide when 4^(L-1) = 2^(L'-1): L' = 2L - 1 levels with branching 2.
    const Geometry g = mixed_geometry();
    BuildSettings four = settings(0.125), two = four;
    four.levels = 4;  // 0.125 * 64 = 8 units: covers the geometry from its origin
    two.branching = 2;
    two.levels = 7;
    const GeometryBuild b4 = builder().build(g, four, test::recorder()), b2 = builder().build(g, two, test::recorder());
    EXPECT_GT(b4.leaf_count, 100u);
    EXPECT_EQ(b4.leaf_count, b2.leaf_count);
    EXPECT_EQ(construct::output_digest(b4, four), construct::output_digest(b2, two));
}

TEST(ConstructBuild, ChunkAndGroupSizesDoNotChangeTheOutput) {
    const Geometry g = drops_subset(64);
    BuildSettings s = settings(0.125);
    const std::string expected = digest(g, s);
    for (auto [chunk, group] : {std::pair{16, 32}, {256, 512}, {64, 1}}) {
        s.chunk = chunk;
        s.eval_group = group;
        EXPECT_EQ(digest(g, s), expected) << "chunk " << chunk << ", group " << group;
    }
}

// The evaluation's SIMD lanes (sdf_edit.h) give every sample the float path's bits: every primitive
// and combine rule, in each format, with 8^3 and 10^3 samples (1000 is no multiple of 16: the last
// value's lanes past the brick are dropped), one and many work-items; and the count's lanes (children
// a work-item) give every child the scalar fold's test.
TEST(ConstructBuild, LanesDoNotChangeTheOutput) {
    const Geometry g = mixed_geometry();
    for (BuildSettings s : {settings(0.125), settings(0.125, BrickFormat::int16, 10), settings(0.25, BrickFormat::float32)}) {
        s.eval_lanes = 1;
        const std::string expected = digest(g, s);
        for (auto [lanes, group] : {std::pair{4, 64}, {8, 1}, {8, 64}, {16, 16}}) {
            s.eval_lanes = lanes;
            s.eval_group = group;
            EXPECT_EQ(digest(g, s), expected) << "lanes " << lanes << ", group " << group << ", samples " << s.samples;
        }
    }
}

// Construction follows the surface at every level: each level keeps at most 4x the reference's
// surface cells of that level (a level kept dense would keep its whole volume), including the coarse
// levels whose threshold reaches C, on hard CSG with little volume and on chains of smooth blends.
void check_levels_follow_surface(const Geometry& g, const BuildSettings& s) {
    const GeometryBuild b = builder().build(g, s, test::recorder());
    construct::Domain domain = construct::make_domain(bounds(g), s.leaf_size, s.branching);
    const std::vector<std::uint64_t> reference = reference::count_surface_cells(g, domain);
    ASSERT_EQ(b.level_reports.size(), reference.size());
    bool coarse_tested = false;
    for (std::size_t l = 0; l < reference.size(); ++l) {
        const std::uint64_t kept = b.level_reports[l].bricks;
        EXPECT_LE(kept, 4 * reference[l] + 1) << g.name << " level " << l << ": " << kept << " kept, reference "
                                              << reference[l];
        EXPECT_GE(kept, reference[l] - reference[l] / 50) << g.name << " level " << l;
        coarse_tested = coarse_tested || domain.half_diagonal(static_cast<int>(l)) > b.clamp_c;
    }
    EXPECT_TRUE(coarse_tested) << g.name << ": no level's threshold reaches C, the coarse test is not exercised";
}

TEST(ConstructBuild, EveryLevelFollowsTheSurfaceHardCsg) {
    check_levels_follow_surface(shipped_geometry("board"), settings(0.125));
    check_levels_follow_surface(shipped_geometry("cubes"), settings(0.25));
}

TEST(ConstructBuild, EveryLevelFollowsTheSurfaceSmoothBlends) {
    check_levels_follow_surface(mixed_geometry(), settings(0.0625));
    check_levels_follow_surface(drops_subset(48), settings(0.125));
}

// Skipping the points where an edit cannot change the fold (BuildSettings::skip_far: a sphere or
// capsule per work-item, then per sample with one lane, per work-item alone in lanes, the work-item's
// test from skip records in lanes, from the staged edit with one lane; any other primitive per
// work-item with one lane) changes no bit: adds and subtracts, smooth and hard, rotated and scaled,
// both sample layouts, int8 and float (where the sign of a zero shows), with and without shared
// aprons, with one lane and with the device's.
TEST(ConstructBuild, SkippingFarEditsDoesNotChangeTheOutput) {
    Geometry drops = drops_subset(160), carved = carved_geometry();
    for (Edit& e : drops.edits) e.transform.translation *= 0.3;  // the drops closer together
    for (Edit& e : carved.edits) e.blend *= 3.0;
    for (const Geometry& g : {drops, carved, capsules_geometry(), assorted_geometry()}) {
        for (BuildSettings s : {settings(0.125), settings(0.125, BrickFormat::float32, 10)}) {
            BuildSettings all = s;
            all.skip_far = false;
            const GeometryBuild full = builder().build(g, all, test::recorder());
            for (auto [lanes, share] : {std::pair{1, 0}, {1, 1}, {0, 0}}) {
                s.eval_lanes = lanes;
                s.apron_share_edits = share;
                const GeometryBuild b = builder().build(g, s, test::recorder());
                const std::string where =
                    fmt::format("{}, {} samples, lanes {}, sharing from {}", g.name, s.samples, lanes, share);
                EXPECT_EQ(construct::list_digest(b), construct::list_digest(full)) << where;
                EXPECT_EQ(construct::output_digest(b, s), construct::output_digest(full, all)) << where;
            }
        }
    }
}

// The count stage's work-items per child (BuildSettings::count_parts: automatic, which on a CPU is a
// SIMD value of children a work-item, and 2 and 16, which compute the values in turn and fold them
// in one) and its work-groups per parent (count_splits 2 and 8 with 4 parts: each takes a share of
// the children) change no bit; nor does
// culling with dependencies, whose lists the cull stage writes with as many bits per work-item as
// its levels need (one at the top, up to a word where a level has many bricks); nor does the cull's
// work-group per parent for its new children (cull_siblings 1: at every level with a parent per compute
// unit, 0: at none); nor do the children kept untested below parents with long lists (count_untested
// 16 and 64: more bricks at the coarse levels, the same leaves). Both the lists and the output are
// compared: long lists at the top levels, smooth and hard edits, branching 2, adaptive leaves, and
// the whole of drops at 0.25, where the cull gives a parent with a long list several work-groups.
TEST(ConstructBuild, CountPartsDoNotChangeTheOutput) {
    const Geometry drops = drops_subset(128), all_drops = drops_subset(1024), carved = carved_geometry();
    BuildSettings octree = settings(0.125), dependent = settings(0.125), adaptive = settings(0.0625);
    octree.branching = 2;
    dependent.dependencies = true;
    adaptive.tolerance = 0.01;
    for (auto [g, s] : {std::pair{&drops, settings(0.0625)}, {&carved, settings(0.125, BrickFormat::float32, 10)},
                        {&drops, octree}, {&drops, dependent}, {&carved, adaptive}, {&all_drops, settings(0.25)}}) {
        const GeometryBuild automatic = builder().build(*g, s, test::recorder());
        ASSERT_GT(automatic.leaf_count, 0u);
        for (auto [parts, splits, siblings, untested] :
             {std::tuple{2, 0, 8, 0}, {16, 0, 8, 16}, {4, 2, 8, 0}, {4, 8, 8, 64}, {0, 0, 1, 16}, {0, 0, 0, 0}}) {
            BuildSettings split = s;
            split.count_parts = parts;
            split.count_splits = splits;
            split.cull_siblings = siblings;
            split.count_untested = untested;
            const GeometryBuild b = builder().build(*g, split, test::recorder());
            const std::string where =
                fmt::format("{}, branching {}, count parts {}, splits {}, cull siblings {}, untested from {}", g->name,
                            s.branching, parts, splits, siblings, untested);
            EXPECT_EQ(construct::list_digest(b), construct::list_digest(automatic)) << where;
            EXPECT_EQ(construct::output_digest(b, split), construct::output_digest(automatic, s)) << where;
        }
    }
}

// The count stage folds with sdf_fold_select, a copy of sdf_combine without branches: bit for bit
// the same result for every operation, hard and smooth (blend 0, NaN and negative count as hard),
// with fields and values that are signed zeros, tiny, in and beyond the blend, infinite or NaN.
TEST(ConstructBuild, FoldWithoutBranchesGivesTheCombinesBits) {
    ocl::Device& device = test::device();
    const ocl::Kernel kernel = ocl::make_kernel(ocl::build_program(device, "fold_probe.cl"), "fold_probe");
    std::vector<SdfEdit> edits;
    for (cl_uint op : {SDF_OP_ADD, SDF_OP_SUBTRACT, SDF_OP_INTERSECT})
        for (float blend : {0.0f, 0.05f, 0.3f, 2.0f, -0.1f, std::nanf("")}) {
            SdfEdit e{};
            e.transform.scale = 1.0f;
            e.transform.rotation[3] = 1.0f;
            e.inv_lipschitz = 1.0f;
            e.blend = blend;
            e.primitive = SDF_PRIM_SPHERE;
            e.op = op;
            edits.push_back(e);
        }
    const float inf = std::numeric_limits<float>::infinity(), nan = std::nanf("");
    const std::vector<float> points = {-0.0f, 0.0f, 1e-30f, -1e-30f, 0.01f, -0.01f, 0.2f, -0.2f, 0.6546f, -0.7f, 3.0f,
                                       -3.0f, inf, -inf, nan};
    std::vector<float> fields, values;
    for (float f : points)
        for (float v : points) {
            fields.push_back(f);
            values.push_back(v);
        }
    const auto n = static_cast<cl_uint>(edits.size()), pairs = static_cast<cl_uint>(fields.size());
    ocl::Buffer<SdfEdit> edit_buffer(device, edits);
    ocl::Buffer<float> field_buffer(device, fields), value_buffer(device, values), out(device, 2 * n * pairs);
    ocl::set_args(kernel.get(), edit_buffer, field_buffer, value_buffer, n, pairs, out);
    ocl::enqueue(device, kernel.get(), "fold_probe", std::size_t{n} * pairs);
    const std::vector<float> got = out.read();
    for (std::size_t i = 0; i < std::size_t{n} * pairs; ++i) {
        const float combine = got[2 * i], select = got[2 * i + 1];
        std::uint32_t a = 0, b = 0;
        std::memcpy(&a, &combine, sizeof a);
        std::memcpy(&b, &select, sizeof b);
        const SdfEdit& e = edits[i / pairs];
        EXPECT_TRUE(a == b || (std::isnan(combine) && std::isnan(select)))
            << "op " << e.op << ", blend " << e.blend << ", field " << fields[i % pairs] << ", value "
            << values[i % pairs] << ": combine " << combine << ", select " << select;
    }
}

// Edit evaluations of a build's leaves where each leaf with at least share_edits edits evaluates its
// 6^3 interior and every apron sample (8^3 samples) that no leaf of its level beside it holds in its
// interior (a face neighbour holds 36 of them, an edge neighbour 6, a corner neighbour 1), and every
// other leaf all its samples.
std::uint64_t owned_evaluations(const GeometryBuild& b, std::uint32_t share_edits) {
    const std::vector<SdfBrick> leaves = b.leaves->read();
    std::set<std::array<std::int64_t, 4>> cells;
    for (const SdfBrick& l : leaves) cells.insert({l.level, l.coord[0], l.coord[1], l.coord[2]});
    std::uint64_t evaluations = 0;
    for (const SdfBrick& l : leaves) {
        std::uint64_t samples = 512;
        for (int dx = -1; dx <= 1 && l.edit_count >= share_edits; ++dx)
            for (int dy = -1; dy <= 1; ++dy)
                for (int dz = -1; dz <= 1; ++dz) {
                    const int moved = (dx != 0) + (dy != 0) + (dz != 0);
                    if (moved > 0 && cells.count({l.level, l.coord[0] + dx, l.coord[1] + dy, l.coord[2] + dz}) > 0)
                        samples -= moved == 1 ? 36 : moved == 2 ? 6 : 1;
                }
        evaluations += samples * l.edit_count;
    }
    return evaluations;
}

// Sharing apron samples with the neighbours (BuildSettings::apron_share_edits: every leaf, some,
// none) changes no bit: uniform and adaptive builds, both sample layouts, every format, branching 2,
// with and without culling.
TEST(ConstructBuild, SharedApronsDoNotChangeTheOutput) {
    const Geometry mixed = mixed_geometry(), drops = drops_subset(64);
    BuildSettings octree = settings(0.125), unculled = settings(0.125), adaptive = settings(0.0625);
    octree.branching = 2;
    unculled.cull = false;
    adaptive.tolerance = 0.01;
    for (auto [g, s] : {std::pair{&mixed, settings(0.125)}, {&mixed, settings(0.125, BrickFormat::int16, 10)},
                        {&mixed, settings(0.25, BrickFormat::float32)}, {&mixed, octree}, {&drops, unculled},
                        {&drops, adaptive}}) {
        BuildSettings own = s, some = s;
        s.apron_share_edits = 1;
        own.apron_share_edits = 0;
        some.apron_share_edits = 3;
        const GeometryBuild shared = builder().build(*g, s, test::recorder());
        const std::string expected = digest(*g, own);
        const std::string where = fmt::format("{}, {} samples, branching {}, tolerance {}", g->name, s.samples,
                                              s.branching, s.tolerance);
        EXPECT_EQ(construct::output_digest(shared, s), expected) << where;
        EXPECT_EQ(digest(*g, some), expected) << where << ", lists of 3 or more";
        EXPECT_GT(shared.leaf_count, 50u);
    }
}

TEST(ConstructBuild, LevelsAndWorkAreReported) {
    measure::Scheduler scheduler(test::device());
    BuildSettings s = settings(0.125);
    s.apron_share_edits = 4;
    const GeometryBuild b = builder().build(drops_subset(64), s, scheduler);
    ASSERT_EQ(b.level_reports.size(), static_cast<std::size_t>(b.levels));
    EXPECT_EQ(b.level_reports.back().bricks, b.leaf_count);
    EXPECT_GT(b.edit_evaluations, b.leaf_count * 512);
    for (const char* r : {"brick pool", "brick records", "aabbs", "edit lists"}) EXPECT_GT(b.memory.at(r), 0u) << r;
    EXPECT_EQ(b.memory.at("brick pool"), b.leaf_count * 512);
    // The roofline's work: drops are smooth unit-scale spheres, 20 FLOPs an evaluation (work.h).
    const construct::StageWork& evaluate = b.work.at(measure::Stage::evaluate);
    EXPECT_EQ(evaluate.evaluations, owned_evaluations(b, 4));
    EXPECT_LT(evaluate.evaluations, b.level_reports.back().edit_entries * 512 * 9 / 10);  // neighbours share aprons
    EXPECT_EQ(evaluate.flop, 20.0 * static_cast<double>(evaluate.evaluations));
    EXPECT_GT(evaluate.bytes, static_cast<double>(b.memory.at("brick pool")));
    EXPECT_EQ(b.work.at(measure::Stage::count).evaluations + b.work.at(measure::Stage::cull).evaluations +
                  evaluate.evaluations,
              b.edit_evaluations);
    EXPECT_EQ(b.first_launch, 0u);
    EXPECT_EQ(b.end_launch, scheduler.size());
    for (const char* stage : {"count", "scan", "subdivide", "cull", "apron", "evaluate", "aabb"})
        EXPECT_TRUE(std::any_of(scheduler.launches().begin(), scheduler.launches().end(),
                                [&](const measure::Launch& l) { return to_string(l.stage) == stage; }))
            << stage;
    // AABBs are the leaves' boxes.
    const std::vector<SdfBounds> boxes = b.aabbs->read();
    const std::vector<SdfBrick> leaves = b.leaves->read();
    ASSERT_EQ(boxes.size(), leaves.size());
    for (int ax = 0; ax < 3; ++ax) {
        EXPECT_FLOAT_EQ(boxes[0].lo[ax], b.origin[ax] + static_cast<float>(leaves[0].coord[ax]) * b.leaf_size);
        EXPECT_FLOAT_EQ(boxes[0].hi[ax] - boxes[0].lo[ax], b.leaf_size);
    }
}

TEST(ConstructBuild, EmptyGeometryGivesAnEmptyValidResult) {
    Geometry g;
    g.name = "empty";
    GeometryBuild b = builder().build(g, settings(0.125), test::recorder());
    EXPECT_EQ(b.leaf_count, 0u);
    g.edits = {make_edit(Primitive::Sphere, {0.5, 0, 0, 0}, {0, 0, 0}, Op::Subtract)};  // removes from nothing
    b = builder().build(g, settings(0.125), test::recorder());
    EXPECT_EQ(b.leaf_count, 0u);
    EXPECT_EQ(b.pool->size(), 0u);
}

TEST(ConstructBuild, DegenerateAndTinyGeometry) {
    Geometry g;
    g.name = "point";
    g.edits = {make_edit(Primitive::Sphere, {1e-6, 0, 0, 0}, {0.3, 0.3, 0.3})};
    const GeometryBuild b = builder().build(g, settings(0.125), test::recorder());
    EXPECT_GE(b.leaf_count, 1u);
    EXPECT_LE(b.leaf_count, 8u);
}

TEST(ConstructBuild, RefusesWhatCannotBeBuilt) {
    const Geometry g = mixed_geometry();
    BuildSettings s = settings(1e-7);  // 2^30 leaf cells per axis and more
    EXPECT_THROW(builder().build(g, s, test::recorder()), InputError);
    s = settings(0.125);
    s.levels = 2;  // too few to cover the geometry
    EXPECT_THROW(builder().build(g, s, test::recorder()), InputError);
    s = settings(0.125);
    s.chunk = 8;
    EXPECT_THROW(builder().build(g, s, test::recorder()), InputError);
    s = settings(0.125);
    s.samples = 9;
    EXPECT_THROW(builder().build(g, s, test::recorder()), InputError);
    s = settings(0.125);
    s.eval_group = 96;
    EXPECT_THROW(builder().build(g, s, test::recorder()), InputError);
    s = settings(std::nan(""));
    EXPECT_THROW(builder().build(g, s, test::recorder()), InputError);
}

// A refused setting is named as the library names it (SettingError::setting()); the CLI and the sweep
// put their flag or key in front, so the message itself names no flag.
TEST(ConstructBuild, RefusedSettingsAreNamedInLibraryTerms) {
    BuildSettings s = settings(0.125);
    s.chunk = 8;
    try {
        s.validate(test::device().info());
        ADD_FAILURE() << "chunk 8 was accepted";
    } catch (const SettingError& e) {
        EXPECT_EQ(e.setting(), "chunk");
        EXPECT_STREQ(e.what(), "chunk must lie in 16..256, got 8");
    }
    const auto refused = [](const BuildSettings& bad) -> std::string {
        try {
            builder().build(mixed_geometry(), bad, test::recorder());
        } catch (const SettingError& e) {
            EXPECT_EQ(std::string(e.what()).find("--"), std::string::npos) << e.what();
            EXPECT_EQ(std::string(e.what()).rfind(e.setting(), 0), 0u) << e.what();
            return e.setting();
        }
        return "(accepted)";
    };
    s = settings(std::nan(""));
    EXPECT_EQ(refused(s), "leaf_size");
    s = settings(0.125);
    s.samples = 9;
    EXPECT_EQ(refused(s), "samples");
    s = settings(0.125);
    s.eval_group = 96;
    EXPECT_EQ(refused(s), "eval_group");
    s = settings(0.125);
    s.eval_lanes = 3;
    EXPECT_EQ(refused(s), "eval_lanes");
    s = settings(0.125);
    s.count_parts = 6;
    EXPECT_EQ(refused(s), "count_parts");
    s = settings(0.125);
    s.count_splits = 3;
    EXPECT_EQ(refused(s), "count_splits");
    s = settings(0.125);
    s.cull_siblings = -1;
    EXPECT_EQ(refused(s), "cull_siblings");
    s = settings(0.125);
    s.count_untested = -1;
    EXPECT_EQ(refused(s), "count_untested");
    s = settings(0.125);
    s.band_voxels = 0.0;
    EXPECT_EQ(refused(s), "band_voxels");
    s = settings(0.125);
    s.levels = 2;  // too few to cover the geometry
    EXPECT_EQ(refused(s), "levels");
}

}  // namespace
}  // namespace sdfbrick
