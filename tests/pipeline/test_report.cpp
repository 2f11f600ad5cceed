// The per-device report figures (pipeline/report.h): their JSON and their text say the same thing.
#include <string>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "pipeline/report.h"

namespace sdfbrick {
namespace {

pipeline::ConstructionFigures one_geometry() {
    pipeline::GeometryFigures g;
    g.name = "blob";
    g.leaf_size = 0.125f;
    g.levels = 1;
    g.bricks = 100;
    g.edit_evaluations = 4000;
    g.level_table = {construct::LevelReport{0, 0.125, 100, 300, 5, 0.1, 0.2, 0.3, 0.4}};
    g.memory = {{"brick pool", 2048}};
    pipeline::ConstructionFigures c;
    c.bricks = g.bricks;
    c.edit_evaluations = g.edit_evaluations;
    c.leaf_edit_entries = 300;
    c.edits_per_leaf_max = 5;
    c.memory = g.memory;
    c.geometries = {g};
    return c;
}

TEST(PipelineReport, BuildFiguresJsonAndTextAgree) {
    pipeline::BuildFigures f;
    f.construction = one_geometry();
    f.stages = {measure::StageStats{measure::Stage::evaluate, 1, measure::spread_of({1.5})}};
    f.total_ms = measure::spread_of({2.0});
    f.captures = 1;
    f.digest = "0123456789abcdef";
    f.list_digest = "fedcba9876543210";
    const nlohmann::json j = pipeline::to_json(f);
    const std::string text = pipeline::to_text(f, false);

    EXPECT_EQ(j["bricks"], 100);
    EXPECT_NE(text.find("geometry blob: 100 leaf bricks of 0.125"), std::string::npos) << text;
    EXPECT_EQ(j["digest"], f.digest);
    EXPECT_EQ(j["list_digest"], f.list_digest);
    EXPECT_NE(text.find("digest 0123456789abcdef (edit lists fedcba9876543210)"), std::string::npos) << text;
    EXPECT_EQ(j["stages"][0]["name"], "evaluate");
    EXPECT_EQ(j["stages"][0]["device_ms"], 1.5);
    EXPECT_EQ(j["device_ms"], 2.0);
    EXPECT_NE(text.find("stages (device ms): evaluate 1.500; total 2.000 ms"), std::string::npos) << text;
    EXPECT_EQ(j["memory"]["brick pool"], 2048);
    EXPECT_NE(text.find("memory: brick pool 2.0 KiB"), std::string::npos) << text;
    EXPECT_EQ(j["edits_per_leaf"]["mean"], 3.0);
    EXPECT_EQ(j["edits_per_leaf"]["max"], 5);
    EXPECT_EQ(j["bricks_per_second"], 100 / 2e-3);
    EXPECT_EQ(j["captures"]["repeat"], 1);
    EXPECT_EQ(j["geometries"][0]["levels"][0]["edit_entries"], 300);
    EXPECT_NE(text.find("       3.00     5"), std::string::npos) << "edits per brick and max in the level table:\n" << text;
}

TEST(PipelineReport, RenderFiguresJsonAndTextAgree) {
    pipeline::RenderFigures f;
    f.construction = one_geometry();
    f.bvh.nodes = 199;
    f.bvh.leaves = 90;
    f.bvh.memory = {{"bvh nodes", 6368}};
    f.combined_pool_bytes = 4096;
    f.build_ms = measure::spread_of({3.0, 5.0});
    f.trace_ms = measure::spread_of({2.0, 2.0});
    f.captures = 2;
    f.width = 64;
    f.height = 32;
    f.group_x = 16;
    f.group_y = 8;
    f.work = {4.3, 12.5};
    const nlohmann::json j = pipeline::to_json(f);
    const std::string text = pipeline::to_text(f, false);

    EXPECT_EQ(j["bricks"], 100);
    EXPECT_EQ(j["bvh"]["nodes"], 199);
    EXPECT_EQ(j["bvh"]["leaves"], 90);
    EXPECT_EQ(j["build_ms"]["median_ms"], 4.0);
    EXPECT_NE(text.find("build 4.000 ms (100 bricks), bvh 0.000 ms (199 nodes over 90 bricks), trace 2.000 ms"),
              std::string::npos)
        << text;
    EXPECT_EQ(j["rays_per_second"], 64.0 * 32 / 2e-3);
    EXPECT_NE(text.find(fmt::format("({:.3g} rays/s", 64.0 * 32 / 2e-3)), std::string::npos) << text;
    EXPECT_EQ(j["work_per_pixel"]["node_visits"], 4.3);
    EXPECT_NE(text.find("4.3 node visits and 12.5 brick steps per ray"), std::string::npos) << text;
    EXPECT_EQ(j["memory"]["combined pool"], 4096);
    EXPECT_EQ(j["memory"]["brick pool"], 2048);
    EXPECT_EQ(j["memory"]["bvh nodes"], 6368);
    EXPECT_EQ(j["captures"]["repeat"], 2);
    EXPECT_EQ(j["trace_group"], nlohmann::json::array({16, 8}));
}

}  // namespace
}  // namespace sdfbrick
