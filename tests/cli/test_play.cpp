// `sdfbrick play`: every frame equals a render of the scene at its time bit for bit (whole and split,
// a static geometry kept from frame to frame beside an animated one), the frames written, the
// report's figures, and bad input refused with one line and nothing written.
#include <filesystem>
#include <string>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli/cli_run.h"

namespace sdfbrick::test {
namespace {

// A static ground slab (no animation: built once, kept) and a geometry of two falling, spinning
// blended spheres and a capsule (rebuilt every frame).
constexpr const char* kMixedScene = R"({
  "name": "mixed", "time": 0.25,
  "camera": {"orbit": {"target": [0, 0.2, 0], "distance": 4.0, "yaw_deg": 30, "pitch_deg": 25}},
  "geometries": [
    {"name": "ground", "edits": [{"primitive": "box", "half_extents": [1.5, 0.1, 1.5], "position": [0, -0.6, 0]}]},
    {"name": "drops", "edits": [
      {"primitive": "sphere", "radius": 0.3, "position": [-0.4, 0.5, 0],
       "animation": {"velocity": [0, -0.8, 0], "wrap_y": [-0.5, 1.0]}},
      {"primitive": "sphere", "radius": 0.25, "position": [0.3, 0.2, 0.1], "blend": 0.15,
       "animation": {"velocity": [0.2, -0.5, 0], "wrap_y": [-0.5, 1.0]}},
      {"primitive": "capsule", "half_length": 0.3, "radius": 0.08, "position": [0, 0.1, -0.3], "rotation": [0, 0, 0.7071067811865476, 0.7071067811865476],
       "op": "subtract", "blend": 0.05, "animation": {"spin_axis": [0, 1, 0], "spin_rate": 2.0}}]}],
  "objects": [{"geometry": "ground"}, {"geometry": "drops"}]
})";

const std::string kImage = "--brick-size 0.0625 --width 64 --height 48";

std::filesystem::path mixed_scene(const std::filesystem::path& dir) {
    write_text(dir / "mixed.json", kMixedScene);
    return dir / "mixed.json";
}

std::string render_digest(const std::filesystem::path& scene, double t, const std::filesystem::path& dir) {
    const CliRun r = sdfbrick(fmt::format("render {} {} --time {:.17g} --out {} --json {}", scene.string(), kImage, t,
                                          (dir / "r.ppm").string(), (dir / "r.json").string()),
                              device_env());
    EXPECT_EQ(r.status, 0) << r.err;
    return nlohmann::json::parse(read_file(dir / "r.json")).at("digest").get<std::string>();
}

nlohmann::json play(const std::string& args, const std::filesystem::path& json, const std::string& env = device_env()) {
    const CliRun r = sdfbrick(fmt::format("play {} --json {}", args, json.string()), env);
    EXPECT_EQ(r.status, 0) << r.err;
    return nlohmann::json::parse(read_file(json));
}

TEST(CliPlay, EveryFrameEqualsARenderAtItsTime) {
    const auto dir = temp_dir("cli_play_frames");
    const auto scene = mixed_scene(dir);
    const nlohmann::json j = play(fmt::format("{} {} --frames 4 --fps 8 --digests --out {}", scene.string(), kImage,
                                              (dir / "f%03d.ppm").string()),
                                  dir / "play.json");
    ASSERT_EQ(j.at("frames").size(), 4u);
    for (const auto& f : j.at("frames")) {
        const int i = f.at("frame").get<int>();
        EXPECT_DOUBLE_EQ(f.at("time").get<double>(), 0.25 + i / 8.0);
        // The ground is built in the first frame only; the animated geometry every frame.
        EXPECT_EQ(f.at("geometries_rebuilt").get<int>(), i == 0 ? 2 : 1);
        EXPECT_GT(f.at("bricks").get<int>(), 0);
        EXPECT_GT(f.at("device_ms").at("construct").get<double>(), 0.0);
        EXPECT_GT(f.at("wall_ms").get<double>(), 0.0);
        EXPECT_TRUE(std::filesystem::is_regular_file(dir / fmt::format("f{:03d}.ppm", i)));
        if (i == 0 || i == 3)  // the first frame and one that kept the ground
            EXPECT_EQ(f.at("digest").get<std::string>(), render_digest(scene, f.at("time").get<double>(), dir)) << i;
    }
    const auto& s = j.at("summary");
    EXPECT_EQ(s.at("frames").get<int>(), 4);
    EXPECT_EQ(s.at("skipped").get<int>(), 1);
    EXPECT_DOUBLE_EQ(s.at("budget_ms").get<double>(), 125.0);
    EXPECT_LE(s.at("wall_ms").at("p50").get<double>(), s.at("wall_ms").at("p99").get<double>());
    EXPECT_EQ(j.at("frames_out").get<std::string>(), (dir / "f%03d.ppm").string());
}

