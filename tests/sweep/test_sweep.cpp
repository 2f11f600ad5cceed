// Sweep grid expansion, keys, sharding, the resume cache, CSV and merging shards (host only), and
// one small sweep on the test device.
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <set>

#include <gtest/gtest.h>

#include "core/errors.h"
#include "core/files.h"
#include "sweep/grid.h"
#include "sweep/runner.h"
#include "test_support.h"
#include "tune/kernels.h"
#include "tune/tuning_db.h"

namespace sdfbrick {
namespace {

sweep::SweepSpec small_spec() {
    sweep::SweepSpec s;
    s.scenes = {"a.json", "b.json"};
    s.brick_sizes = {0.5, 0.25, 0.125};
    s.chunks = {16, 64};
    s.culls = {true, false};
    return s;
}

// Tolerances are an axis after brick sizes; 0 is the uniform build, whose key is the one it had
// before the axis existed (resume caches and merges keep matching).
TEST(Sweep, TolerancesAreAnAxis) {
    sweep::SweepSpec s;
    s.scenes = {"a.json"};
    s.brick_sizes = {0.25, 0.125};
    s.tolerances = {0.0, 0.01};
    const auto points = sweep::expand(s, {"cpu"});
    ASSERT_EQ(points.size(), 4u);
    EXPECT_EQ(points[0].tolerance, 0.0);
    EXPECT_EQ(points[1].tolerance, 0.01);
    EXPECT_EQ(points[0].key(s).find("tolerance"), std::string::npos);
    EXPECT_NE(points[1].key(s).find(";tolerance=0.01"), std::string::npos);
    s.tolerances = {-1.0};
    try {
        s.validate();
        ADD_FAILURE() << "a negative tolerance was accepted";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("tolerances"), std::string::npos) << e.what();
    }
}

TEST(Sweep, GridExpandsEveryCombinationOnce) {
    const sweep::SweepSpec s = small_spec();
    const auto points = sweep::expand(s, {"gpu", "cpu"});
    ASSERT_EQ(points.size(), 2u * 2 * 3 * 2 * 2);
    EXPECT_EQ(s.size_per_device(), 24u);
    std::set<std::string> keys;
    for (std::size_t i = 0; i < points.size(); ++i) {
        EXPECT_EQ(points[i].index, i);
        keys.insert(points[i].key(s));
    }
    EXPECT_EQ(keys.size(), points.size()) << "every point has its own key";
    // Devices outermost, then scenes, brick sizes, chunks, culling (innermost of the given ones).
    EXPECT_EQ(points[0].device, "gpu");
    EXPECT_EQ(points[24].device, "cpu");
    EXPECT_EQ(points[0].scene, "a.json");
    EXPECT_EQ(points[12].scene, "b.json");
    EXPECT_EQ(points[0].brick_size, 0.5);
    EXPECT_EQ(points[4].brick_size, 0.25);
    EXPECT_EQ(points[0].chunk, 16);
    EXPECT_EQ(points[2].chunk, 64);
    EXPECT_TRUE(points[0].cull);
    EXPECT_FALSE(points[1].cull);
    // Dimensions not given take one default value: "auto" for the tuned ones.
    EXPECT_FALSE(points[0].group.has_value());
    EXPECT_FALSE(points[0].trace_group.has_value());
    EXPECT_EQ(points[0].format, "int8");
    EXPECT_EQ(points[0].method, "sphere");
    EXPECT_NE(points[0].key(s).find("group=auto"), std::string::npos);
}

TEST(Sweep, KeyChangesWithEverythingThatChangesResults) {
    sweep::SweepSpec s = small_spec();
    const sweep::SweepPoint p = sweep::expand(s, {"dev"}).front();
    const std::string key = p.key(s);
    sweep::SweepSpec other = s;
    other.width = 320;
    EXPECT_NE(p.key(other), key);
    other = s;
    other.repeat = 5;
    EXPECT_NE(p.key(other), key);
    sweep::SweepPoint q = p;
    q.normals = "tetra";
    EXPECT_NE(q.key(s), key);
    q = p;
    q.index = 99;  // the position in the grid is not a parameter
    EXPECT_EQ(q.key(s), key);
}

TEST(Sweep, BadSpecsAreRefusedByName) {
    sweep::SweepSpec s = small_spec();
    s.chunks = {8};
    EXPECT_THROW(
        try { s.validate(); } catch (const InputError& e) {
            EXPECT_NE(std::string(e.what()).find("chunks"), std::string::npos) << e.what();
            throw;
        },
        InputError);
    s = small_spec();
    s.trace_groups = {"16by8"};
    EXPECT_THROW(s.validate(), InputError);
    s = small_spec();
    s.scenes.clear();
    EXPECT_THROW(s.validate(), InputError);
    EXPECT_THROW(sweep::spec_from_json({{"scenes", {"a.json"}}, {"chunk", {16}}}, "f.json"), InputError)
        << "a misspelt key is refused";
    EXPECT_THROW(sweep::spec_from_json({{"scenes", {"a.json"}}, {"chunks", "many"}}, "f.json"), InputError);
    EXPECT_THROW(sweep::expand(small_spec(), {"d"}, 10), InputError) << "over the point limit";
    // Four lists of 65,536 values: 2^64 points, which a plain product wraps to 0 ("empty").
    s = small_spec();
    s.brick_sizes.assign(65536, 0.5);
    s.tolerances.assign(65536, 0.0);
    s.chunks.assign(65536, 16);
    s.groups.assign(65536, 64);
    try {
        sweep::expand(s, {"d"});
        ADD_FAILURE() << "a grid of 2^64 points was accepted";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("more than 1000000"), std::string::npos) << e.what();
    }
}

