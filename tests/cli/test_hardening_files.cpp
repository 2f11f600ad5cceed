// The command line against hostile and failing file systems: a full file system mid-write, a signal
// mid-write, a later output failing after earlier ones were made, pictures into an unusable folder,
// kernel sources that are endless or blocking, journals through links, meshes outside the scene's
// folder, merged shards that lie about themselves, exports of nothing and exports too large for the
// host. Each gives one line, its exit status, and leaves nothing behind.
#include <sys/stat.h>

#include <chrono>
#include <filesystem>
#include <string>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "cli/cli_run.h"
#include "core/files.h"
#include "scene/mesh.h"
#include "test_support.h"

namespace sdfbrick {
namespace {

namespace fs = std::filesystem;
using test::CliRun;
using test::scene_path;
using test::device_env;
using test::sdfbrick;

std::size_t entries(const fs::path& dir) {
    std::size_t n = 0;
    for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir)) ++n;
    return n;
}

const std::string kSpheres = scene_path("spheres") + " --brick-size 0.25";

// A file system that fills up mid-write (a file size limit: writes fail with EFBIG, the signal
// ignored): the output is refused with exit 2 and nothing, not even a truncated file, is left. The
// same command runs once unlimited first, which also warms the device compiler's caches (so that
// only the output's own writes meet the limit), and gives the output's size.
TEST(CliHardening, AFullFileSystemLeavesNoTruncatedOutput) {
    const fs::path dir = test::temp_dir("cli_full_fs");
    const std::string cases[] = {"render " + kSpheres + " --width 256 --height 192 --out " + (dir / "o.png").string(),
                                 "export " + kSpheres + " --vdb " + (dir / "o.vdb").string()};
    for (const std::string& args : cases) {
        const CliRun whole = sdfbrick(args, device_env());
        ASSERT_EQ(whole.status, 0) << args << ": " << whole.err;
        ASSERT_EQ(entries(dir), 1u);
        const fs::path out = fs::directory_iterator(dir)->path();
        const std::uintmax_t size = fs::file_size(out);
        fs::remove(out);
        const std::uintmax_t blocks = size / 512 / 2;  // the shell's ulimit -f counts 512-byte blocks
        ASSERT_GE(blocks, 1u) << out << " holds only " << size << " bytes";
        const CliRun full = sdfbrick(args, fmt::format("trap '' XFSZ; ulimit -f {}; {}", blocks, device_env()));
        EXPECT_EQ(full.status, 2) << args << ": " << full.err;
        EXPECT_TRUE(test::one_clean_line(full)) << args;
        EXPECT_NE(full.err.find("write failed"), std::string::npos) << full.err;
        EXPECT_EQ(entries(dir), 0u) << args << " left " << fs::directory_iterator(dir)->path();
    }
}

// SIGTERM while an output is written (once its temporary file holds the bytes): the process ends by
// the signal and no temporary file is left.
TEST(CliHardening, ASignalMidWriteLeavesNoTemporaryFile) {
    const fs::path dir = test::temp_dir("cli_signal");
    const CliRun r = sdfbrick("render " + kSpheres + " --width 32 --height 24 --out " + (dir / "o.ppm").string() +
                                  " --json " + (dir / "r.json").string(),
                              device_env() + " SDFBRICK_FAULT=signal:1");
    EXPECT_EQ(r.status, 128 + 15) << r.err;  // the shell's status of a child ended by SIGTERM
    EXPECT_EQ(entries(dir), 0u) << "left " << fs::directory_iterator(dir)->path();
}

// export writes its files as one: a failing later file leaves none of the earlier ones.
TEST(CliHardening, ExportWritesAllItsFilesOrNone) {
    const fs::path dir = test::temp_dir("cli_export_all");
    const std::string args = "export " + kSpheres + " --vdb " + (dir / "a.vdb").string() + " --nvdb " +
                             (dir / "a.nvdb").string() + " --json " + (dir / "r.json").string();
    for (const char* fault : {"write:2", "write:3"}) {
        const CliRun r = sdfbrick(args, device_env() + " SDFBRICK_FAULT=" + fault);
        EXPECT_EQ(r.status, 2) << fault << ": " << r.err;
        EXPECT_TRUE(test::one_clean_line(r)) << fault;
        EXPECT_EQ(entries(dir), 0u) << fault << " left " << fs::directory_iterator(dir)->path();
    }
    const CliRun r = sdfbrick(args, device_env());
    EXPECT_EQ(r.status, 0) << r.err;
    EXPECT_EQ(entries(dir), 3u);
}

