// The run loop: warm-up and captures, one launch recorder per pass, digests, and the trace-only loop.
#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <stdexcept>
#include <string>

#include "pipeline/run.h"
#include "scene/scene_json.h"
#include "test_support.h"

namespace sdfbrick {
namespace {

Scene spheres() {
    const Scene file = load_scene(std::string(SDFBRICK_SOURCE_DIR) + "/scenes/spheres.json");
    return scene_at(file, file.time);
}

pipeline::Runner& runner() {
    static pipeline::Runner r(test::device());
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

TEST(PipelineRun, RefusesBadCounts) {
    EXPECT_THROW(runner().run(spheres(), spec(pipeline::Work::construct, -1, 1)), std::invalid_argument);
    EXPECT_THROW(runner().run(spheres(), spec(pipeline::Work::construct, 0, 0)), std::invalid_argument);
}

}  // namespace
}  // namespace sdfbrick
