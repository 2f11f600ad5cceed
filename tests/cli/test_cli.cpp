// The command line as a user meets it: exit status, one-line errors, no partial output files,
// the shipped scenes, and the generator reproducing them byte for byte.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <string>
#include <sys/wait.h>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli/cli_run.h"
#include "core/files.h"
#include "scene/generate.h"
#include "sdf_types.h"
#include "test_support.h"
#include "tune/kernels.h"
#include "tune/tuning_db.h"

namespace sdfbrick {
namespace {

namespace fs = std::filesystem;

using test::CliRun;
using test::scene_path;
using test::sdfbrick;
using test::test_device_spec;

TEST(Cli, DevicesListsAtLeastOneDevice) {
    const CliRun r = sdfbrick("devices --json");
    ASSERT_EQ(r.status, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    ASSERT_TRUE(j.is_array());
    ASSERT_FALSE(j.empty());
    EXPECT_TRUE(j[0].contains("name"));
    EXPECT_TRUE(j[0].contains("compute_units"));
}

TEST(Cli, SceneInfoReportsEditCounts) {
    const std::pair<const char*, int> expected[] = {{"spheres", 2}, {"drops", 1024}, {"cubes", 216}, {"rain", 512}, {"fractal", 64}};
    for (const auto& [name, edits] : expected) {
        const CliRun r = sdfbrick("scene info " + scene_path(name) + " --json");
        ASSERT_EQ(r.status, 0) << name << ": " << r.err;
        const auto j = nlohmann::json::parse(r.out);
        EXPECT_EQ(j["geometries"][0]["edits"].template get<int>(), edits) << name;
    }
}

TEST(Cli, GeneratorReproducesShippedScenes) {
    for (const std::string_view view : generated_scene_names()) {
        const std::string name(view);
        const CliRun r = sdfbrick("scene generate " + name);
        ASSERT_EQ(r.status, 0) << r.err;
        EXPECT_EQ(r.out, read_file(scene_path(name))) << name << ": scenes/" << name
                                                      << ".json differs from `sdfbrick scene generate " << name << "`";
    }
}

TEST(Cli, EvalWritesPictureAndReport) {
    const fs::path dir = test::temp_dir("cli_eval");
    const CliRun r = sdfbrick("eval " + scene_path("spheres") + " --size 64 -o " + (dir / "s.ppm").string() + " --json " +
                           (dir / "r.json").string(), "SDFBRICK_DEVICE=" + test_device_spec());
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_TRUE(fs::exists(dir / "s.ppm"));
    const auto j = nlohmann::json::parse(read_file(dir / "r.json"));
    EXPECT_EQ(j["scene"]["edits"].get<int>(), 2);
    EXPECT_EQ(j["devices"][0]["accuracy"]["sign_mismatches"].get<int>(), 0);
    EXPECT_LT(j["devices"][0]["accuracy"]["max_abs_error"].get<double>(), 1e-5);
    EXPECT_GT(j["devices"][0]["device_ms"].get<double>(), 0.0);
}

TEST(Cli, BuildReportsBricksDigestStagesMemory) {
    const fs::path dir = test::temp_dir("cli_build");
    const std::string env = "SDFBRICK_DEVICE=" + test_device_spec();
    const CliRun r = sdfbrick("build " + scene_path("spheres") + " --brick-size 0.125 --repeat 2 --json " +
                              (dir / "r.json").string(), env);
    ASSERT_EQ(r.status, 0) << r.err;
    const auto j = nlohmann::json::parse(read_file(dir / "r.json"));
    EXPECT_GT(j["bricks"].get<int>(), 100);
    EXPECT_EQ(j["digest"].get<std::string>().size(), 16u);
    EXPECT_GT(j["memory"]["brick pool"].get<std::uint64_t>(), 0u);
    EXPECT_TRUE(j["devices"][0]["captures"]["identical"].get<bool>());
    std::set<std::string> stages;
    for (const auto& st : j["stages"]) stages.insert(st["name"].get<std::string>());
    for (const char* s : {"count", "scan", "subdivide", "cull", "evaluate", "aabb"}) EXPECT_TRUE(stages.count(s)) << s;
    std::set<std::string> roofline;  // FLOPs and bytes over each stage's median time
    for (const auto& st : j["devices"][0]["roofline"]["stages"]) {
        roofline.insert(st["stage"].get<std::string>());
        EXPECT_GT(st["flop"].get<double>(), 0.0) << st;
        EXPECT_NEAR(st["gflops"].get<double>(), st["flop"].get<double>() / (st["ms"].get<double>() * 1e6),
                    1e-9 * st["gflops"].get<double>()) << st;
    }
    EXPECT_EQ(roofline, (std::set<std::string>{"count", "cull", "evaluate"}));
    EXPECT_NE(r.out.find("roofline"), std::string::npos) << r.out;
    const CliRun lanes = sdfbrick("build " + scene_path("spheres") + " --brick-size 0.125 --lanes 1 --json " +
                                  (dir / "lanes.json").string(), env);
    ASSERT_EQ(lanes.status, 0) << lanes.err;
    EXPECT_EQ(nlohmann::json::parse(read_file(dir / "lanes.json"))["digest"], j["digest"]);
    const CliRun off = sdfbrick("build " + scene_path("spheres") + " --brick-size 0.125 --no-cull --json " +
                                (dir / "off.json").string(), env);
    ASSERT_EQ(off.status, 0) << off.err;
    EXPECT_EQ(nlohmann::json::parse(read_file(dir / "off.json"))["digest"], j["digest"]);
    const CliRun bad = sdfbrick("build " + scene_path("spheres") + " --brick-size 0.125 --chunk 4", env);
    EXPECT_EQ(bad.status, 2);
    EXPECT_NE(bad.err.find("--chunk"), std::string::npos) << bad.err;
}

TEST(Cli, RenderWritesPicturesAndAccuracy) {
    const fs::path dir = test::temp_dir("cli_render");
    const std::string env = "SDFBRICK_DEVICE=" + test_device_spec();
    const fs::path out = dir / "s.ppm";
    const CliRun r = sdfbrick("render " + scene_path("spheres") + " --brick-size 0.125 --width 48 --height 32 --compare "
                              "--repeat 2 --out " + out.string() + " --json " + (dir / "r.json").string(), env);
    ASSERT_EQ(r.status, 0) << r.err;
    for (const char* f : {"s.ppm", "s-reference.ppm", "s-difference.ppm"}) EXPECT_TRUE(fs::exists(dir / f)) << f;
    const auto j = nlohmann::json::parse(read_file(dir / "r.json"));
    std::map<std::string, nlohmann::json> stages;
    for (const auto& st : j["stages"]) stages[st["name"].get<std::string>()] = st;
    for (const char* s : {"count", "evaluate", "bvh", "trace", "reference"}) ASSERT_TRUE(stages.count(s)) << s;
    for (const char* s : {"evaluate", "trace"}) {  // two captures: median, min, max and cv per stage
        EXPECT_GT(stages[s]["median_ms"].get<double>(), 0.0) << s;
        EXPECT_EQ(stages[s]["samples_ms"].size(), 2u) << s;
        EXPECT_LE(stages[s]["min_ms"].get<double>(), stages[s]["max_ms"].get<double>()) << s;
    }
    EXPECT_GT(j["rays_per_second"].get<double>(), 0.0);
    EXPECT_TRUE(j["devices"][0]["captures"]["identical"].get<bool>());
    EXPECT_EQ(j["devices"][0]["captures"]["warmup"], 1);
    bool evaluate_row = false;
    for (const auto& k : j["devices"][0]["kernels"]) {
        if (k["kernel"] == "brick_count") {  // it runs at every level: a row per level, adding up to the kernel's
            int launches = 0, last = -1;
            double total = 0.0;
            for (const auto& l : k["levels"]) {
                EXPECT_GT(l["level"].get<int>(), last);
                last = l["level"].get<int>();
                launches += l["launches"].get<int>();
                total += l["total_ms"].get<double>();
            }
            EXPECT_GT(k["levels"].size(), 1u);
            EXPECT_EQ(launches, k["launches"].get<int>());
            EXPECT_NEAR(total, k["total_ms"].get<double>(), 1e-9);
        }
        if (k["kernel"] != "brick_evaluate") continue;
        evaluate_row = true;
        EXPECT_EQ(k["launches"], 2);
        EXPECT_GT(k["attributes"]["local_mem_bytes"].get<double>(), 0.0);
        EXPECT_TRUE(k["occupancy"].contains("theoretical"));
    }
    EXPECT_TRUE(evaluate_row);
    const auto& a = j["accuracy"];
    EXPECT_GT(a["both_hit"].get<int>(), 100);
    EXPECT_LT(a["depth_error_p99"].get<double>(), 0.5);
    EXPECT_LT(a["normal_error_mean_deg"].get<double>(), 2.0);
    const CliRun bad = sdfbrick("render " + scene_path("spheres") + " --mode x-ray", env);
    EXPECT_EQ(bad.status, 2);
    EXPECT_NE(bad.err.find("--mode"), std::string::npos) << bad.err;
    const CliRun big = sdfbrick("render " + scene_path("spheres") + " --width 5000", env);
    EXPECT_EQ(big.status, 2);
    EXPECT_NE(big.err.find("--width"), std::string::npos) << big.err;
}

// tune writes the database; a following build reads it (and says so); --no-tuning ignores it; compare
// reads two build reports.
TEST(Cli, TuneWritesTheDatabaseAndLaterRunsUseIt) {
    const fs::path dir = test::temp_dir("cli_tune");
    const std::string db = (dir / "tuning.json").string();
    const std::string env = "SDFBRICK_DEVICE=" + test_device_spec() + " SDFBRICK_TUNING_DB=" + db;
    const CliRun t = sdfbrick("tune " + scene_path("spheres") + " --brick-size 0.5 --kernels evaluate,trace --strategy random "
                              "--budget 3 --repeat 1 --warmup 0 --width 32 --height 16", env);
    ASSERT_EQ(t.status, 0) << t.err;
    const auto j = nlohmann::json::parse(read_file(db));
    ASSERT_EQ(j["entries"].size(), 2u) << j.dump();
    const auto& e = j["entries"][0]["kernel"] == "brick_evaluate" ? j["entries"][0] : j["entries"][1];
    const int chunk = e["params"]["chunk"], group = e["params"]["group"];
    EXPECT_EQ(e["evaluated"], 3);

    const CliRun b = sdfbrick("build " + scene_path("spheres") + " --brick-size 0.5 --repeat 2 --json " + (dir / "a.json").string(), env);
    ASSERT_EQ(b.status, 0) << b.err;
    EXPECT_NE(b.out.find(fmt::format("brick_evaluate chunk {} group {} (device)", chunk, group)), std::string::npos) << b.out;
    const auto report = nlohmann::json::parse(read_file(dir / "a.json"));
    EXPECT_EQ(report["settings"]["chunk"], chunk);
    EXPECT_EQ(report["tuning"]["brick_evaluate"]["source"], "device");

    const CliRun given = sdfbrick("build " + scene_path("spheres") + " --brick-size 0.5 --chunk 16 --group 32", env);
    EXPECT_NE(given.out.find("chunk 16 group 32 (command line)"), std::string::npos) << given.out;
    const CliRun off = sdfbrick("--no-tuning build " + scene_path("spheres") + " --brick-size 0.5 --repeat 2 --json " + (dir / "b.json").string(), env);
    ASSERT_EQ(off.status, 0) << off.err;
    EXPECT_NE(off.out.find("chunk 64 group 128 (default)"), std::string::npos) << off.out;

    const CliRun c = sdfbrick("compare " + (dir / "a.json").string() + " " + (dir / "b.json").string(), env);
    ASSERT_EQ(c.status, 0) << c.err;
    for (const char* s : {"evaluate", "total", "stage(s) changed"}) EXPECT_NE(c.out.find(s), std::string::npos) << c.out;
}

// With no tuning file yet, a build takes the compiled-in layer's values for a known device (this
// machine's PoCL is one), else the defaults, and says which; --no-tuning ignores both layers.
TEST(Cli, BuildUsesTheBuiltinTuningLayerUnlessTuningIsOff) {
    const fs::path dir = test::temp_dir("cli_builtin_tuning");
    const std::string env = "SDFBRICK_DEVICE=" + test_device_spec() + " SDFBRICK_TUNING_DB=" + (dir / "none.json").string();
    const ocl::DeviceInfo& d = test::device().info();
    const tune::Lookup expect = tune::TuningDb().find(d.name, d.driver_version, d.vendor, tune::kEvaluateKernel);
    const tune::Config want = expect.entry ? expect.params : tune::evaluate_kernel().default_config();
    const CliRun b = sdfbrick("build " + scene_path("spheres") + " --brick-size 0.5 --json " + (dir / "a.json").string(), env);
    ASSERT_EQ(b.status, 0) << b.err;
    const auto report = nlohmann::json::parse(read_file(dir / "a.json"));
    EXPECT_EQ(report["tuning"]["brick_evaluate"]["source"], tune::to_string(expect.source)) << d.name;
    EXPECT_EQ(report["settings"]["chunk"], want.at("chunk"));
    EXPECT_EQ(report["settings"]["group"], want.at("group"));
    EXPECT_NE(b.out.find(fmt::format("brick_evaluate chunk {} group {} ({})", want.at("chunk"), want.at("group"),
                                     tune::to_string(expect.source))), std::string::npos) << b.out;
    EXPECT_FALSE(fs::exists(dir / "none.json")) << "reading never writes the file";

    const CliRun off = sdfbrick("--no-tuning build " + scene_path("spheres") + " --brick-size 0.5 --json " + (dir / "b.json").string(), env);
    ASSERT_EQ(off.status, 0) << off.err;
    EXPECT_NE(off.out.find("chunk 64 group 128 (default)"), std::string::npos) << off.out;
    EXPECT_EQ(nlohmann::json::parse(read_file(dir / "b.json"))["tuning"]["brick_evaluate"]["source"], "default");
}

// Two shards of a sweep, then merge: one complete CSV with every grid point.
TEST(Cli, SweepShardsMerge) {
    const fs::path dir = test::temp_dir("cli_sweep");
    const std::string env = "SDFBRICK_DEVICE=" + test_device_spec() + " SDFBRICK_TUNING_DB=off";
    const std::string grid = "sweep --scenes " + scene_path("spheres") + " --brick-sizes 0.5 --chunks 16,32 --cull on,off "
                             "--width 32 --height 16 --warmup 0 --repeat 1 ";
    for (int i = 0; i < 2; ++i) {
        const CliRun r = sdfbrick(grid + fmt::format("--shard {}/2 --out {}", i, (dir / fmt::format("s{}", i)).string()), env);
        ASSERT_EQ(r.status, 0) << r.err;
        EXPECT_NE(r.out.find("2 points of 4 in the grid"), std::string::npos) << r.out;
    }
    const CliRun again = sdfbrick(grid + "--shard 0/2 --out " + (dir / "s0").string(), env);  // resumed: all cached
    ASSERT_EQ(again.status, 0) << again.err;
    const CliRun m = sdfbrick("merge " + (dir / "s0.json").string() + " " + (dir / "s1.json").string() + " --out " +
                              (dir / "all").string(), env);
    ASSERT_EQ(m.status, 0) << m.err;
    EXPECT_NE(m.out.find("4 points from 2 files, complete"), std::string::npos) << m.out;
    const std::string csv = read_file(dir / "all.csv");
    EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 5) << csv;
    const CliRun part = sdfbrick("merge " + (dir / "s0.json").string() + " --out " + (dir / "part").string(), env);
    EXPECT_NE(part.out.find("NOT complete"), std::string::npos) << part.out;
    const CliRun bad = sdfbrick("sweep --scenes " + scene_path("spheres") + " --chunks 7", env);
    EXPECT_EQ(bad.status, 2);
    EXPECT_NE(bad.err.find("chunks"), std::string::npos) << bad.err;
}

// A setting the library refuses: exit status 2 and one line that names the flag, then the message in
// the library's terms (the setting's own name).
TEST(Cli, RefusedSettingNamesItsFlag) {
    const fs::path dir = test::temp_dir("cli_setting");
    const std::string env = "SDFBRICK_DEVICE=" + test_device_spec() + " SDFBRICK_TUNING_DB=" + (dir / "tuning.json").string();
    const std::string spheres = scene_path("spheres");
    const std::pair<std::string, std::string> cases[] = {
        {"build " + spheres + " --brick-size 0.5 --chunk 8", "sdfbrick: --chunk: chunk must lie in 16..256, got 8\n"},
        {"render " + spheres + " --width 5000", "sdfbrick: --width: width 5000 is outside 1..3840\n"},
        {"render " + spheres + " --brick-size 0.5 --width 32 --height 16 --group-x 4096 --group-y 4096",
         "sdfbrick: --group-x: group_x x group_y = 4096 x 4096 is not a work-group size "},
        {"sweep --scenes " + spheres + " --shard 4/4", "sdfbrick: --shard: shard must be i/n with 0 <= i < n (e.g. 0/4), got \"4/4\"\n"},
        {"tune " + spheres + " --brick-size 0.5 --kernels evaluate --strategy genetic",
         "sdfbrick: --strategy: strategy must be auto, full, random or anneal, got \"genetic\"\n"},
        {"scene info " + spheres + " --bricks 1e-12", "sdfbrick: --bricks: leaf_size 1e-12 is too small for the bounds"},
        {"build " + spheres + " --brick-size 1e-12", "sdfbrick: --brick-size: leaf_size 1e-12 is too small for the bounds"},
        {"build " + spheres + " --tolerance 0", "sdfbrick: --tolerance: tolerance must be a positive number, got 0\n"},
        {"build " + spheres + " --tolerance -0.5", "sdfbrick: --tolerance: tolerance must be a positive number, got -0.5\n"},
        {"build " + spheres + " --brick-size 0.0625 --tolerance 1e-9",
         "sdfbrick: --tolerance: tolerance 1e-09 is finer than float precision allows"},
    };
    for (const auto& [args, expect] : cases) {
        const CliRun r = sdfbrick(args, env);
        EXPECT_EQ(r.status, 2) << args << ": " << r.err;
        EXPECT_EQ(r.err.rfind(expect, 0), 0u) << args << ": stderr was: " << r.err;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << args << ": not one line: " << r.err;
    }
    EXPECT_FALSE(fs::exists(dir / "tuning.json")) << "a refused tune wrote the database";
}

// Every kind of bad input: exit status 2, one line on stderr naming the place, no output file.
TEST(Cli, BadInputIsRefusedCleanly) {
    const fs::path dir = test::temp_dir("cli_bad");
    struct Case { const char* what; std::string file_text; std::string expect; std::string extra_args; };
    const std::string ok_scene = R"({"geometries": [{"name": "g", "edits": [{"primitive": "sphere", "radius": 1}]}]})";
    const Case cases[] = {
        {"truncated", ok_scene.substr(0, 30), "line 1, column", ""},
        {"unknown primitive", R"({"geometries": [{"name": "g", "edits": [{"primitive": "blob", "radius": 1}]}]})", "/geometries/0/edits/0/primitive", ""},
        {"unknown op", R"({"geometries": [{"name": "g", "edits": [{"primitive": "sphere", "radius": 1, "op": "xor"}]}]})", "/geometries/0/edits/0/op", ""},
        {"missing field", R"({"geometries": [{"name": "g", "edits": [{"primitive": "sphere"}]}]})", "missing field \"radius\"", ""},
        {"infinite", R"({"geometries": [{"name": "g", "edits": [{"primitive": "sphere", "radius": 1e999}]}]})", "not finite", ""},
        {"NaN", R"({"geometries": [{"name": "g", "edits": [{"primitive": "sphere", "radius": NaN}]}]})", "invalid JSON", ""},
        {"negative size", R"({"geometries": [{"name": "g", "edits": [{"primitive": "box", "half_extents": [1, -1, 1]}]}]})", "/half_extents/1: must be > 0", ""},
        {"non-unit quaternion", R"({"geometries": [{"name": "g", "edits": [{"primitive": "sphere", "radius": 1, "rotation": [1, 1, 0, 0]}]}]})", "not a unit quaternion", ""},
        {"unknown device", ok_scene, "no OpenCL device matches 'no-such-device'", "--device no-such-device"},
    };
    int n = 0;
    for (const Case& c : cases) {
        const fs::path scene = dir / ("bad" + std::to_string(n++) + ".json");
        std::ofstream(scene) << c.file_text;
        const fs::path img = dir / "out.ppm", report = dir / "out.json";
        const CliRun r = sdfbrick(c.extra_args + " eval " + scene.string() + " -o " + img.string() + " --json " + report.string());
        EXPECT_EQ(r.status, 2) << c.what << ": " << r.err;
        EXPECT_NE(r.err.find(c.expect), std::string::npos) << c.what << ": stderr was: " << r.err;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << c.what << ": not one line: " << r.err;
        if (c.extra_args.empty()) {
            EXPECT_NE(r.err.find(scene.string()), std::string::npos) << c.what << ": file not named: " << r.err;
        }
        EXPECT_FALSE(fs::exists(img)) << c.what << ": left a picture behind";
        EXPECT_FALSE(fs::exists(report)) << c.what << ": left a report behind";
        for (const auto& entry : fs::directory_iterator(dir))
            EXPECT_EQ(entry.path().filename().string().find(".tmp-"), std::string::npos) << c.what << ": left " << entry.path();
    }
    // Too many edits: generated rather than written out by hand.
    std::string many = R"({"geometries": [{"name": "g", "edits": [)";
    for (unsigned i = 0; i <= SDF_MAX_EDITS; ++i) many += std::string(i ? "," : "") + R"({"primitive": "sphere", "radius": 1})";
    std::ofstream(dir / "many.json") << many << "]}]}";
    const CliRun r = sdfbrick("scene info " + (dir / "many.json").string());
    EXPECT_EQ(r.status, 2);
    EXPECT_NE(r.err.find("/geometries/0/edits: 65537 edits"), std::string::npos) << r.err;
    // Bad options are input errors too.
    EXPECT_EQ(sdfbrick("eval " + scene_path("spheres") + " --size 0").status, 2);
    EXPECT_EQ(sdfbrick("no-such-verb").status, 2);
}

}  // namespace
}  // namespace sdfbrick