// A scene whose geometry has no surface: export refuses it (no grid to write) with exit 2 and
// writes nothing.
TEST(CliHardening, ExportOfNoBricksIsRefusedAndWritesNothing) {
    const fs::path dir = test::temp_dir("cli_export_empty");
    test::write_text(dir / "empty.json",
                     R"({"geometries": [{"name": "g", "edits": [{"primitive": "sphere", "radius": 0.5, "op": "subtract"}]}]})");
    const CliRun r = sdfbrick("export " + (dir / "empty.json").string() + " --brick-size 0.25 --vdb " +
                                  (dir / "e.vdb").string() + " --json " + (dir / "e.json").string(),
                              device_env());
    EXPECT_EQ(r.status, 2) << r.err;
    EXPECT_TRUE(test::one_clean_line(r));
    EXPECT_NE(r.err.find("nothing to write: no object"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir / "e.vdb"));
    EXPECT_FALSE(fs::exists(dir / "e.json"));
}

// An export whose leaves cannot fit in the host's memory is refused while the levels are counted,
// before the leaves are made, with the figure (here: an address-space limit of 1.5 GiB, and bricks
// of drops far smaller than it can hold).
TEST(CliHardening, ExportTooLargeForTheHostIsRefusedBeforeItsLeaves) {
    const fs::path dir = test::temp_dir("cli_export_memory");
    const auto start = std::chrono::steady_clock::now();
    const CliRun r = sdfbrick("export " + scene_path("drops") + " --brick-size 0.004 --vdb " + (dir / "d.vdb").string(),
                              "ulimit -v 1572864; " + device_env());
    EXPECT_EQ(r.status, 2) << r.err;
    EXPECT_TRUE(test::one_clean_line(r));
    EXPECT_NE(r.err.find("bytes of host memory"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("use a larger"), std::string::npos) << r.err;
    EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(120));
    EXPECT_EQ(entries(dir), 0u);
}

// Pictures into a folder that cannot be made: refused before any work, one line naming it; a write
// that fails after the folder was made takes the folder away again.
TEST(CliHardening, StabilityPicturesIntoAnUnusableFolderLeaveNothing) {
    const fs::path dir = test::temp_dir("cli_stability_folder");
    test::write_text(dir / "file", "x");
    const std::string args = scene_path("stability/grazing_plane") +
                             " --brick-size 0.25 --methods sphere --normals central --formats int8 --builds uniform "
                             "--width 16 --height 12 --pictures ";
    const CliRun under_file = sdfbrick("stability " + args + (dir / "file" / "pics").string(), device_env());
    EXPECT_EQ(under_file.status, 2) << under_file.err;
    EXPECT_TRUE(test::one_clean_line(under_file));
    EXPECT_NE(under_file.err.find("cannot write pictures here"), std::string::npos) << under_file.err;
    const CliRun failing = sdfbrick("stability " + args + (dir / "pics").string(), device_env() + " SDFBRICK_FAULT=write:2");
    EXPECT_EQ(failing.status, 2) << failing.err;
    EXPECT_TRUE(test::one_clean_line(failing));
    EXPECT_FALSE(fs::exists(dir / "pics"));
    EXPECT_EQ(entries(dir), 1u);
}

// Kernel sources from --kernel-dir are read as other inputs are: an endless device or a FIFO is
// refused by kind at once (no reading until memory runs out, no waiting for a writer).
TEST(CliHardening, KernelSourcesThatAreSpecialFilesAreRefused) {
    const fs::path dir = test::temp_dir("cli_kernel_dir");
    for (const char* kind : {"zero", "fifo"}) {
        const fs::path kernels = dir / kind;
        fs::create_directories(kernels);
        for (const auto& e : fs::directory_iterator(fs::path(SDFBRICK_SOURCE_DIR) / "kernels")) {
            const fs::path to = kernels / e.path().filename();
            if (e.path().extension() != ".cl") fs::copy_file(e.path(), to);
            else if (std::string(kind) == "zero") fs::create_symlink("/dev/zero", to);
            else ASSERT_EQ(::mkfifo(to.c_str(), 0600), 0);
        }
        const auto start = std::chrono::steady_clock::now();
        const CliRun r = sdfbrick("--kernel-dir " + kernels.string() + " eval " + scene_path("spheres") + " --size 8",
                                  device_env() + " SDFBRICK_CACHE_DIR=off");
        EXPECT_EQ(r.status, 2) << kind << ": " << r.err;
        EXPECT_TRUE(test::one_clean_line(r)) << kind;
        EXPECT_NE(r.err.find("not a regular file"), std::string::npos) << kind << ": " << r.err;
        EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(60)) << kind;
    }
}