TEST(Sweep, SpecFromJsonAcceptsValuesAndLists) {
    const sweep::SweepSpec s = sweep::spec_from_json(
        {{"scenes", "a.json"}, {"brick_sizes", {0.5, 0.25}}, {"cull", {true, false}}, {"trace_groups", "8x8"},
         {"width", 64}, {"height", 32}, {"repeat", 2}, {"accuracy", false}},
        "f.json");
    EXPECT_EQ(s.scenes, std::vector<std::string>{"a.json"});
    EXPECT_EQ(s.brick_sizes.size(), 2u);
    EXPECT_EQ(s.culls, (std::vector<bool>{true, false}));
    EXPECT_EQ(s.trace_groups, std::vector<std::string>{"8x8"});
    EXPECT_EQ(s.width, 64);
    EXPECT_FALSE(s.accuracy);
    EXPECT_EQ(sweep::spec_from_json(sweep::to_json(s), "round trip").size_per_device(), s.size_per_device());
}

TEST(Sweep, ShardsPartitionTheGrid) {
    const auto points = sweep::expand(small_spec(), {"gpu"});
    for (std::size_t n : {1u, 2u, 3u, 5u, 24u, 30u}) {
        std::vector<std::size_t> seen;
        for (std::size_t i = 0; i < n; ++i)
            for (const auto& p : sweep::shard_points(points, {i, n})) seen.push_back(p.index);
        std::sort(seen.begin(), seen.end());
        ASSERT_EQ(seen.size(), points.size()) << n << " shards";
        for (std::size_t i = 0; i < seen.size(); ++i) EXPECT_EQ(seen[i], i) << n << " shards";
    }
    const auto shard = sweep::parse_shard("1/4");
    EXPECT_EQ(shard.index, 1u);
    EXPECT_EQ(shard.count, 4u);
    for (const char* bad : {"4/4", "1/0", "a/b", "1", "-1/3", "1/3x"}) EXPECT_THROW(sweep::parse_shard(bad), InputError) << bad;
}

// A fake finished row for a point (what run_points would record).
sweep::SweepRow fake_row(const sweep::SweepSpec& s, const sweep::SweepPoint& p) {
    sweep::SweepRow r;
    r.index = p.index;
    r.key = p.key(s);
    r.scene = p.scene;
    r.status = "ok";
    r.results.emplace().build_ms.median = 1.0 + static_cast<double>(p.index);
    return r;
}

// A row with results: build time only.
sweep::SweepRow build_ms_row(double ms) {
    sweep::SweepRow r;
    r.results.emplace().build_ms.median = ms;
    return r;
}

