// `sdfbrick compare --gate` through the command line: a real regression on the test device (culling
// off keeps the digest and grows the edit evaluations) exits 3 with every output written, the same
// build twice exits 0, and bad input exits 2 with one line and no output.
#include <filesystem>
#include <string>

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
using test::sdfbrick;

TEST(CliGate, ARealRegressionExitsThreeAndTheSameBuildTwicePasses) {
    const fs::path dir = test::temp_dir("cli_gate_real");
    const std::string env = test::device_env();
    const auto build = [&](const std::string& name, const std::string& flags) {
        const CliRun r = sdfbrick("build " + scene_path("spheres") + flags + " --json " + (dir / name).string(), env);
        ASSERT_EQ(r.status, 0) << r.err;
    };
    build("a.json", "");
    build("b.json", "");
    build("off.json", " --no-cull");
    const std::string a = (dir / "a.json").string(), b = (dir / "b.json").string(), off = (dir / "off.json").string();
    const std::string outputs = " --summary " + (dir / "s.md").string() + " --junit " + (dir / "j.xml").string() +
                                " --json " + (dir / "v.json").string();

    const CliRun same = sdfbrick("compare " + a + " " + b + " --gate default" + outputs);
    ASSERT_EQ(same.status, 0) << same.err << same.out;
    EXPECT_NE(same.out.find("## sdfbrick compare --gate: PASS"), std::string::npos) << same.out;
    EXPECT_EQ(read_file(dir / "s.md"), same.out);
    EXPECT_TRUE(nlohmann::json::parse(read_file(dir / "v.json"))["passed"].get<bool>());

    const CliRun regressed = sdfbrick("compare " + a + " " + off + " --gate default" + outputs);
    ASSERT_EQ(regressed.status, 3) << regressed.err << regressed.out;
    EXPECT_TRUE(test::one_clean_line(regressed));
    EXPECT_NE(regressed.err.find("sdfbrick: gate: FAIL: "), std::string::npos) << regressed.err;
    EXPECT_NE(regressed.err.find("edit_evaluations"), std::string::npos) << regressed.err;
    EXPECT_NE(read_file(dir / "s.md").find("| counters | `/edit_evaluations` |"), std::string::npos);
    EXPECT_NE(read_file(dir / "s.md").find("settings/cull true -> false (a work setting"), std::string::npos);
    EXPECT_NE(read_file(dir / "j.xml").find("<failure type=\"regression\""), std::string::npos);
    const auto verdict = nlohmann::json::parse(read_file(dir / "v.json"));
    EXPECT_FALSE(verdict["passed"].get<bool>());
    bool digest_kept = false;
    for (const auto& c : verdict["checks"]) digest_kept |= c["figure"] == "/digest" && c["outcome"] == "pass" && c["base"] == c["new"];
    EXPECT_TRUE(digest_kept) << "culling changes no bit of the output";

    // Without --gate, compare prints the per-stage deltas as before and exits 0.
    const CliRun deltas = sdfbrick("compare " + a + " " + off);
    EXPECT_EQ(deltas.status, 0) << deltas.err;
    EXPECT_NE(deltas.out.find("stage(s) changed"), std::string::npos) << deltas.out;
}

TEST(CliGate, BadInputExitsTwoWithOneLineAndNoOutput) {
    const fs::path dir = test::temp_dir("cli_gate_bad");
    const nlohmann::json report = {{"command", "build"},
                                   {"scene", {{"name", "spheres"}, {"time", 0.0}}},
                                   {"settings", {{"brick_size", 0.0625}}},
                                   {"digest", "fd3bb34f812387af"},
                                   {"bricks", 8568}};
    nlohmann::json drops = report;
    drops["scene"]["name"] = "drops";
    test::write_text(dir / "a.json", report.dump());
    test::write_text(dir / "drops.json", drops.dump());
    test::write_text(dir / "broken.json", "{\"bricks\": ");
    const std::string a = (dir / "a.json").string(), summary = (dir / "out" / "s.md").string();
    fs::create_directories(dir / "out");
    const std::pair<std::string, std::string> cases[] = {
        {"compare " + a + " " + a + " --gate 'countrs<=2%'", "--gate: gate rule \"countrs<=2%\": unknown rule"},
        {"compare " + a + " " + a + " --gate ''", "--gate: gate rules: empty"},
        {"compare " + a + " " + (dir / "drops.json").string() + " --gate default", "reports of different runs: scene/name spheres -> drops"},
        {"compare " + a + " " + a + " --gate mismatch", "/accuracy/mismatch_fraction: missing (rule mismatch needs it"},
        {"compare " + a + " " + a + " --gate time", "/captures/repeat: one capture"},
        {"compare " + a + " " + (dir / "broken.json").string() + " --gate default", "broken.json"},
        {"compare " + a + " " + a + " --summary " + summary, "--summary requires --gate"},
        {"compare " + a + " " + a + " --allow-different", "--allow-different requires --gate"},
        // Outputs are checked before any report is read: the broken report is not reached.
        {"compare " + a + " " + (dir / "broken.json").string() + " --gate default --summary " + (dir / "no" / "s.md").string(), "no/s.md"},
        {"compare " + a + " " + a + " --gate default --summary " + summary + " --json " + summary, "s.md"},
    };
    for (const auto& [args, message] : cases) {
        const CliRun run = sdfbrick(args);
        EXPECT_EQ(run.status, 2) << args << "\n" << run.err << run.out;
        EXPECT_TRUE(test::one_clean_line(run)) << args;
        EXPECT_NE(run.err.find(message), std::string::npos) << args << "\n" << run.err;
        EXPECT_TRUE(fs::is_empty(dir / "out")) << args;
    }
    // Allowed, the different scenes are gated (and noted).
    const CliRun allowed = sdfbrick("compare " + a + " " + (dir / "drops.json").string() + " --gate default --allow-different");
    EXPECT_EQ(allowed.status, 0) << allowed.err;
    EXPECT_NE(allowed.out.find("scene/name spheres -> drops (a different run"), std::string::npos) << allowed.out;
}

}  // namespace
}  // namespace sdfbrick
