// The executor: placements over lanes give the same bits, lanes keep their state from run to run,
// settings are asked once per lane, and trace passes run through an earlier execution's bricks.
#include <gtest/gtest.h>

#include <string>

#include "pipeline/executor.h"
#include "pipeline/report.h"
#include "scene/scene_json.h"
#include "test_support.h"

namespace sdfbrick {
namespace {

Scene scene(const char* name) {
    const Scene file = load_scene(std::string(SDFBRICK_SOURCE_DIR) + "/scenes/" + name + ".json");
    return scene_at(file, file.time);
}

pipeline::Executor& executor() {
    static pipeline::Executor e(test::device());
    return e;
}

pipeline::Job job(pipeline::Work work, double tolerance = 0.0, int* asked = nullptr) {
    pipeline::Job j;
    j.work = work;
    j.settings = [=](const ocl::DeviceInfo&) {
        if (asked) ++*asked;
        pipeline::LaneSettings s;
        s.build.leaf_size = tolerance > 0.0 ? 0.0625 : 0.25;
        s.build.tolerance = tolerance;
        s.trace.width = 64;
        s.trace.height = 48;
        return s;
    };
    return j;
}

// A split over the one device (the whole stage on one lane: nothing merged) gives the whole
// placement's bricks, edit lists and image, uniform and adaptive; its report has the same keys.
TEST(PipelineExecutor, SplitOnOneDeviceEqualsWhole) {
    for (double tolerance : {0.0, 0.004}) {
        const Scene s = scene(tolerance > 0.0 ? "thin" : "spheres");
        int asked = 0;
        pipeline::Job j = job(pipeline::Work::trace, tolerance, &asked);
        j.repeat = 2;
        const pipeline::Execution whole = executor().run(s, j);
        const pipeline::Execution split = executor().run(s, j, pipeline::Placement::split);
        EXPECT_EQ(asked, 2) << "settings are asked once per lane and run";
        ASSERT_TRUE(split.split.has_value());
        EXPECT_FALSE(whole.split.has_value());
        EXPECT_EQ(split.job().brick_digest, whole.job().brick_digest) << tolerance;
        EXPECT_EQ(split.job().list_digest, whole.job().list_digest) << tolerance;
        EXPECT_EQ(split.job().trace_digest, whole.job().trace_digest) << tolerance;
        EXPECT_TRUE(split.job().identical);
        ASSERT_TRUE(split.construct_split && split.trace_split);
        EXPECT_EQ(split.construct_split->devices.at(0).done, 1.0);
        // The lane's own launches are the job's: one lane did everything.
        ASSERT_EQ(split.lanes.size(), 1u);
        EXPECT_EQ(split.lanes[0].run.captures.size(), 2u);
        EXPECT_EQ(split.lanes[0].run.captures.back().size(), split.job().captures.back().size());
        const nlohmann::json a = pipeline::to_json(pipeline::render_figures(whole));
        const nlohmann::json b = pipeline::to_json(pipeline::render_figures(split));
        for (const auto& [key, value] : a.items()) EXPECT_TRUE(b.contains(key)) << key;
        EXPECT_EQ(pipeline::placement_json(split)["placement"], "split");
        EXPECT_EQ(pipeline::placement_json(whole)["placement"], "whole");
    }
}

// A lane keeps its builders and tracer from run to run; a second run gives the same bits.
TEST(PipelineExecutor, LanesKeepTheirStateAcrossRuns) {
    const Scene s = scene("spheres");
    const pipeline::Execution first = executor().run(s, job(pipeline::Work::trace));
    const pipeline::Lane* lane = &executor().lane(0);
    const construct::BrickBuilder* builder = &executor().lane(0).builder();
    const pipeline::Execution second = executor().run(s, job(pipeline::Work::trace));
    EXPECT_EQ(&executor().lane(0), lane);
    EXPECT_EQ(&executor().lane(0).builder(), builder);
    EXPECT_EQ(second.job().trace_digest, first.job().trace_digest);
}

// BVH-only work splits too (the home lane makes the BVH), and trace passes through an earlier
// execution's bricks give the image of a run that builds and traces.
TEST(PipelineExecutor, TraceThroughAnEarlierBuild) {
    const Scene s = scene("spheres");
    const pipeline::Execution traced = executor().run(s, job(pipeline::Work::trace));
    for (pipeline::Placement p : {pipeline::Placement::whole, pipeline::Placement::split}) {
        const pipeline::Execution built = executor().run(s, job(pipeline::Work::bvh), p);
        EXPECT_GT(built.job().bricks.bvh.node_count, 0u) << to_string(p);
        EXPECT_FALSE(built.job().trace.has_value());
        const pipeline::Execution again = executor().trace(s, built, job(pipeline::Work::trace));
        ASSERT_EQ(again.lanes.size(), 1u);
        EXPECT_EQ(again.job().trace_digest, traced.job().trace_digest) << to_string(p);
    }
}

// The reference tracer alone (no brick work) runs on the home lane.
TEST(PipelineExecutor, ReferenceAlone) {
    const Scene s = scene("spheres");
    pipeline::Job j = job(pipeline::Work::trace);
    j.bricks = false;
    j.reference = true;
    const pipeline::Execution e = executor().run(s, j);
    ASSERT_TRUE(e.home_lane().reference.has_value());
    EXPECT_EQ(e.home_lane().reference->image.width, 64);
    EXPECT_TRUE(e.job().captures.empty());
}

TEST(PipelineExecutor, RefusesAJobWithoutSettings) {
    pipeline::Job j;
    EXPECT_THROW(executor().run(scene("spheres"), j), std::invalid_argument);
    EXPECT_THROW(pipeline::Executor(std::vector<ocl::Device*>{}), std::invalid_argument);
}

}  // namespace
}  // namespace sdfbrick