TEST(Sweep, MergeJoinsShardsAndReportsWhatIsMissing) {
    const sweep::SweepSpec s = small_spec();
    const auto grid = sweep::expand(s, {"gpu"});
    std::vector<nlohmann::json> docs;
    for (std::size_t i = 0; i < 3; ++i) {
        std::vector<sweep::SweepRow> rows;
        for (const auto& p : sweep::shard_points(grid, {i, 3})) rows.push_back(fake_row(s, p));
        docs.push_back(sweep::sweep_document(s, {i, 3}, grid.size(), rows));
    }
    const sweep::Merged all = sweep::merge({docs[2], docs[0], docs[1]}, {"c", "a", "b"});
    EXPECT_TRUE(all.complete);
    EXPECT_TRUE(all.notes.empty());
    ASSERT_EQ(all.rows.size(), grid.size());
    for (std::size_t i = 0; i < grid.size(); ++i) EXPECT_EQ(all.rows[i].index, i) << "rows back in grid order";

    const sweep::Merged part = sweep::merge({docs[0], docs[2]}, {"a", "c"});
    EXPECT_FALSE(part.complete);
    EXPECT_TRUE(std::any_of(part.notes.begin(), part.notes.end(), [](const std::string& n) { return n.find("shard 1/3 is missing") != std::string::npos; }));

    const sweep::Merged twice = sweep::merge({docs[0], docs[0], docs[1], docs[2]}, {"a", "a2", "b", "c"});
    EXPECT_EQ(twice.rows.size(), grid.size()) << "duplicates are merged once";
    EXPECT_FALSE(twice.notes.empty());

    sweep::SweepSpec other = s;
    other.width = 99;
    const sweep::Merged mixed = sweep::merge({docs[0], sweep::sweep_document(other, {}, 1, {})}, {"a", "other"});
    EXPECT_FALSE(mixed.complete);
    EXPECT_THROW(sweep::merge({nlohmann::json{{"command", "build"}}}, {"x.json"}), InputError);
}

TEST(Sweep, CsvHasEveryColumnAndQuotesText) {
    sweep::SweepRow r;
    r.scene = "drops";
    r.status = "error";
    r.error = "bad, \"quoted\"\nline";
    r.cull = true;
    r.brick_size = 0.125;
    const std::string csv = sweep::to_csv({r});
    const std::string header = csv.substr(0, csv.find('\n'));
    EXPECT_EQ(std::count(header.begin(), header.end(), ',') + 1, static_cast<long>(sweep::csv_columns().size()));
    EXPECT_NE(csv.find("\"bad, \"\"quoted\"\"\nline\""), std::string::npos) << csv;
    EXPECT_NE(csv.find(",0.125,"), std::string::npos) << csv;
    const std::string row = csv.substr(csv.find('\n') + 1);
    EXPECT_NE(row.find("drops"), std::string::npos);
}

// The CSV header is the column list, in the order the sweep has always written (tools/sweep_charts.py
// and docs/sweep.md read it); the JSON-only key is not a CSV column.
TEST(Sweep, CsvHeaderIsTheColumnList) {
    const std::vector<std::string> names = sweep::csv_columns();
    std::string joined;
    for (const std::string& n : names) joined += (joined.empty() ? "" : ",") + n;
    const std::string csv = sweep::to_csv({});
    EXPECT_EQ(csv, joined + "\n");
    EXPECT_EQ(joined,
              "index,scene,scene_file,device,vendor,driver,platform,brick_size,tolerance,chunk,group,trace_group,cull,"
              "format,samples,method,normals,width,height,status,error,repeats,identical,bricks,pool_bytes,"
              "check_error_max,levels,edit_evaluations,"
              "memory_bytes,build_ms,build_min_ms,build_max_ms,build_cv,trace_ms,trace_min_ms,trace_max_ms,trace_cv,"
              "bvh_ms,stage_edit_bounds_ms,stage_dependencies_ms,stage_count_ms,stage_scan_ms,stage_subdivide_ms,"
              "stage_cull_ms,stage_check_ms,stage_order_ms,stage_apron_ms,stage_evaluate_ms,stage_aabb_ms,evaluate_local_bytes,"
              "evaluate_registers,"
              "evaluate_groups_per_cu,evaluate_resident_groups,evaluate_occupancy,evaluate_waves,"
              "evaluations_per_second,write_gbps,bandwidth_fraction,peak_bandwidth_gbps,peak_fma_gflops,mismatch,"
              "depth_mean,depth_p99,normal_mean,normal_p99,psnr");
    std::vector<std::string> all;
    for (const sweep::Column& c : sweep::columns()) all.push_back(c.name);
    EXPECT_EQ(all.size(), names.size() + 1);
    EXPECT_EQ(all.back(), "key");
}

