// The run loop: warm-up and captures, one launch recorder per pass, digests, and the trace-only loop.
#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <stdexcept>
#include <string>

#include "core/hash.h"
#include "pipeline/run.h"
#include "scene/scene_json.h"
#include "test_support.h"

namespace sdfbrick {
namespace {

Scene spheres() {
    const Scene file = load_scene(std::string(SDFBRICK_SOURCE_DIR) + "/scenes/spheres.json");
    return scene_at(file, file.time);
}

pipeline::Lane& runner() {
    static pipeline::Lane r(test::device());
    return r;
}

pipeline::RunSpec spec(pipeline::Work work, int warmup, int repeat) {
    pipeline::RunSpec s;
    s.work = work;
    s.build.leaf_size = 0.25;
    s.trace.width = 64;
    s.trace.height = 48;
    s.warmup = warmup;
    s.repeat = repeat;
    return s;
}

std::set<std::string> stages_of(const measure::Capture& c) {
    std::set<std::string> out;
    for (const measure::Launch& l : c) out.insert(std::string(to_string(l.stage)));
    return out;
}

TEST(PipelineRun, CapturesFollowTheWarmUpAndAreIdentical) {
    pipeline::RunSpec s = spec(pipeline::Work::trace, 1, 3);
    s.brick_digests = true;
    const pipeline::Run run = runner().run(spheres(), s);
    ASSERT_EQ(run.captures.size(), 3u);
    EXPECT_TRUE(run.identical);
    EXPECT_EQ(run.build_ms.samples.size(), 3u);
    EXPECT_EQ(run.trace_ms.samples.size(), 3u);
    EXPECT_FALSE(run.brick_digest.empty());
    EXPECT_FALSE(run.trace_digest.empty());
    ASSERT_TRUE(run.trace.has_value());
    EXPECT_EQ(run.trace_digest, pipeline::buffer_digest(run.trace->buffer));
    // One recorder per pass: every capture holds construction, BVH and trace, and only its own launches.
    for (const measure::Capture& c : run.captures) {
        const std::set<std::string> st = stages_of(c);
        for (const char* name : {"count", "scan", "subdivide", "evaluate", "aabb", "bvh", "tlas", "trace"})
            EXPECT_TRUE(st.count(name)) << name;
        EXPECT_EQ(c.size(), run.captures.front().size());
    }
    double total = 0.0;
    for (const measure::Launch& l : run.captures.back()) total += l.device_ms;
    EXPECT_DOUBLE_EQ(run.total_ms.samples.back(), total);
}

TEST(PipelineRun, WorkStopsWhereAsked) {
    const pipeline::Run built = runner().run(spheres(), spec(pipeline::Work::construct, 0, 1));
    const std::set<std::string> st = stages_of(built.captures.front());
    EXPECT_TRUE(st.count("evaluate"));
    EXPECT_FALSE(st.count("bvh"));
    EXPECT_FALSE(st.count("trace"));
    EXPECT_FALSE(built.trace.has_value());
    EXPECT_TRUE(built.trace_digest.empty());
    EXPECT_TRUE(built.brick_digest.empty());  // not asked for
    const pipeline::Run with_bvh = runner().run(spheres(), spec(pipeline::Work::bvh, 0, 1));
    EXPECT_TRUE(stages_of(with_bvh.captures.front()).count("tlas"));
    EXPECT_FALSE(stages_of(with_bvh.captures.front()).count("trace"));
    EXPECT_EQ(with_bvh.bricks.bricks, built.bricks.bricks);
}

TEST(PipelineRun, TraceOnlyLoopMatchesTheFullPass) {
    const Scene scene = spheres();
    const pipeline::Run full = runner().run(scene, spec(pipeline::Work::trace, 0, 1));
    const pipeline::Run built = runner().run(scene, spec(pipeline::Work::bvh, 0, 1));
    const pipeline::Run traced = runner().trace(scene, built.bricks, spec(pipeline::Work::trace, 1, 2));
    ASSERT_EQ(traced.captures.size(), 2u);
    EXPECT_EQ(stages_of(traced.captures.front()), (std::set<std::string>{"trace"}));
    EXPECT_TRUE(traced.identical);
    EXPECT_EQ(traced.trace_digest, full.trace_digest);
}

Scene scene_named(const char* name) {
    const Scene file = load_scene(std::string(SDFBRICK_SOURCE_DIR) + "/scenes/" + name + ".json");
    return scene_at(file, file.time);
}

// A device whose pool holds another scene's memory (stale bytes in every reused buffer) gives the
// bits of a newly opened one, in every capture; the later passes do reuse memory.
TEST(PipelineRun, ReusedMemoryGivesTheBitsOfAFreshDevice) {
    const Scene rain = scene_named("rain");
    pipeline::RunSpec s = spec(pipeline::Work::trace, 0, 1);
    s.brick_digests = true;
    s.trace.shade = true;
    ocl::DeviceSet fresh = test::open_test_devices();
    pipeline::Lane first(fresh[0]);
    const pipeline::Run clean = first.run(rain, s);
    runner().run(spheres(), s);  // leaves its buffers in the shared device's pool
    const std::size_t reused = test::device().memory_pool()->reused();
    s.repeat = 3;
    const pipeline::Run again = runner().run(rain, s);
    EXPECT_GT(test::device().memory_pool()->reused(), reused);
    EXPECT_TRUE(again.identical);
    EXPECT_EQ(again.brick_digest, clean.brick_digest);
    EXPECT_EQ(again.list_digest, clean.list_digest);
    EXPECT_EQ(again.trace_digest, clean.trace_digest);
    ASSERT_TRUE(again.trace && clean.trace);
    EXPECT_EQ(again.trace->colour.pixels, clean.trace->colour.pixels);
}

// What the device reduces and digests equals what the host computes from the arrays read back.
TEST(PipelineRun, DeviceCountersAndDigestsEqualTheHosts) {
    const Scene scene = scene_named("rain");
    pipeline::RunSpec s = spec(pipeline::Work::trace, 0, 1);
    s.brick_digests = true;
    const pipeline::Run run = runner().run(scene, s);
    ASSERT_TRUE(run.trace.has_value());
    const render::WorkCounts host = render::work_counts(run.trace->buffer);
    const render::WorkCounts device = run.trace->work.per_pixel();
    EXPECT_EQ(device.node_visits, host.node_visits);
    EXPECT_EQ(device.brick_steps, host.brick_steps);
    EXPECT_EQ(device.capped_rays, host.capped_rays);
    Fnv1a64 bricks, lists;
    for (const construct::GeometryBuild& b : run.bricks.builds) {
        bricks.add_part(construct::output_digest(b, s.build));
        lists.add_part(construct::list_digest(b));
        const std::vector<SdfBrick> leaves = b.leaves->read();
        std::uint64_t entries = 0;
        std::uint32_t longest = 0;
        for (const SdfBrick& r : leaves) {
            entries += r.edit_count;
            longest = std::max(longest, r.edit_count);
        }
        ASSERT_FALSE(b.level_reports.empty());
        EXPECT_EQ(b.level_reports.back().max_edits, longest);
        EXPECT_EQ(b.level_reports.back().edit_entries, entries);
        EXPECT_EQ(b.edits_per_leaf_max, longest);
    }
    EXPECT_EQ(run.brick_digest, bricks.hex());
    EXPECT_EQ(run.list_digest, lists.hex());
}

// Without RunSpec::image nothing of the image comes back, and its digest is the same.
TEST(PipelineRun, ImageStaysOnTheDeviceUnlessAsked) {
    pipeline::RunSpec s = spec(pipeline::Work::trace, 0, 2);
    const pipeline::Run with = runner().run(spheres(), s);
    s.image = false;
    const pipeline::Run without = runner().run(spheres(), s);
    ASSERT_TRUE(with.trace && without.trace);
    EXPECT_EQ(with.trace->buffer.pixels(), 64u * 48u);
    EXPECT_EQ(without.trace->buffer.pixels(), 0u);
    EXPECT_EQ(without.trace_digest, with.trace_digest);
    EXPECT_EQ(without.trace->work.node_visits, with.trace->work.node_visits);
    EXPECT_EQ(without.wall_ms.samples.size(), 2u);
}

TEST(PipelineRun, RefusesBadCounts) {
    EXPECT_THROW(runner().run(spheres(), spec(pipeline::Work::construct, -1, 1)), std::invalid_argument);
    EXPECT_THROW(runner().run(spheres(), spec(pipeline::Work::construct, 0, 0)), std::invalid_argument);
}

}  // namespace
}  // namespace sdfbrick