TEST(CliPlay, SplitFramesEqualWholeFrames) {
    const auto dir = temp_dir("cli_play_split");
    const auto scene = mixed_scene(dir);
    const std::string args = fmt::format("{} {} --frames 2 --dt 0.1 --from 1 --digests", scene.string(), kImage);
    const nlohmann::json whole = play(args, dir / "whole.json");
    const nlohmann::json split = play(args + " --devices split", dir / "split.json");
    EXPECT_EQ(split.at("placement").get<std::string>(), "split");
    for (std::size_t i = 0; i < 2; ++i) {
        EXPECT_EQ(split.at("frames")[i].at("digest"), whole.at("frames")[i].at("digest")) << i;
        EXPECT_EQ(split.at("frames")[i].at("brick_digest"), whole.at("frames")[i].at("brick_digest")) << i;
    }
    EXPECT_TRUE(split.at("fps").is_null());
}

TEST(CliPlay, BadInputIsOneLineAndWritesNothing) {
    const auto dir = temp_dir("cli_play_bad");
    const auto scene = mixed_scene(dir).string();
    const auto json = (dir / "r.json").string();
    write_text(dir / "log.jsonl", "{\"frame\": 0, \"op\": \"remove\", \"geometry\": \"drops\", \"index\": 0}\n"
                                  "{\"frame\": 1, \"op\": \"remove\", \"geometry\": \"drops\", \"index\": 9}\n");
    const std::string log = (dir / "log.jsonl").string();
    write_text(dir / "late.jsonl", "{\"frame\": 3, \"op\": \"remove\", \"geometry\": \"drops\", \"index\": 0}\n");
    const std::string late = (dir / "late.jsonl").string();
    const std::pair<std::string, std::string> cases[] = {
        {"--edits " + log, "log.jsonl:2: /index: no edit 9 in geometry \"drops\" (it has 2 there)"},
        {"--edits " + (dir / "none.jsonl").string(), "none.jsonl"},
        {"--work all", "--work must be construct, bvh or trace"},
        {"--work bvh --out " + (dir / "f%d.ppm").string(), "--out needs --work trace"},
        {"--fps 0", "--fps must be > 0"},
        {"--dt -1", "--dt must be > 0"},
        {"--fps 30 --dt 0.1", "exclude each other"},
        {"--frames 0", "--frames must lie in 1 .. 100000"},
        {"--frames 100001", "--frames must lie in 1 .. 100000"},
        {"--edits " + late, "late.jsonl:1: /frame: frame 3 is not played (--frames 2)"},
        {"--out " + (dir / "frame.ppm").string(), "one frame field"},
        {"--out " + (dir / "f%d-%d.ppm").string(), "one frame field"},
        {"--out " + (dir / "f%x.ppm").string(), "one frame field"},
        {"--out " + (dir / "missing/f%d.ppm").string(), "missing"},
        {"--mode glow", "--mode must be"},
    };
    for (const auto& [flags, message] : cases) {
        const std::string frames = flags.find("--frames") == std::string::npos ? "--frames 2" : "";
        const CliRun r = sdfbrick(fmt::format("play {} {} {} --json {}", scene, frames, flags, json), device_env());
        EXPECT_EQ(r.status, 2) << flags << ": " << r.err;
        EXPECT_TRUE(one_clean_line(r)) << flags;
        EXPECT_NE(r.err.find(message), std::string::npos) << flags << ": " << r.err;
        EXPECT_FALSE(std::filesystem::exists(json)) << flags;
    }
}

}  // namespace
}  // namespace sdfbrick::test