// The sweep's cache is a journal: a link planted at its path is refused, its target left alone.
TEST(CliHardening, SweepCacheThroughALinkIsRefused) {
    const fs::path dir = test::temp_dir("cli_sweep_cache_link");
    test::write_text(dir / "victim", "precious\n");
    fs::create_symlink(dir / "victim", dir / "s.cache.jsonl");
    const CliRun r = sdfbrick("sweep --scenes " + scene_path("spheres") +
                                  " --brick-sizes 0.25 --no-accuracy --warmup 0 --repeat 1 --width 16 --height 12 --out " +
                                  (dir / "s").string(),
                              device_env());
    EXPECT_EQ(r.status, 2) << r.err;
    EXPECT_TRUE(test::one_clean_line(r));
    EXPECT_NE(r.err.find("a symbolic link"), std::string::npos) << r.err;
    EXPECT_EQ(read_file(dir / "victim"), "precious\n");
    EXPECT_FALSE(fs::exists(dir / "s.csv"));
}

// A scene reads meshes only from its own folder unless --allow-outside names another.
TEST(CliHardening, MeshesOutsideTheScenesFolderNeedAllowOutside) {
    const fs::path dir = test::temp_dir("cli_mesh_outside");
    fs::create_directories(dir / "scene");
    fs::create_directories(dir / "meshes");
    write_obj(icosphere(0.5, 1), dir / "meshes" / "ball.obj");
    test::write_text(dir / "scene" / "s.json",
                     R"({"geometries": [{"name": "g", "edits": [{"primitive": "mesh", "file": "../meshes/ball.obj", "resolution": 8}]}]})");
    const CliRun refused = sdfbrick("scene info " + (dir / "scene" / "s.json").string());
    EXPECT_EQ(refused.status, 2) << refused.err;
    EXPECT_TRUE(test::one_clean_line(refused));
    EXPECT_NE(refused.err.find("/geometries/0/edits/0/file: "), std::string::npos) << refused.err;
    EXPECT_NE(refused.err.find("outside the scene's folder"), std::string::npos) << refused.err;
    const CliRun allowed = sdfbrick("--allow-outside " + (dir / "meshes").string() + " scene info " + (dir / "scene" / "s.json").string());
    EXPECT_EQ(allowed.status, 0) << allowed.err;
    const CliRun not_a_folder = sdfbrick("--allow-outside " + (dir / "nothing").string() + " scene info " + (dir / "scene" / "s.json").string());
    EXPECT_EQ(not_a_folder.status, 2) << not_a_folder.err;
    EXPECT_TRUE(test::one_clean_line(not_a_folder));
}

// merge checks what it reads: points must be row objects of typed fields, shard index and count
// non-negative integers with index < count. Each refusal names the file and the JSON path.
TEST(CliHardening, MergeRefusesShardsThatLieAboutThemselves) {
    const fs::path dir = test::temp_dir("cli_merge_lies");
    const auto doc = [](const std::string& shard, const std::string& points) {
        return R"({"command": "sweep", "spec": {}, "grid_points": 3, "shard": )" + shard + R"(, "points": )" + points + "}";
    };
    const std::pair<std::string, std::string> cases[] = {
        {doc(R"({"index": 0, "count": 1})", "[1, 2, 3]"), "/points/0: expected a row object"},
        {doc(R"({"index": -1, "count": 1})", "[]"), "/shard/index: expected a non-negative integer"},
        {doc(R"({"index": 1e18, "count": 1})", "[]"), "/shard/index: expected a non-negative integer"},
        {doc(R"({"index": 0.5, "count": 1})", "[]"), "/shard/index: expected a non-negative integer"},
        {doc(R"({"index": 3, "count": 2})", "[]"), "/shard: index 3 of 2 shards is out of range"},
        {doc(R"({"index": 0, "count": 1})", R"([{"index": "x"}])"), "/points/0/index: expected an integer"},
        {doc(R"({"index": 0, "count": 1})", R"([{"index": 1, "scene": 7}])"), "/points/0/scene: expected a string"},
        {doc(R"("zero")", "[]"), "/shard: expected an object"},
    };
    for (const auto& [text, expected] : cases) {
        test::write_text(dir / "in.json", text);
        const CliRun r = sdfbrick("merge " + (dir / "in.json").string() + " --out " + (dir / "m").string());
        EXPECT_EQ(r.status, 2) << text << ": " << r.err;
        EXPECT_TRUE(test::one_clean_line(r)) << text;
        EXPECT_NE(r.err.find((dir / "in.json").string() + ": " + expected), std::string::npos) << text << ": " << r.err;
        EXPECT_FALSE(fs::exists(dir / "m.csv"));
    }
}

}  // namespace
}  // namespace sdfbrick
