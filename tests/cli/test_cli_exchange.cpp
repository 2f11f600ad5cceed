// `sdfbrick export` and `sdfbrick sample` as a user meets them: files and reports written, bad
// input refused with one line and exit 2, nothing partial left behind.
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <string>
#include <tuple>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "core/files.h"
#include "exchange/vdb.h"
#include "cli/cli_run.h"
#include "test_support.h"

namespace sdfbrick {
namespace {

namespace fs = std::filesystem;

using Result = test::CliRun;

// The CLI on the test device.
Result sdfbrick(const std::string& args) {
    return test::sdfbrick(args, "SDFBRICK_DEVICE=" + test::test_device_spec());
}

const std::string kSpheres = std::string(SDFBRICK_SOURCE_DIR) + "/scenes/spheres.json";

TEST(CliExchange, ExportWritesTheFormatsBuiltInAndAReport) {
    const fs::path dir = test::temp_dir("cli_export");
    const bool openvdb = exchange::vdb_available(exchange::VdbFormat::openvdb);
    const bool nanovdb = exchange::vdb_available(exchange::VdbFormat::nanovdb);
    const std::string vdb = " --vdb " + (dir / "s.vdb").string(), nvdb = " --nvdb " + (dir / "s.nvdb").string();
    const Result r = sdfbrick("export " + kSpheres + " --brick-size 0.125" + (openvdb ? vdb : "") + (nanovdb ? nvdb : "") +
                                  " --json " + (dir / "r.json").string());
    if (!openvdb && !nanovdb) {
        EXPECT_EQ(r.status, 2);  // neither flag given
    } else {
        ASSERT_EQ(r.status, 0) << r.err;
        const auto j = nlohmann::json::parse(read_file(dir / "r.json"));
        EXPECT_GT(j["bricks"].get<int>(), 100);
        ASSERT_EQ(j["files"].size(), static_cast<std::size_t>(openvdb) + static_cast<std::size_t>(nanovdb));
        for (const auto& f : j["files"]) {
            EXPECT_EQ(f["file_bytes"].get<std::uint64_t>(), fs::file_size(f["path"].get<std::string>()));
            EXPECT_FALSE(f["grids"].empty());
        }
        EXPECT_NE(r.out.find("level set"), std::string::npos) << r.out;
    }
    // A format not built in is refused in one line naming its package, before any work.
    for (const auto& [available, flag, package] : {std::tuple(openvdb, vdb, "libopenvdb-dev"), std::tuple(nanovdb, nvdb, "libnanovdb-dev")}) {
        if (available) continue;
        const Result refused = sdfbrick("export " + kSpheres + flag);
        EXPECT_EQ(refused.status, 2);
        EXPECT_NE(refused.err.find(package), std::string::npos) << refused.err;
    }
}

TEST(CliExchange, SampleWritesDistancesAndRefusesBadPoints) {
    const fs::path dir = test::temp_dir("cli_sample");
    test::write_text(dir / "p.csv", "x,y,z\n0,0,0\n1,0,0\n50,50,50\n");
    const Result r = sdfbrick("sample " + kSpheres + " --brick-size 0.125 --points " + (dir / "p.csv").string() +
                                  " -o " + (dir / "out.csv").string());
    ASSERT_EQ(r.status, 0) << r.err;
    const std::string csv = read_file(dir / "out.csv");
    EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 4);
    EXPECT_NE(csv.find("\n50,50,50,,,,,-1,0,"), std::string::npos) << csv;

    test::write_text(dir / "bad.csv", "1,2,3\n4,5\n");
    const Result bad = sdfbrick("sample " + kSpheres + " --points " + (dir / "bad.csv").string() + " -o " +
                                    (dir / "bad-out.csv").string());
    EXPECT_EQ(bad.status, 2);
    EXPECT_NE(bad.err.find("bad.csv: line 2"), std::string::npos) << bad.err;
    EXPECT_EQ(std::count(bad.err.begin(), bad.err.end(), '\n'), 1) << bad.err;
    EXPECT_FALSE(fs::exists(dir / "bad-out.csv"));
    // A first line of numbers that do not parse is an error, not a header taken silently.
    test::write_text(dir / "range.csv", "1e400,0,0\n1,2,3\n");
    const Result range = sdfbrick("sample " + kSpheres + " --points " + (dir / "range.csv").string() + " -o " +
                                  (dir / "range-out.csv").string());
    EXPECT_EQ(range.status, 2);
    EXPECT_NE(range.err.find("range.csv: line 1"), std::string::npos) << range.err;
    EXPECT_FALSE(fs::exists(dir / "range-out.csv"));
    EXPECT_EQ(sdfbrick("export " + kSpheres).status, 2);  // no output named
}

}  // namespace
}  // namespace sdfbrick