// A row goes to JSON and back unchanged; parts a row lacks leave their keys out, unknown values are null.
TEST(Sweep, RowsReadBackFromTheirJson) {
    sweep::SweepRow ok;
    ok.index = 7;
    ok.scene = "drops";
    ok.chunk = 32;
    ok.trace_group = "16x8";
    ok.key = "k";
    sweep::PointResults& r = ok.results.emplace();
    r.bricks = 1234;
    r.build_ms.median = 2.5;
    r.build_ms.cv = 0.01;
    r.stage_ms.back() = 0.25;
    r.evaluate = sweep::EvaluateOccupancy{4096, std::nullopt, 3, std::nullopt, std::nullopt, 1.5};
    r.accuracy = sweep::PointAccuracy{0.001, 0.05, 0.2, 0.9, 3.5, std::nullopt};
    const nlohmann::json j = sweep::to_json(ok);
    EXPECT_EQ(j["bricks"], 1234);
    EXPECT_EQ(j["build_ms"], 2.5);
    EXPECT_EQ(j["stage_aabb_ms"], 0.25);
    EXPECT_EQ(j["evaluate_groups_per_cu"], 3);
    EXPECT_TRUE(j["evaluate_registers"].is_null());
    EXPECT_TRUE(j["psnr"].is_null());
    EXPECT_TRUE(j["group"].is_null()) << "auto";
    EXPECT_FALSE(j.contains("error"));
    EXPECT_FALSE(j.contains("write_gbps")) << "no write bandwidth measured";
    EXPECT_EQ(sweep::to_json(sweep::row_from_json(j)), j);
    EXPECT_EQ(sweep::to_csv({sweep::row_from_json(j)}), sweep::to_csv({ok}));

    sweep::SweepRow failed;
    failed.status = "error";
    failed.error = "no device";
    const nlohmann::json e = sweep::to_json(failed);
    EXPECT_EQ(e["error"], "no device");
    for (const char* key : {"identical", "bricks", "build_ms", "mismatch"}) EXPECT_FALSE(e.contains(key)) << key;
    EXPECT_FALSE(sweep::row_from_json(e).results.has_value());
}

TEST(Sweep, CacheResumesAndSurvivesACutLine) {
    const std::filesystem::path path = test::temp_dir("sweep") / "cache.jsonl";
    std::filesystem::remove(path);
    {
        sweep::ResultCache cache(path);
        cache.add("k1", build_ms_row(1.5));
        cache.add("k2", build_ms_row(2.5));
    }
    {
        std::ofstream out(path, std::ios::app);
        out << "{\"key\": \"k3\", \"row\": {\"bui";  // a run killed mid-write
    }
    {
        sweep::ResultCache again(path);
        EXPECT_EQ(again.size(), 2u);
        ASSERT_NE(again.find("k2"), nullptr);
        EXPECT_EQ(again.find("k2")->results->build_ms.median, 2.5);
        EXPECT_EQ(again.find("k3"), nullptr);
        again.add("k3", build_ms_row(3.5));  // the point that was cut short, run again
    }
    sweep::ResultCache third(path);
    EXPECT_EQ(third.size(), 3u) << "a line appended after a cut line is not lost";
}

TEST(Sweep, CacheWithoutAPathStaysInMemory) {
    const std::filesystem::path dir = test::temp_dir("sweep-memory");
    const std::filesystem::path before = std::filesystem::current_path();
    std::filesystem::current_path(dir);
    {
        sweep::ResultCache cache{std::filesystem::path()};
        cache.add("k1", build_ms_row(1.5));
        ASSERT_NE(cache.find("k1"), nullptr);
        EXPECT_EQ(cache.size(), 1u);
    }
    std::filesystem::current_path(before);
    EXPECT_TRUE(std::filesystem::is_empty(dir)) << "nothing is written";
    EXPECT_EQ(sweep::ResultCache(std::filesystem::path()).size(), 0u);
}

