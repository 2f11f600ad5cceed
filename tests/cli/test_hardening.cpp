// The command line against hostile input and failing surroundings: special files as inputs and
// outputs, echoed input, outputs left behind, wrongly typed reports and sweep files, non-finite
// numbers, kernel build failures, and injected faults (core/fault.h) at every point.
#include <sys/stat.h>

#include <chrono>
#include <filesystem>
#include <string>
#include <thread>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli/cli_run.h"
#include "core/files.h"
#include "test_support.h"

namespace sdfbrick {
namespace {

namespace fs = std::filesystem;
using test::CliRun;
using test::scene_path;
using test::device_env;
using test::one_clean_line;
using test::sdfbrick;

std::string scene_with_edit(const std::string& edit) {
    return R"({"geometries": [{"name": "g", "edits": [)" + edit + "]}]}";
}

TEST(CliHardening, OutputsToSpecialFilesAreWrittenInPlaceAndFailedWritesReported) {
    const fs::path dir = test::temp_dir("cli_special_out");
    const fs::path fifo = dir / "fifo", got = dir / "got";
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    const CliRun r = sdfbrick("scene generate spheres -o " + fifo.string(),
                              fmt::format("(timeout 30 cat {} > {} &);", fifo.string(), got.string()));
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_TRUE(fs::is_fifo(fifo)) << "the FIFO was replaced by a regular file";
    const std::string expected = read_file(scene_path("spheres"));
    for (int i = 0; i < 100 && read_file(got).size() < expected.size(); ++i)
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
    EXPECT_EQ(read_file(got), expected);

    const CliRun full = sdfbrick("scene generate spheres -o /dev/full");
    EXPECT_EQ(full.status, 2);
    EXPECT_TRUE(one_clean_line(full));
    EXPECT_NE(full.err.find("/dev/full: write failed"), std::string::npos) << full.err;
    EXPECT_TRUE(fs::is_character_file("/dev/full"));

    const CliRun stdout_full = sdfbrick("scene generate drops", "", ">/dev/full");
    EXPECT_EQ(stdout_full.status, 2);
    EXPECT_TRUE(one_clean_line(stdout_full));
    EXPECT_NE(stdout_full.err.find("standard output: write failed"), std::string::npos) << stdout_full.err;

    const CliRun closed = sdfbrick("scene info " + scene_path("spheres"), "", ">&-");
    EXPECT_EQ(closed.status, 2);
    EXPECT_TRUE(one_clean_line(closed));
    EXPECT_NE(closed.err.find("standard output is closed"), std::string::npos) << closed.err;
}

TEST(CliHardening, SpecialAndHugeInputFilesAreRefused) {
    const fs::path dir = test::temp_dir("cli_special_in");
    ASSERT_EQ(::mkfifo((dir / "fifo").c_str(), 0600), 0);
    test::write_text(dir / "huge.json", "");
    fs::resize_file(dir / "huge.json", kMaxInputBytes + 1);  // sparse
    const std::pair<std::string, std::string> cases[] = {
        {"/dev/zero", "a character device, not a regular file"},
        {(dir / "fifo").string(), "a FIFO, not a regular file"},  // no writer: must not block
        {dir.string(), "a directory, not a regular file"},
        {(dir / "huge.json").string(), "at most"},
    };
    for (const auto& [file, expected] : cases) {
        const CliRun r = sdfbrick("scene info " + file, "timeout 60");
        EXPECT_EQ(r.status, 2) << file << ": " << r.err;
        EXPECT_TRUE(one_clean_line(r)) << file;
        EXPECT_NE(r.err.find(expected), std::string::npos) << r.err;
    }
}

TEST(CliHardening, EchoedInputIsEscapedCappedAndOnOneLine) {
    const fs::path dir = test::temp_dir("cli_echo");
    test::write_text(dir / "newline.json", scene_with_edit(R"({"primitive": "sphere\nsdfbrick: fake error", "radius": 1})"));
    test::write_text(dir / "escape.json", scene_with_edit(R"({"primitive": "\u001b[2J\u001b[31mred", "radius": 1})"));
    test::write_text(dir / "nul.json", scene_with_edit(R"({"primitive": "sph\u0000ere", "radius": 1})"));
    test::write_text(dir / "key.json", scene_with_edit(R"({"primitive": "sphere", "radius": 1, "a\nb": 2})"));
    test::write_text(dir / "long.json", scene_with_edit(R"({"primitive": ")" + std::string(16 << 20, 'x') + R"(", "radius": 1})"));
    test::write_text(dir / "deep.json", std::string(100000, '['));
    test::write_text(dir / "bytes.json", scene_with_edit("{\"primitive\": \"sph\xff\xfe\", \"radius\": 1}"));
    for (const char* name : {"newline", "escape", "nul", "key", "long", "deep", "bytes"}) {
        const CliRun r = sdfbrick(fmt::format("scene info {}/{}.json", dir.string(), name));
        EXPECT_EQ(r.status, 2) << name;
        EXPECT_TRUE(one_clean_line(r)) << name;
        EXPECT_LT(r.err.size(), 800u) << name << ": " << r.err.substr(0, 800);
    }
    EXPECT_NE(sdfbrick("scene info " + (dir / "nul.json").string()).err.find("\"sph\\x00ere\""), std::string::npos);
    const CliRun bad_flag = sdfbrick("build " + scene_path("spheres") + " --chunk x");
    EXPECT_EQ(bad_flag.status, 2);
    EXPECT_TRUE(one_clean_line(bad_flag));
}

TEST(CliHardening, FailedRunsLeaveNoOutputBehind) {
    const fs::path dir = test::temp_dir("cli_no_partial");
    const std::string out = (dir / "o.ppm").string();
    const std::string render = "render " + scene_path("spheres") + " --brick-size 0.5 --width 16 --height 12 --out " + out;
    const CliRun bad_json = sdfbrick(render + " --compare --json /nonexistent/r.json", device_env());
    EXPECT_EQ(bad_json.status, 2);
    EXPECT_TRUE(one_clean_line(bad_json));
    EXPECT_NE(bad_json.err.find("/nonexistent/r.json"), std::string::npos) << bad_json.err;
    const CliRun eval = sdfbrick("eval " + scene_path("spheres") + " --size 16 -o " + out + " --json /nonexistent/r.json", device_env());
    EXPECT_EQ(eval.status, 2);
    EXPECT_TRUE(one_clean_line(eval));
    // The third of four outputs fails as it is written: none of the four is left.
    const CliRun third = sdfbrick(render + " --compare --json " + (dir / "r.json").string(), device_env() + " SDFBRICK_FAULT=write:3");
    EXPECT_EQ(third.status, 2);
    EXPECT_TRUE(one_clean_line(third));
    EXPECT_TRUE(fs::is_empty(dir)) << "left behind: " << fs::directory_iterator(dir)->path();
}

TEST(CliHardening, SweepSurvivesAnErrorQuotingBytesThatAreNotUtf8) {
    const fs::path dir = test::temp_dir("cli_sweep_bytes");
    test::write_text(dir / "bad.json", scene_with_edit("{\"primitive\": \"sph\xff\", \"radius\": 1}"));
    const CliRun r = sdfbrick(fmt::format("sweep --scenes {} --brick-sizes 0.5 --width 16 --height 16 --repeat 1 --warmup 0 --out {}",
                                          (dir / "bad.json").string(), (dir / "s").string()), device_env());
    ASSERT_EQ(r.status, 0) << r.err;
    const auto doc = nlohmann::json::parse(read_file(dir / "s.json"));
    EXPECT_NE(doc.dump().find("\\\\xff"), std::string::npos) << doc.dump();
}

TEST(CliHardening, CompareNamesTheFileAndPathOfWronglyTypedReports) {
    const fs::path dir = test::temp_dir("cli_compare_types");
    const std::pair<const char*, const char*> cases[] = {
        {R"({"stages": [{"name": "count", "median_ms": "fast"}]})", "/stages/0/median_ms: expected a number"},
        {R"({"stages": [{"name": 3, "median_ms": 1}]})", "/stages/0/name: expected a string"},
        {R"({"stages": {"name": "count"}})", "/stages: expected an array"},
        {R"({"devices": [{"stages": [{"name": "x", "min_ms": null}]}]})", "/devices/0/stages/0/min_ms: expected a number"},
        {R"({"nothing": 1})", "no per-stage times"},
    };
    const fs::path good = dir / "good.json";
    test::write_text(good, R"({"stages": [{"name": "count", "median_ms": 1}]})");
    for (const auto& [text, expected] : cases) {
        test::write_text(dir / "bad.json", text);
        const CliRun r = sdfbrick("compare " + good.string() + " " + (dir / "bad.json").string());
        EXPECT_EQ(r.status, 2) << text << ": " << r.err;
        EXPECT_TRUE(one_clean_line(r));
        EXPECT_NE(r.err.find((dir / "bad.json").string() + ": " + expected), std::string::npos) << r.err;
    }
}

TEST(CliHardening, SweepFileValuesAreTypedStrictly) {
    const fs::path dir = test::temp_dir("cli_sweep_values");
    const std::pair<const char*, const char*> cases[] = {
        {R"("accuracy": "yes")", R"("accuracy" must be true or false)"},
        {R"("width": 1e30)", R"("width" must be a whole number in)"},
        {R"("width": 64.5)", R"("width" must be a whole number in)"},
        {R"("chunks": [32, 64.5])", R"("chunks" must be a whole number)"},
    };
    for (const auto& [value, expected] : cases) {
        test::write_text(dir / "s.json", fmt::format(R"({{"scenes": ["{}"], {}}})", scene_path("spheres"), value));
        const CliRun r = sdfbrick(fmt::format("sweep {} --out {}", (dir / "s.json").string(), (dir / "o").string()), device_env());
        EXPECT_EQ(r.status, 2) << value << ": " << r.err;
        EXPECT_TRUE(one_clean_line(r));
        EXPECT_NE(r.err.find(expected), std::string::npos) << r.err;
    }
}

TEST(CliHardening, TuneRefusesTheSettingsBuildRefuses) {
    const fs::path dir = test::temp_dir("cli_tune_checks");
    const fs::path db = dir / "tuning.json";
    for (const char* flag : {"--chunk 7", "--group 3"}) {
        const CliRun r = sdfbrick("tune " + scene_path("spheres") + " --brick-size 0.5 " + flag + " --tuning-db " + db.string(), device_env());
        EXPECT_EQ(r.status, 2) << flag << ": " << r.out << r.err;
        EXPECT_TRUE(one_clean_line(r));
        EXPECT_NE(r.err.find(std::string(flag).substr(0, 7)), std::string::npos) << r.err;
        EXPECT_FALSE(fs::exists(db));
    }
}

TEST(CliHardening, KernelBuildFailureSaysSoInItsFirstLine) {
    const fs::path dir = test::temp_dir("cli_kernel_build");
    fs::copy(fs::path(SDFBRICK_SOURCE_DIR) / "kernels", dir / "kernels");
    test::write_text(dir / "kernels" / "brick_count.cl", read_file(dir / "kernels" / "brick_count.cl") + "\nint broken( {\n");
    const CliRun r = sdfbrick("--kernel-dir " + (dir / "kernels").string() + " build " + scene_path("spheres") + " --brick-size 0.5",
                              device_env() + " SDFBRICK_CACHE_DIR=off");
    EXPECT_EQ(r.status, 1) << r.err;
    const std::string first = r.err.substr(0, r.err.find('\n'));
    EXPECT_EQ(first.rfind("sdfbrick: error: OpenCL error CL_BUILD_PROGRAM_FAILURE", 0), 0u) << r.err;
    EXPECT_NE(first.find("brick_count.cl:"), std::string::npos) << first;
}

TEST(CliHardening, NonFiniteOverflowingAndDuplicateValuesAreRefused) {
    const fs::path dir = test::temp_dir("cli_numbers");
    const std::string spheres = scene_path("spheres");
    for (const std::string& args : {"build " + spheres + " --time nan", "render " + spheres + " --time inf",
                                    "eval " + spheres + " --offset nan", "eval " + spheres + " --offset 1e999",
                                    "build " + spheres + " --brick-size -inf"}) {
        const CliRun r = sdfbrick(args, device_env());
        EXPECT_EQ(r.status, 2) << args;
        EXPECT_TRUE(one_clean_line(r)) << args;
    }
    const std::pair<std::string, std::string> scenes[] = {
        {R"({"primitive": "sphere", "radius": 1e308})", "/geometries/0/edits/0/radius: 1e+308 is out of range"},
        {R"({"primitive": "sphere", "radius": 1, "scale": 1e308})", "/geometries/0/edits/0/scale: 1e+308 is out of range"},
        {R"({"primitive": "sphere", "radius": 1, "blend": 1e308})", "/geometries/0/edits/0/blend: 1e+308 is out of range"},
        {R"({"primitive": "sphere", "radius": -1, "radius": 1})", "/geometries/0/edits/0/radius: duplicate key"},
    };
    for (const auto& [edit, expected] : scenes) {
        test::write_text(dir / "s.json", scene_with_edit(edit));
        const CliRun r = sdfbrick("scene info " + (dir / "s.json").string());
        EXPECT_EQ(r.status, 2) << edit;
        EXPECT_TRUE(one_clean_line(r));
        EXPECT_NE(r.err.find(expected), std::string::npos) << r.err;
    }
}

TEST(CliHardening, TinyBrickSizeIsPrintedWithItsDigits) {
    const CliRun r = sdfbrick("build " + scene_path("spheres") + " --brick-size 1e-9", device_env());
    EXPECT_EQ(r.status, 2);
    EXPECT_TRUE(one_clean_line(r));
    EXPECT_NE(r.err.find("1e-09"), std::string::npos) << r.err;
}

// Under a 2 GiB address-space limit a large build runs out of host memory: one line, no driver
// abort, no report. (Not in the sanitizer run: ASan needs far more address space than this.)
TEST(CliHardening, HostOutOfMemoryIsOneLineNotAnAbort) {
    const fs::path dir = test::temp_dir("cli_host_memory");
    const CliRun r = sdfbrick("build " + scene_path("drops") + " --brick-size 0.02 --json " + (dir / "r.json").string(),
                              "ulimit -v 2097152; " + device_env());
    EXPECT_TRUE(r.status == 1 || r.status == 2) << r.status << ": " << r.err;
    EXPECT_TRUE(one_clean_line(r));
    EXPECT_NE(r.err.find("the host cannot map that much more memory"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir / "r.json"));
}

// Two outputs of one command that name one file (the same path, or another path to it) are refused
// before any work: the second would silently replace the first.
TEST(CliHardening, TwoOutputsNamingOneFileAreRefused) {
    const fs::path dir = test::temp_dir("cli_same_output");
    const std::string spheres = scene_path("spheres") + " --brick-size 0.25";
    test::write_text(dir / "p.csv", "x,y,z\n0,0,0\n");
    const std::string cases[] = {
        "render " + spheres + " --width 32 --height 24 --out " + (dir / "a.ppm").string() + " --json " + (dir / "a.ppm").string(),
        "render " + spheres + " --width 32 --height 24 --out " + (dir / "a.ppm").string() + " --json " + (dir / "." / "a.ppm").string(),
        "sample " + spheres + " --points " + (dir / "p.csv").string() + " -o " + (dir / "s.csv").string() + " --json " +
            (dir / "s.csv").string(),
        "eval " + scene_path("spheres") + " --size 8 --out " + (dir / "e.ppm").string() + " --json " + (dir / "e.ppm").string()};
    for (const std::string& args : cases) {
        const CliRun r = sdfbrick(args, device_env());
        EXPECT_EQ(r.status, 2) << args << ": " << r.err;
        EXPECT_TRUE(one_clean_line(r)) << args;
        EXPECT_NE(r.err.find("named as two outputs"), std::string::npos) << r.err;
        EXPECT_TRUE(r.out.empty()) << r.out;
    }
    for (const char* f : {"a.ppm", "s.csv", "e.ppm"}) EXPECT_FALSE(fs::exists(dir / f)) << f;
}

// Every fault point gives one line, its documented exit status (1 for OpenCL failures, 2 for a
// failed write), and leaves no output file.
TEST(CliFault, EachPointGivesOneLineItsStatusAndNoOutput) {
    const fs::path dir = test::temp_dir("cli_fault");
    const std::pair<const char*, int> cases[] = {{"alloc:1", 1}, {"alloc:5", 1}, {"build:1", 1}, {"build:3", 1},
                                                 {"launch:1", 1}, {"launch:20", 1}, {"write:1", 2}, {"write:2", 2}};
    for (const auto& [fault, status] : cases) {
        const CliRun r = sdfbrick("render " + scene_path("spheres") + " --brick-size 0.25 --width 32 --height 24 --out " +
                                      (dir / "o.ppm").string() + " --json " + (dir / "r.json").string(),
                                  device_env() + " SDFBRICK_CACHE_DIR=off SDFBRICK_FAULT=" + fault);
        EXPECT_EQ(r.status, status) << fault << ": " << r.err;
        EXPECT_TRUE(one_clean_line(r)) << fault;
        EXPECT_NE(r.err.find("injected fault"), std::string::npos) << fault << ": " << r.err;
        EXPECT_TRUE(fs::is_empty(dir)) << fault << " left " << fs::directory_iterator(dir)->path();
    }
    const CliRun malformed = sdfbrick("scene generate spheres -o " + (dir / "s.json").string(), "SDFBRICK_FAULT=explode:1");
    EXPECT_EQ(malformed.status, 2);
    EXPECT_TRUE(one_clean_line(malformed));
}

}  // namespace
}  // namespace sdfbrick
