// Split runs over two PoCL devices (POCL_DEVICES="pthread pthread", one core each: POCL_CPU_MAX_CU_NUM,
// or POCL_MAX_PTHREAD_COUNT before PoCL 4): PoCL reads its
// device list when the platform starts, so these tests run the command line in a child process with
// that environment. Split results equal one device's bit for bit, with and without device faults.
#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <sys/wait.h>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "core/files.h"
#include "pipeline/split.h"
#include "cli/cli_run.h"
#include "test_support.h"

namespace sdfbrick {
namespace {

namespace fs = std::filesystem;

using test::CliRun;

// Two one-core PoCL devices, a rate store in dir, and `extra` environment (which may turn the store off).
std::string two_devices(const fs::path& dir, const std::string& extra = "") {
    return fmt::format("POCL_DEVICES='pthread pthread' POCL_CPU_MAX_CU_NUM=1 POCL_MAX_PTHREAD_COUNT=1 SDFBRICK_RATES={} {}",
                       (dir / "rates.json").string(), extra);
}


nlohmann::json run_json(const fs::path& dir, const std::string& env, const std::string& args) {
    const fs::path report = dir / "r.json";
    fs::remove(report);
    const CliRun r = test::sdfbrick(args + " --json " + report.string(), env);
    EXPECT_EQ(r.status, 0) << args << "\n" << r.err;
    return r.status == 0 ? nlohmann::json::parse(read_file(report)) : nlohmann::json::object();
}

using test::scene_path;

// Two geometries (so that every geometry's parts are merged), three objects.
fs::path two_geometry_scene(const fs::path& dir) {
    const fs::path p = dir / "two.json";
    test::write_text(p, R"({"version": 1, "name": "two",
  "camera": {"fov_deg": 45.0, "orbit": {"distance": 6.0, "pitch_deg": 15.0, "target": [0.0, 0.0, 0.0], "yaw_deg": 20.0}},
  "geometries": [
    {"name": "blob", "edits": [{"primitive": "sphere", "radius": 1.0},
                              {"primitive": "sphere", "radius": 0.6, "position": [0.8, 0.5, 0.0], "blend": 0.3}]},
    {"name": "ball", "edits": [{"primitive": "sphere", "radius": 0.7, "position": [0.0, 0.2, 0.1]}]}],
  "objects": [{"name": "a", "geometry": "blob", "position": [-1.2, 0.0, 0.0]},
              {"name": "b", "geometry": "ball", "position": [1.3, 0.0, 0.0]},
              {"name": "c", "geometry": "blob", "position": [0.0, 1.5, -1.0], "scale": 0.5}]})");
    return p;
}

constexpr const char* kRender = " --brick-size 0.125 --width 96 --height 64 --mode shaded --shadow-rays 1 --ao-rays 1";

TEST(PipelineSplit, BuildEqualsOneDeviceBitForBit) {
    const fs::path dir = test::temp_dir("split_build");
    const std::string env = two_devices(dir);
    const std::string two = two_geometry_scene(dir).string();
    for (const std::string& args : {"build " + scene_path("drops") + " --brick-size 0.25",
                                    "build " + scene_path("drops") + " --brick-size 0.25 --apron-share-edits 1",
                                    "build " + two + " --brick-size 0.125", "build " + two + " --brick-size 0.125 --no-cull"}) {
        {
            const nlohmann::json one = run_json(dir, env, "--device 0 " + args);
            fs::remove(dir / "rates.json");  // split by the static estimate: half each, whatever the load
            const nlohmann::json split = run_json(dir, env, "--device cpu --devices split " + args);
            ASSERT_EQ(split["placement"]["construct"]["devices"].size(), 2u);
            EXPECT_EQ(split["digest"], one["digest"]) << args;
            EXPECT_EQ(split["list_digest"], one["devices"][0]["list_digest"]) << args;
            EXPECT_EQ(split["bricks"], one["bricks"]) << args;
            for (const auto& d : split["placement"]["construct"]["devices"]) EXPECT_GT(d["done"].get<double>(), 0.1) << args;
        }
    }
}

// Shaded renders of one and of several geometries with instances, and the other methods and normal
// rules: the image of one device, byte for byte.
TEST(PipelineSplit, RenderEqualsOneDeviceBitForBit) {
    const fs::path dir = test::temp_dir("split_render");
    const std::string env = two_devices(dir);
    const std::string two = two_geometry_scene(dir).string();
    for (const std::string& args :
         {"render " + scene_path("spheres") + kRender, "render " + two + kRender,
          "render " + two + " --brick-size 0.125 --width 96 --height 64 --method analytic --normals tetra",
          "render " + two + " --brick-size 0.125 --width 96 --height 64 --method hybrid --normals central"}) {
        const nlohmann::json one = run_json(dir, env, "--device 0 " + args + " --out " + (dir / "one.ppm").string());
        fs::remove(dir / "rates.json");  // split by the static estimate: half each, whatever the load
        const nlohmann::json split =
            run_json(dir, env, "--device cpu --devices split " + args + " --out " + (dir / "split.ppm").string());
        EXPECT_EQ(split["digest"], one["digest"]) << args;
        EXPECT_EQ(split["bricks"], one["bricks"]) << args;
        EXPECT_EQ(read_file(dir / "split.ppm"), read_file(dir / "one.ppm")) << args;
        for (const auto& d : split["placement"]["trace"]["devices"]) EXPECT_GT(d["done"].get<double>(), 0.1) << args;
        // Where the time went: every device ran kernels and copied; each tracing device received the
        // whole merged scene, so the same bytes.
        for (const char* stage : {"construct", "trace"})
            for (const auto& d : split["placement"][stage]["devices"]) {
                EXPECT_GT(d["kernels_ms"].get<double>(), 0.0) << stage;
                EXPECT_GT(d["copied_bytes"].get<std::uint64_t>(), 0u) << stage;
                EXPECT_LE(d["copies_ms"].get<double>(), d["busy_ms"].get<double>()) << stage;
            }
        EXPECT_EQ(split["placement"]["trace"]["devices"][0]["copied_bytes"], split["placement"]["trace"]["devices"][1]["copied_bytes"]);
    }
}

// Adaptive leaves split at the coarsest leaf level at the latest: the same bricks, levels, pool and
// image as on one device, the same per-level leaves.
TEST(PipelineSplit, AdaptiveEqualsOneDeviceBitForBit) {
    const fs::path dir = test::temp_dir("split_adaptive");
    const std::string env = two_devices(dir, "SDFBRICK_RATES=off");
    for (const std::string& args : {"build " + scene_path("thin") + " --brick-size 0.03125 --tolerance 0.004",
                                    "render " + two_geometry_scene(dir).string() +
                                        " --width 96 --height 64 --mode shaded --shadow-rays 1 --ao-rays 1"
                                        " --brick-size 0.03125 --tolerance 0.003"}) {
        const bool build = args.starts_with("build");
        const auto out = [&](const char* name) { return build ? "" : " --out " + (dir / name).string(); };
        const nlohmann::json one = run_json(dir, env, "--device 0 " + args + out("one.ppm"));
        const nlohmann::json split = run_json(dir, env, "--device cpu --devices split " + args + out("split.ppm"));
        EXPECT_EQ(split["digest"], one["digest"]) << args;
        EXPECT_EQ(split["bricks"], one["bricks"]) << args;
        ASSERT_EQ(split["placement"]["construct"]["devices"].size(), 2u) << args;
        for (const auto& d : split["placement"]["construct"]["devices"]) EXPECT_GT(d["done"].get<double>(), 0.0) << args;
        if (build) {
            EXPECT_EQ(split["list_digest"], one["list_digest"]) << args;
            const auto& a = one["geometries"][0]["levels"];
            const auto& b = split["geometries"][0]["levels"];
            ASSERT_EQ(a.size(), b.size());
            for (std::size_t l = 0; l < a.size(); ++l) EXPECT_EQ(a[l]["leaves"], b[l]["leaves"]) << l;
        } else {
            EXPECT_EQ(read_file(dir / "split.ppm"), read_file(dir / "one.ppm")) << args;
        }
    }
}

// --compare and --reference run on the device that holds the job's bricks: the same accuracy and
// pictures as one device, and a report of the same schema as one device's.
TEST(PipelineSplit, CompareAndReferenceEqualOneDevice) {
    const fs::path dir = test::temp_dir("split_compare");
    const std::string env = two_devices(dir, "SDFBRICK_RATES=off");
    for (const std::string& extra : {std::string(" --compare"), std::string(" --reference --mode normals")}) {
        const std::string args = "render " + scene_path("spheres") + " --brick-size 0.125 --width 96 --height 64" + extra;
        const nlohmann::json one = run_json(dir, env, "--device 0 " + args + " --out " + (dir / "one.ppm").string());
        const nlohmann::json split =
            run_json(dir, env, "--device cpu --devices split " + args + " --out " + (dir / "split.ppm").string());
        EXPECT_EQ(split["digest"], one["digest"]) << extra;
        EXPECT_EQ(read_file(dir / "split.ppm"), read_file(dir / "one.ppm")) << extra;
        if (extra == " --compare") {
            EXPECT_EQ(split["accuracy"], one["accuracy"]);
            EXPECT_EQ(read_file(dir / "split-reference.ppm"), read_file(dir / "one-reference.ppm"));
            EXPECT_EQ(read_file(dir / "split-difference.ppm"), read_file(dir / "one-difference.ppm"));
        }
        for (const auto& [key, value] : one.items()) EXPECT_TRUE(split.contains(key)) << key << extra;
        EXPECT_EQ(one["placement"]["placement"], "whole");
        EXPECT_EQ(split["placement"]["placement"], "split");
    }
}

// sample reads the merged bricks of a split back: the same distances as one device's.
TEST(PipelineSplit, SampleEqualsOneDevice) {
    const fs::path dir = test::temp_dir("split_sample");
    const std::string env = two_devices(dir, "SDFBRICK_RATES=off");
    std::string points = "x,y,z\n";
    for (int i = 0; i < 64; ++i) points += fmt::format("{},{},{}\n", -1.6 + 0.05 * i, 0.3 - 0.01 * i, 0.02 * (i % 7));
    test::write_text(dir / "p.csv", points);
    const std::string args = "sample " + scene_path("drops") + " --brick-size 0.25 --points " + (dir / "p.csv").string();
    const CliRun one = test::sdfbrick("--device 0 " + args + " -o " + (dir / "one.csv").string(), env);
    ASSERT_EQ(one.status, 0) << one.err;
    const CliRun split = test::sdfbrick("--device cpu --devices split " + args + " -o " + (dir / "split.csv").string(), env);
    ASSERT_EQ(split.status, 0) << split.err;
    EXPECT_EQ(read_file(dir / "split.csv"), read_file(dir / "one.csv"));
}

// The first run splits by the static estimate and stores each device's measured rate; a store that
// says device 1 is three times faster moves three quarters of the work there, one that says it is a
// hundred times faster all of it.
TEST(PipelineSplit, BalanceFollowsMeasuredRates) {
    const fs::path dir = test::temp_dir("split_balance");
    const std::string env = two_devices(dir);
    const std::string args =
        "--device cpu --devices split render " + scene_path("spheres") + kRender + " --out " + (dir / "p.ppm").string();
    const nlohmann::json first = run_json(dir, env, args);
    EXPECT_EQ(first["placement"]["construct"]["basis"], pipeline::kStaticBasis);
    EXPECT_NEAR(first["placement"]["construct"]["devices"][0]["planned"].get<double>(), 0.5, 1e-9);
    nlohmann::json store = nlohmann::json::parse(read_file(dir / "rates.json"));
    ASSERT_EQ(store.size(), 2u);
    double r = 1.0;
    const std::string workload = "spheres at 0.125";
    EXPECT_EQ(first["placement"]["construct"]["workload"], workload);
    for (auto& [key, rates] : store.items()) {  // keys begin with the device index: 0 first
        for (const char* stage : {"construct", "trace"}) {
            ASSERT_GT(rates[workload][stage].get<double>(), 0.0) << key;
            rates[workload][stage] = r;
        }
        r = 3.0;
    }
    test::write_text(dir / "rates.json", store.dump());
    const nlohmann::json second = run_json(dir, env, args);
    for (const char* stage : {"construct", "trace"}) {
        EXPECT_EQ(second["placement"][stage]["basis"], "measured rates");
        EXPECT_NEAR(second["placement"][stage]["devices"][0]["planned"].get<double>(), 0.25, 1e-9) << stage;
        EXPECT_NEAR(second["placement"][stage]["devices"][1]["planned"].get<double>(), 0.75, 1e-9) << stage;
    }
    EXPECT_EQ(second["digest"], first["digest"]);
    EXPECT_GT(second["placement"]["construct"]["speedup_estimated"].get<double>(), 0.0);
    // Under a tenth of the total weight: no share at all.
    r = 1.0;
    for (auto& [key, rates] : store.items()) {
        for (const char* stage : {"construct", "trace"}) rates[workload][stage] = r;
        r = 100.0;
    }
    test::write_text(dir / "rates.json", store.dump());
    const nlohmann::json third = run_json(dir, env, args);
    for (const char* stage : {"construct", "trace"}) {
        EXPECT_EQ(third["placement"][stage]["devices"][0]["done"].get<double>(), 0.0) << stage;
        EXPECT_EQ(third["placement"][stage]["devices"][1]["done"].get<double>(), 1.0) << stage;
    }
    EXPECT_EQ(third["digest"], first["digest"]);
    // Rates of another workload (scene and brick size) are not this one's: device 0's rate for
    // spheres at 0.125 beside device 1's for another scene gives the static estimate.
    for (auto& [key, rates] : store.items()) {
        if (key.front() == '1') rates["other at 0.125"] = rates[workload];
        if (key.front() == '1') rates.erase(workload);
    }
    test::write_text(dir / "rates.json", store.dump());
    const nlohmann::json fourth = run_json(dir, env, args);
    for (const char* stage : {"construct", "trace"}) EXPECT_EQ(fourth["placement"][stage]["basis"], pipeline::kStaticBasis) << stage;
}

// A device that fails at its n-th launch has its share redone by the other: the same bits, and the
// report names the failure. Without a rate store both devices take half, so launch 40 lands in the
// BVH and 44 in shading: the trace stage.
TEST(PipelineSplit, DeviceFaultGivesTheSameBits) {
    const fs::path dir = test::temp_dir("split_fault");
    const std::string args =
        "--device cpu --devices split render " + scene_path("spheres") + kRender + " --out " + (dir / "p.ppm").string();
    const nlohmann::json clean = run_json(dir, two_devices(dir, "SDFBRICK_RATES=off"), args);
    for (int device : {0, 1}) {
        for (int n : {1, 12, 40, 44}) {
            const std::string fault = fmt::format("SDFBRICK_RATES=off SDFBRICK_FAULT=launch@{}:{}", device, n);
            const nlohmann::json j = run_json(dir, two_devices(dir, fault), args);
            EXPECT_EQ(j["digest"], clean["digest"]) << fault;
            EXPECT_EQ(j["bricks"], clean["bricks"]) << fault;
            const std::string stage = n < 40 ? "construct" : "trace";
            const auto& failure = j["placement"][stage]["devices"][device]["failure"];
            ASSERT_TRUE(failure.is_string()) << fault << " " << j.dump();
            EXPECT_NE(failure.get<std::string>().find("injected"), std::string::npos) << failure;
            EXPECT_GT(j["placement"][stage]["devices"][1 - device]["done"].get<double>(), 0.99) << fault;
        }
    }
}

// A device out of memory for its part takes parts of half the width, and leaves the run when even
// a sixty-fourth of the stage does not fit; the report says why, and the bits stay the same.
TEST(PipelineSplit, DeviceThatCannotHoldItsShareGetsLess) {
    const fs::path dir = test::temp_dir("split_memory");
    const std::string args = "--device cpu --devices split build " + scene_path("drops") + " --brick-size 0.25";
    const nlohmann::json clean = run_json(dir, two_devices(dir, "SDFBRICK_RATES=off"), args);
    const nlohmann::json once = run_json(dir, two_devices(dir, "SDFBRICK_RATES=off SDFBRICK_FAULT=alloc@1:1"), args);
    EXPECT_EQ(once["digest"], clean["digest"]);
    const auto& shares = once["placement"]["construct"]["devices"];
    EXPECT_TRUE(shares[1]["failure"].is_null()) << shares;
    ASSERT_TRUE(shares[1]["limit"].is_string()) << shares;
    EXPECT_NE(shares[1]["limit"].get<std::string>().find("could not hold 50.0%"), std::string::npos) << shares;
    EXPECT_NEAR(shares[1]["done"].get<double>(), 0.25, 1e-12);
    EXPECT_NEAR(shares[0]["done"].get<double>(), 0.75, 1e-12);
    std::string every = "SDFBRICK_RATES=off SDFBRICK_FAULT=";
    for (int n = 1; n <= 6; ++n) every += fmt::format("{}alloc@1:{}", n > 1 ? "," : "", n);
    const nlohmann::json never = run_json(dir, two_devices(dir, every), args);
    EXPECT_EQ(never["digest"], clean["digest"]);
    const auto& gone = never["placement"]["construct"]["devices"];
    ASSERT_TRUE(gone[1]["failure"].is_string()) << gone;
    EXPECT_NE(gone[1]["failure"].get<std::string>().find("could not hold even 1.6%"), std::string::npos) << gone;
    EXPECT_EQ(gone[1]["done"].get<double>(), 0.0);
    EXPECT_EQ(gone[0]["done"].get<double>(), 1.0);
}

// Two devices of one context each compile and cache their own programs (a program made in a
// context of two devices has a binary slot per device), and a second run loads them all.
TEST(PipelineSplit, EachDeviceCachesItsOwnPrograms) {
    const fs::path dir = test::temp_dir("split_cache");
    const auto entries = [](const fs::path& cache) {
        std::size_t n = 0;
        for (const auto& e : fs::directory_iterator(cache)) n += e.path().extension() == ".bin";
        return n;
    };
    const std::string build = " build " + scene_path("spheres") + " --brick-size 0.25";
    run_json(dir, two_devices(dir, "SDFBRICK_RATES=off SDFBRICK_CACHE_DIR=" + (dir / "one").string()), "--device 0" + build);
    const std::string split_env = two_devices(dir, "SDFBRICK_RATES=off SDFBRICK_CACHE_DIR=" + (dir / "two").string());
    run_json(dir, split_env, "--device cpu --devices split" + build);
    const std::size_t one = entries(dir / "one"), two = entries(dir / "two");
    EXPECT_GT(one, 0u);
    // Both devices compiled the construction programs (only the device that holds the merged bricks
    // digests them).
    EXPECT_GT(two, one + one / 2);
    run_json(dir, split_env, "--device cpu --devices split" + build);
    EXPECT_EQ(entries(dir / "two"), two);
}

// --repeat times several passes after the warm-ups: one wall time per capture and stage, the same
// digests in every pass.
TEST(PipelineSplit, RepeatedCapturesGiveTheSameBits) {
    const fs::path dir = test::temp_dir("split_repeat");
    const std::string env = two_devices(dir, "SDFBRICK_RATES=off");
    const std::string render = " render " + scene_path("spheres") + kRender + " --out " + (dir / "p.ppm").string();
    const nlohmann::json once = run_json(dir, env, "--device cpu --devices split" + render);
    const nlohmann::json thrice = run_json(dir, env, "--device cpu --devices split" + render + " --repeat 3 --warmup 1");
    EXPECT_TRUE(thrice["captures"]["identical"].get<bool>());
    EXPECT_EQ(thrice["digest"], once["digest"]);
    EXPECT_EQ(once["wall_ms"]["samples_ms"].size(), 1u);
    ASSERT_EQ(thrice["wall_ms"]["samples_ms"].size(), 3u);
    EXPECT_GT(thrice["wall_ms"]["median_ms"].get<double>(), 0.0);
    // Each lane's own launches, captured three times.
    for (const auto& d : thrice["devices"]) {
        EXPECT_EQ(d["captures"], 3) << d.dump();
        EXPECT_FALSE(d["stages"].empty()) << d.dump();
        EXPECT_GT(d["total_ms"]["median_ms"].get<double>(), 0.0);
    }
}

TEST(PipelineSplit, FaultOnEveryDeviceIsOneClearError) {
    const fs::path dir = test::temp_dir("split_fault_all");
    const CliRun r = test::sdfbrick("--device cpu --devices split render " + scene_path("spheres") + kRender + " --out " +
                                        (dir / "p.ppm").string() + " --json " + (dir / "r.json").string(),
                                    two_devices(dir, "SDFBRICK_FAULT=launch@0:3,launch@1:5"));
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.err.find("every device failed"), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_FALSE(fs::exists(dir / "p.ppm"));
    EXPECT_FALSE(fs::exists(dir / "r.json"));
}

TEST(PipelineSplit, BadInputNamesTheFlag) {
    const fs::path dir = test::temp_dir("split_bad");
    const std::string env = two_devices(dir);
    const std::string build = " build " + scene_path("spheres") + " --brick-size 0.125";
    const CliRun mode = test::sdfbrick("--devices halves" + build, env);
    EXPECT_EQ(mode.status, 2);
    EXPECT_NE(mode.err.find("--devices"), std::string::npos) << mode.err;
    const CliRun twice = test::sdfbrick("--device 0,cpu --devices split" + build, env);
    EXPECT_EQ(twice.status, 2);
    EXPECT_NE(twice.err.find("--device: device 0"), std::string::npos) << twice.err;
    // A malformed fault value is refused before any work (not as one failed lane of a split that
    // goes on without it), and so is a rate store that a file stands in the way of.
    const CliRun fault = test::sdfbrick("--device cpu --devices split" + build, env + " SDFBRICK_FAULT=launch@1:x");
    EXPECT_EQ(fault.status, 2) << fault.out;
    EXPECT_NE(fault.err.find("SDFBRICK_FAULT: item 'launch@1:x'"), std::string::npos) << fault.err;
    test::write_text(dir / "file", "x");
    const CliRun rates = test::sdfbrick("--device cpu --devices split" + build,
                                        two_devices(dir, "SDFBRICK_RATES=" + (dir / "file" / "rates.json").string()));
    EXPECT_EQ(rates.status, 2) << rates.out;
    EXPECT_NE(rates.err.find("is not a folder"), std::string::npos) << rates.err;
    EXPECT_EQ(std::count(rates.err.begin(), rates.err.end(), '\n'), 1) << rates.err;
    EXPECT_TRUE(rates.out.empty()) << rates.out;
    const CliRun other = test::sdfbrick("--device cpu --devices split eval " + scene_path("spheres") + " --size 8", env);
    EXPECT_EQ(other.status, 2);
    EXPECT_NE(other.err.find("only build, render, export and sample"), std::string::npos) << other.err;
}

}  // namespace
}  // namespace sdfbrick
