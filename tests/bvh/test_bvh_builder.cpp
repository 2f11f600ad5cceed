// The brick BVH: every brick reachable once, boxes nested, rebuilds valid and bit-identical, and the
// tree checker itself.
#include <gtest/gtest.h>

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "bvh/bvh_builder.h"
#include "construct/brick_builder.h"
#include "core/hash.h"
#include "scene/scene_json.h"
#include "test_support.h"

namespace sdfbrick {
namespace {

using construct::BuildSettings;

construct::BrickBuilder& brick_builder() {
    static construct::BrickBuilder b(test::device());
    return b;
}

bvh::BvhBuilder& bvh_builder() {
    static bvh::BvhBuilder b(test::device());
    return b;
}

Scene shipped(const char* name) {
    const Scene s = load_scene(std::string(SDFBRICK_SOURCE_DIR) + "/scenes/" + name + ".json");
    return scene_at(s, s.time);
}

BuildSettings settings(double leaf) {
    BuildSettings s;
    s.leaf_size = leaf;
    return s;
}

// Every geometry's bricks and the scene's BVH over them.
struct Built {
    BuildSettings settings;
    std::vector<construct::GeometryBuild> builds;
    bvh::SceneBvh bvh;
    // Geometry g's bricks that can hold a hit, found on the host.
    std::vector<std::uint8_t> in_tree(std::size_t g) const {
        return bvh::hit_bricks(builds[g].pool->read(), settings, builds[g]);
    }
};

Built build(const Scene& scene, const BuildSettings& s) {
    measure::Scheduler scheduler(test::device());
    Built out{s, {}, {}};
    for (const Geometry& g : scene.geometries) out.builds.push_back(brick_builder().build(g, s, scheduler));
    out.bvh = bvh_builder().build(scene, out.builds, s, scheduler);
    return out;
}

// Every brick that can hold a hit is in the tree once and no other is; checked for each format,
// whose thresholds differ in stored units.
TEST(Bvh, EveryHitBrickReachableAndBoxesNested) {
    for (const auto& [branching, format] : {std::pair{4, construct::BrickFormat::int8}, {2, construct::BrickFormat::int8},
                                            {4, construct::BrickFormat::int16}, {4, construct::BrickFormat::float32}}) {
        const Scene scene = shipped("spheres");
        BuildSettings s = settings(0.125);
        s.branching = branching;
        s.format = format;
        const Built b = build(scene, s);
        const std::string where = fmt::format("branching {}, format {}", branching, construct::to_string(format));
        ASSERT_EQ(b.builds.size(), 1u);
        const std::vector<SdfBvhWideNode> nodes = b.bvh.nodes->read();
        const std::vector<SdfBounds> boxes = b.builds[0].aabbs->read();
        const std::vector<std::uint8_t> in_tree = b.in_tree(0);
        const auto kept = static_cast<std::size_t>(std::count(in_tree.begin(), in_tree.end(), 1));
        ASSERT_GT(boxes.size(), 100u);
        // Bricks in the band outside the surface are left out, most bricks stay.
        EXPECT_LT(kept, boxes.size()) << where;
        EXPECT_GT(kept * 2, boxes.size()) << where;
        EXPECT_EQ(b.bvh.tree_leaves[0], kept) << where;
        EXPECT_EQ(b.bvh.node_count, nodes.size());
        // the binary tree's nodes at even depth: between a third and two thirds of its n - 1 when balanced
        EXPECT_LT(nodes.size() * 3, (kept - 1) * 2 + 3);
        EXPECT_GT(nodes.size() * 3, kept - 4);
        EXPECT_EQ(bvh::check_tree(nodes, b.bvh.roots[0], boxes, in_tree), "") << where;
        // The root box is the union of the tree's bricks.
        for (int a = 0; a < 3; ++a) {
            float lo = INFINITY, hi = -INFINITY;
            for (std::size_t i = 0; i < boxes.size(); ++i)
                if (in_tree[i]) lo = std::min(lo, boxes[i].lo[a]), hi = std::max(hi, boxes[i].hi[a]);
            EXPECT_EQ(b.bvh.geometry_boxes[0].lo[a], lo);
            EXPECT_EQ(b.bvh.geometry_boxes[0].hi[a], hi);
        }
    }
}

// The refit's work-items hand boxes to each other through global memory: a larger tree, rebuilt
// several times, must stay valid and bit-identical (this caught a visibility race on a GPU).
TEST(Bvh, RebuildsAreValidAndIdentical) {
    const Scene scene = shipped("drops");
    const Built b = build(scene, settings(0.25));
    const std::vector<SdfBounds> boxes = b.builds[0].aabbs->read();
    const std::vector<std::uint8_t> in_tree = b.in_tree(0);
    std::string first;
    for (int i = 0; i < 8; ++i) {
        const bvh::SceneBvh t = bvh_builder().build(scene, b.builds, b.settings, test::recorder());
        const std::vector<SdfBvhWideNode> nodes = t.nodes->read();
        ASSERT_EQ(bvh::check_tree(nodes, t.roots[0], boxes, in_tree), "") << "rebuild " << i;
        const std::string d = Fnv1a64().add_values(std::span<const SdfBvhWideNode>(nodes)).hex();
        if (i == 0) first = d;
        ASSERT_EQ(d, first) << "rebuild " << i;
    }
}

// Work-items that share a brick's test (GPUs: several, CPUs: one) give the same tree.
TEST(Bvh, SharedHitTestsGiveTheSameTree) {
    const Scene scene = shipped("drops");
    const Built b = build(scene, settings(0.25));
    const std::string expected = Fnv1a64().add_values(std::span<const SdfBvhWideNode>(b.bvh.nodes->read())).hex();
    for (const std::size_t parts : {1, 4, 16, 64}) {
        bvh::BvhBuilder shared(test::device(), parts);
        const bvh::SceneBvh t = shared.build(scene, b.builds, b.settings, test::recorder());
        EXPECT_EQ(Fnv1a64().add_values(std::span<const SdfBvhWideNode>(t.nodes->read())).hex(), expected) << parts;
        EXPECT_EQ(t.tree_leaves, b.bvh.tree_leaves) << parts;
    }
    EXPECT_THROW(bvh::BvhBuilder(test::device(), 3), std::invalid_argument);
}

// A wide node with three leaf slots and an unused one, then three ways to break it.
TEST(Bvh, CheckTreeFindsBrokenTrees) {
    const std::vector<SdfBounds> boxes{{{0, 0, 0}, {1, 1, 1}}, {{1, 0, 0}, {2, 1, 1}}, {{5, 5, 5}, {6, 6, 6}}};
    SdfBvhWideNode w{};
    for (int k = 0; k < 3; ++k) {
        w.lo_x[k] = boxes[k].lo[0], w.lo_y[k] = boxes[k].lo[1], w.lo_z[k] = boxes[k].lo[2];
        w.hi_x[k] = boxes[k].hi[0], w.hi_y[k] = boxes[k].hi[1], w.hi_z[k] = boxes[k].hi[2];
        w.child[k] = ~k;
    }
    w.child[3] = SDF_WIDE_EMPTY;
    const std::vector<std::uint8_t> all{1, 1, 1}, first_two{1, 1, 0};
    EXPECT_EQ(bvh::check_tree(std::vector<SdfBvhWideNode>{w}, 0, boxes, all), "");
    SdfBvhWideNode missing = w;
    missing.child[2] = SDF_WIDE_EMPTY;
    EXPECT_NE(bvh::check_tree(std::vector<SdfBvhWideNode>{missing}, 0, boxes, all), "");
    EXPECT_EQ(bvh::check_tree(std::vector<SdfBvhWideNode>{missing}, 0, boxes, first_two), "");
    EXPECT_NE(bvh::check_tree(std::vector<SdfBvhWideNode>{w}, 0, boxes, first_two), "");  // a leaf out of the tree
    SdfBvhWideNode wrong_box = w;
    wrong_box.hi_y[1] = 1.5f;
    EXPECT_NE(bvh::check_tree(std::vector<SdfBvhWideNode>{wrong_box}, 0, boxes, all), "");
    // an internal slot whose box does not contain the node it names
    SdfBvhWideNode top = w;
    top.child[2] = 1;
    top.hi_x[2] = 5.5f;
    SdfBvhWideNode inner{};
    inner.lo_x[0] = 5, inner.lo_y[0] = 5, inner.lo_z[0] = 5, inner.hi_x[0] = 6, inner.hi_y[0] = 6, inner.hi_z[0] = 6;
    inner.child[0] = ~2;
    inner.child[1] = inner.child[2] = inner.child[3] = SDF_WIDE_EMPTY;
    EXPECT_NE(bvh::check_tree(std::vector<SdfBvhWideNode>{top, inner}, 0, boxes, all), "");
    top.hi_x[2] = 6.0f;
    EXPECT_EQ(bvh::check_tree(std::vector<SdfBvhWideNode>{top, inner}, 0, boxes, all), "");
}

}  // namespace
}  // namespace sdfbrick
