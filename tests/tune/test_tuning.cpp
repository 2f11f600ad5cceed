// The tuning database (fallback device -> vendor -> default, file round trip, damaged files), applying
// it to a run's settings, the search strategies, and `compare`'s spread rule.
#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "core/errors.h"
#include "test_support.h"
#include "tune/apply.h"
#include "tune/search.h"
#include "tune/tuning_db.h"

namespace sdfbrick {
namespace {

tune::Entry entry(const std::string& device, const std::string& driver, const std::string& vendor, const std::string& kernel,
                  int chunk) {
    return {device, driver, vendor, kernel, {{"chunk", chunk}, {"group", 64}}, {{"time_ms", 1.0}}};
}

TEST(TuneTuning, LookupFallsBackDeviceThenVendorThenDefault) {
    tune::TuningDb db;
    db.put(entry("GPU A", "1.0", "Acme", "brick_evaluate", 32));
    db.put(entry("GPU B", "2.0", "Acme", "brick_evaluate", 128));  // tuned later: the vendor's most recent
    db.put(entry("CPU C", "5.0", "Other", "trace_primary", 16));

    const tune::Lookup exact = db.find("GPU A", "1.0", "Acme", "brick_evaluate");
    EXPECT_EQ(exact.source, tune::Source::device);
    EXPECT_EQ(exact.params.at("chunk"), 32);

    const tune::Lookup new_driver = db.find("GPU A", "1.1", "Acme", "brick_evaluate");
    EXPECT_EQ(new_driver.source, tune::Source::vendor) << "another driver is another device entry";
    EXPECT_EQ(new_driver.params.at("chunk"), 128);

    const tune::Lookup same_vendor = db.find("GPU Z", "9", "Acme", "brick_evaluate");
    EXPECT_EQ(same_vendor.source, tune::Source::vendor);
    ASSERT_NE(same_vendor.entry, nullptr);
    EXPECT_EQ(same_vendor.entry->device, "GPU B");

    const tune::Lookup none = db.find("CPU C", "5.0", "Other", "brick_evaluate");
    EXPECT_EQ(none.source, tune::Source::fallback) << "entries of another kernel do not apply";
    EXPECT_TRUE(none.params.empty());

    db.put(entry("GPU A", "1.0", "Acme", "brick_evaluate", 256));  // re-tuned: replaces, becomes the most recent
    EXPECT_EQ(db.entries().size(), 3u);
    EXPECT_EQ(db.find("GPU A", "1.0", "Acme", "brick_evaluate").params.at("chunk"), 256);
    EXPECT_EQ(db.find("GPU Q", "1", "Acme", "brick_evaluate").params.at("chunk"), 256);
}

TEST(TuneTuning, FileRoundTripAndDamagedFiles) {
    const auto dir = test::temp_dir("tuning");
    tune::TuningDb db;
    db.put(entry("GPU A", "1.0", "Acme", "brick_evaluate", 32));
    db.save(dir / "sub" / "tuning.json");
    const tune::TuningDb back = tune::TuningDb::load(dir / "sub" / "tuning.json");
    ASSERT_EQ(back.entries().size(), 1u);
    EXPECT_EQ(back.entries()[0].params.at("chunk"), 32);
    EXPECT_EQ(back.entries()[0].record.at("time_ms"), 1.0);
    EXPECT_TRUE(tune::TuningDb::load(dir / "missing.json").entries().empty()) << "a missing file is an empty database";
    for (const char* bad : {"{", "[]", "{\"format\": \"other\", \"entries\": []}",
                            "{\"format\": \"sdfbrick tuning 1\", \"entries\": [{\"device\": 1}]}"}) {
        test::write_text(dir / "bad.json", bad);
        EXPECT_THROW(tune::TuningDb::load(dir / "bad.json"), InputError) << bad;
    }
    {
        test::ScopedEnv env(tune::kTuningDbEnv, (dir / "x.json").string());
        EXPECT_EQ(tune::TuningDb::default_path(), dir / "x.json");
    }
    test::ScopedEnv off(tune::kTuningDbEnv, "off");
    EXPECT_FALSE(tune::TuningDb::default_path().has_value());
}

ocl::DeviceInfo fake_device(const std::string& name, const std::string& vendor) {
    ocl::DeviceInfo d;
    d.name = name;
    d.vendor = vendor;
    d.driver_version = "1.0";
    d.max_work_group_size = 256;
    d.local_mem_bytes = 48 * 1024;
    d.local_mem_type = "local";
    return d;
}

TEST(TuneTuning, ApplyKeepsWhatTheCommandLineGaveAndWhatTheDeviceCannotTake) {
    tune::TuningDb db;
    db.put({"GPU A", "1.0", "Acme", tune::kEvaluateKernel, {{"chunk", 128}, {"group", 256}}, {}});
    db.put({"GPU A", "1.0", "Acme", tune::kTraceKernel, {{"group_x", 8}, {"group_y", 4}}, {}});
    const ocl::DeviceInfo gpu = fake_device("GPU A", "Acme");

    construct::BuildSettings s;
    render::TraceSettings t;
    tune::Applied a = tune::apply_tuning(&db, gpu, {}, s, &t);
    EXPECT_EQ(s.chunk, 128);
    EXPECT_EQ(s.eval_group, 256);
    EXPECT_EQ(t.group_x, 8);
    EXPECT_EQ(t.group_y, 4);
    EXPECT_EQ(a.record[tune::kEvaluateKernel]["source"], "device");
    EXPECT_NE(a.text.find("chunk 128"), std::string::npos) << a.text;

    s = {};
    s.chunk = 16;  // given on the command line
    t = {};
    a = tune::apply_tuning(&db, gpu, {true, false, true}, s, &t);
    EXPECT_EQ(s.chunk, 16);
    EXPECT_EQ(s.eval_group, 256);
    EXPECT_EQ(t.group_x, render::TraceSettings{}.group_x);

    s = {};
    ocl::DeviceInfo small = fake_device("GPU S", "Acme");  // vendor fallback, but its work-groups are smaller
    small.max_work_group_size = 128;
    a = tune::apply_tuning(&db, small, {}, s, nullptr);
    EXPECT_EQ(s.eval_group, construct::BuildSettings{}.eval_group) << "a value the device refuses is not applied";
    EXPECT_EQ(s.chunk, construct::BuildSettings{}.chunk);
    EXPECT_TRUE(a.record[tune::kEvaluateKernel].contains("not_applied"));

    s = {};
    a = tune::apply_tuning(nullptr, gpu, {}, s, nullptr);
    EXPECT_EQ(s.chunk, construct::BuildSettings{}.chunk);
    EXPECT_EQ(a.record[tune::kEvaluateKernel]["source"], "default");
}

// A bowl with its minimum at (chunk 64, group 128); group 512 cannot run.
double bowl(const tune::Config& c) {
    if (c.at("group") == 512) return std::numeric_limits<double>::infinity();
    const double x = std::log2(c.at("chunk")) - 6.0, y = std::log2(c.at("group")) - 7.0;
    return 1.0 + x * x + 2.0 * y * y;
}

tune::Space bowl_space() {
    return {{{"chunk", {16, 32, 64, 128, 256}}, {"group", {32, 64, 128, 256, 512}}}};
}

TEST(TuneTuning, SearchStrategiesFindTheMinimumWithinBudget) {
    const tune::Space space = bowl_space();
    ASSERT_EQ(space.size(), 25u);
    EXPECT_EQ(space.at(0), (tune::Config{{"chunk", 16}, {"group", 32}}));
    EXPECT_EQ(space.at(1), (tune::Config{{"chunk", 16}, {"group", 64}}));
    EXPECT_EQ(space.at(24), (tune::Config{{"chunk", 256}, {"group", 512}}));

    const tune::SearchResult full = tune::search(space, tune::Strategy::full, 1, 7, bowl);
    EXPECT_EQ(full.evaluated.size(), 25u) << "full search ignores the budget";
    EXPECT_EQ(full.best, (tune::Config{{"chunk", 64}, {"group", 128}}));
    EXPECT_EQ(full.best_cost, 1.0);

    const tune::SearchResult all_random = tune::search(space, tune::Strategy::random, 100, 7, bowl);
    EXPECT_EQ(all_random.evaluated.size(), 25u);
    EXPECT_EQ(all_random.best, full.best);
    const tune::SearchResult some = tune::search(space, tune::Strategy::random, 10, 7, bowl);
    EXPECT_EQ(some.evaluated.size(), 10u);
    EXPECT_EQ(tune::search(space, tune::Strategy::random, 10, 7, bowl).evaluated, some.evaluated) << "seeded";

    const tune::SearchResult anneal = tune::search(space, tune::Strategy::anneal, 15, 3, bowl);
    EXPECT_LE(anneal.evaluated.size(), 15u);
    EXPECT_EQ(anneal.best, full.best) << "a bowl is found by annealing";

    EXPECT_EQ(tune::strategy_from_string("auto", space, 40), tune::Strategy::full);
    EXPECT_EQ(tune::strategy_from_string("auto", space, 10), tune::Strategy::anneal);
    EXPECT_THROW(tune::strategy_from_string("genetic", space, 10), InputError);
}

}  // namespace
}  // namespace sdfbrick