// A small sweep on the test device: every point runs, the accuracy columns are filled, a second run
// takes every point from the cache, and culling on/off give the same bricks.
TEST(Sweep, RunsPointsOnTheDeviceAndResumes) {
    sweep::SweepSpec s;
    s.scenes = {std::string(SDFBRICK_SOURCE_DIR) + "/scenes/spheres.json"};
    s.brick_sizes = {0.5};
    s.chunks = {16, 32};
    s.culls = {true, false};
    s.width = 48;
    s.height = 32;
    s.warmup = 0;
    s.repeat = 2;
    ocl::DeviceSet devices = test::open_test_devices();
    const auto labels = sweep::device_labels(devices);
    const auto points = sweep::shard_points(sweep::expand(s, {labels.front()}), {0, 1});
    const std::filesystem::path path = test::temp_dir("sweep-run") / "cache.jsonl";
    std::filesystem::remove(path);
    sweep::ResultCache cache(path);
    std::size_t calls = 0;
    const auto rows = sweep::run_points(s, points, devices, nullptr, cache, [&](const sweep::Progress&) { ++calls; });
    ASSERT_EQ(rows.size(), 4u);
    EXPECT_EQ(calls, 5u) << "once per point and once at the end";
    for (const auto& row : rows) {
        const nlohmann::json r = sweep::to_json(row);  // the row as the JSON output has it
        ASSERT_EQ(r["status"], "ok") << r.dump();
        EXPECT_GT(r["bricks"].get<double>(), 0);
        EXPECT_GT(r["build_ms"].get<double>(), 0);
        EXPECT_GE(r["build_max_ms"].get<double>(), r["build_min_ms"].get<double>());
        EXPECT_GT(r["trace_ms"].get<double>(), 0);
        EXPECT_GT(r["stage_evaluate_ms"].get<double>(), 0);
        EXPECT_TRUE(r["identical"].get<bool>());
        EXPECT_LT(r["mismatch"].get<double>(), 0.05);
        EXPECT_LT(r["depth_p99"].get<double>(), 1.0);
        EXPECT_EQ(r["evaluate_local_bytes"].get<double>() >= 16.0 * r["chunk"].get<double>(), true) << r.dump();
        EXPECT_EQ(row.results->bricks, rows[0].results->bricks);
    }
    EXPECT_EQ(rows[0].chunk, 16);
    EXPECT_EQ(rows[2].chunk, 32);
    std::size_t cached = 0;
    sweep::ResultCache again(path);
    sweep::run_points(s, points, devices, nullptr, again, [&](const sweep::Progress& p) { cached = p.cached; });
    EXPECT_EQ(cached, 4u);
}

// spheres at 0.5, one timed run of a 32 x 16 image without the accuracy pass.
sweep::SweepSpec spheres_spec() {
    sweep::SweepSpec s;
    s.scenes = {std::string(SDFBRICK_SOURCE_DIR) + "/scenes/spheres.json"};
    s.brick_sizes = {0.5};
    s.width = 32;
    s.height = 16;
    s.warmup = 0;
    s.repeat = 1;
    s.accuracy = false;
    return s;
}

// Swept values are never replaced by the tuning database: a database entry for the test device's
// trace group and evaluation chunk leaves the points' own values, and fills the group not swept.
TEST(Sweep, SweptValuesWinOverTheTuningDatabase) {
    sweep::SweepSpec s = spheres_spec();
    s.chunks = {32};
    s.trace_groups = {"8x4"};
    ocl::DeviceSet devices = test::open_test_devices();
    const ocl::DeviceInfo& info = devices[0].info();
    tune::TuningDb db(tune::Layers::without_builtin);
    db.put({info.name, info.driver_version, info.vendor, tune::kTraceKernel, {{"group_x", 16}, {"group_y", 2}}, {}});
    db.put({info.name, info.driver_version, info.vendor, tune::kEvaluateKernel, {{"chunk", 128}, {"group", 32}}, {}});
    const auto points = sweep::expand(s, {sweep::device_labels(devices).front()});
    sweep::ResultCache cache(test::temp_dir("sweep-tuned") / "cache.jsonl");
    const auto rows = sweep::run_points(s, points, devices, &db, cache, nullptr);
    ASSERT_EQ(rows.size(), 1u);
    ASSERT_EQ(rows[0].status, "ok") << to_json(rows[0]).dump();
    EXPECT_EQ(rows[0].trace_group, "8x4");
    EXPECT_EQ(rows[0].chunk, 32);
    EXPECT_EQ(rows[0].group, 32) << "not swept: the database's";
}

// A value the device refuses (a trace work-group larger than any device allows) makes that point a
// row with status "error" whose text names the sweep key that gave the value; the sweep goes on.
TEST(Sweep, RefusedValueNamesItsKey) {
    sweep::SweepSpec s = spheres_spec();
    s.trace_groups = {"4096x4096", "8x8"};
    ocl::DeviceSet devices = test::open_test_devices();
    const auto points = sweep::expand(s, {sweep::device_labels(devices).front()});
    const std::filesystem::path path = test::temp_dir("sweep-refused") / "cache.jsonl";
    sweep::ResultCache cache(path);
    const auto rows = sweep::run_points(s, points, devices, nullptr, cache, nullptr);
    ASSERT_EQ(rows.size(), 2u);
    EXPECT_EQ(rows[0].status, "error") << to_json(rows[0]).dump();
    const std::string error = rows[0].error.value_or("");
    EXPECT_EQ(error.rfind("\"trace_groups\": group_x x group_y = 4096 x 4096", 0), 0u) << error;
    EXPECT_EQ(rows[1].status, "ok") << to_json(rows[1]).dump();
}

}  // namespace
}  // namespace sdfbrick
