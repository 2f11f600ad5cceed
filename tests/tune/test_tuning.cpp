// The tuned kernels' declarations, the tuning database (fallback file device -> file vendor -> builtin
// device -> builtin vendor -> default, file round trip, damaged files), applying it to a run's settings,
// the search strategies, the tuner on the test device, and `compare`'s spread rule.
#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "core/errors.h"
#include "test_support.h"
#include "scene/scene_json.h"
#include "tune/apply.h"
#include "tune/kernels.h"
#include "tune/search.h"
#include "tune/tuner.h"
#include "tune/tuning_db.h"

namespace sdfbrick {
namespace {

tune::Entry entry(const std::string& device, const std::string& driver, const std::string& vendor, const std::string& kernel,
                  int chunk) {
    return {device, driver, vendor, kernel, {{"chunk", chunk}, {"group", 64}}, {{"time_ms", 1.0}}};
}

TEST(TuneTuning, LookupFallsBackDeviceThenVendorThenDefault) {
    tune::TuningDb db(tune::Layers::without_builtin);  // "no entry" means the default
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
    tune::TuningDb db(tune::Layers::without_builtin);
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
    a = tune::apply_tuning(&db, gpu, {.chunk = true, .trace_group = true}, s, &t);
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

constexpr const char* kH100 = "NVIDIA H100 80GB HBM3";
constexpr const char* kNvidia = "NVIDIA Corporation";

TEST(TuneTuning, BuiltinLayerIsFoundByDeviceNameThenVendor) {
    const tune::TuningDb db;  // an empty file over the compiled-in layer
    const tune::Lookup h100 = db.find(kH100, "999.99", kNvidia, tune::kEvaluateKernel);
    EXPECT_EQ(h100.source, tune::Source::builtin_device) << "the device name matches whatever the driver";
    EXPECT_EQ(h100.params, (tune::Config{{"chunk", 32}, {"group", 64}, {"registers", 56}}));
    EXPECT_EQ(h100.entry->record.at("scenes").size(), 3u) << "tuned over three scenes";
    ASSERT_NE(h100.entry, nullptr);
    EXPECT_EQ(h100.entry->driver, "580.159.04");
    EXPECT_EQ(db.find(kH100, "580.159.04", kNvidia, tune::kTraceKernel).params,
              (tune::Config{{"group_x", 4}, {"group_y", 8}}));

    EXPECT_EQ(db.find("NVIDIA H200", "580.159.04", kNvidia, tune::kTraceKernel).params,
              (tune::Config{{"group_x", 8}, {"group_y", 16}, {"registers", 64}}));

    const tune::Lookup other = db.find("NVIDIA Some Other GPU", "1.0", kNvidia, tune::kTraceKernel);
    EXPECT_EQ(other.source, tune::Source::builtin_vendor) << "the vendor's most recent entry, the H200's";
    EXPECT_EQ(other.params, (tune::Config{{"group_x", 8}, {"group_y", 16}, {"registers", 64}}));
    EXPECT_EQ(tune::to_string(other.source), "builtin vendor");
    EXPECT_EQ(tune::layer_of(other.source), "builtin");

    const tune::Lookup pocl = db.find("cpu-skylake-avx512-Intel(R) Xeon(R) Processor", "5.0+debian", "GenuineIntel",
                                      tune::kEvaluateKernel);
    EXPECT_EQ(pocl.source, tune::Source::builtin_device);
    EXPECT_EQ(pocl.params, (tune::Config{{"chunk", 32}, {"group", 64}}));

    EXPECT_EQ(db.find("Unknown", "1", "Nobody", tune::kEvaluateKernel).source, tune::Source::fallback);
    EXPECT_EQ(tune::TuningDb(tune::Layers::without_builtin).find(kH100, "580.159.04", kNvidia, tune::kEvaluateKernel).source,
              tune::Source::fallback);
    EXPECT_TRUE(db.to_json()["entries"].empty()) << "the compiled-in layer is never written to the file";
}

TEST(TuneTuning, UserEntriesWinOverTheBuiltinLayer) {
    tune::TuningDb db;
    db.put(entry(kH100, "580.159.04", kNvidia, tune::kEvaluateKernel, 256));
    const tune::Lookup own = db.find(kH100, "580.159.04", kNvidia, tune::kEvaluateKernel);
    EXPECT_EQ(own.source, tune::Source::device);
    EXPECT_EQ(own.params.at("chunk"), 256);
    EXPECT_EQ(tune::layer_of(own.source), "file");
    // The file's vendor entry comes before the compiled-in device entry.
    const tune::Lookup vendor = db.find(kH100, "600.0", kNvidia, tune::kEvaluateKernel);
    EXPECT_EQ(vendor.source, tune::Source::vendor);
    EXPECT_EQ(vendor.params.at("chunk"), 256);
    // The file has nothing for the trace kernel: the compiled-in entry.
    EXPECT_EQ(db.find(kH100, "580.159.04", kNvidia, tune::kTraceKernel).source, tune::Source::builtin_device);
}

TEST(TuneTuning, ApplyReportsTheBuiltinLayerAndTuningOffIgnoresIt) {
    ocl::DeviceInfo h100 = fake_device(kH100, kNvidia);
    h100.max_work_group_size = 1024;
    const tune::TuningDb db;
    construct::BuildSettings s;
    render::TraceSettings t;
    tune::Applied a = tune::apply_tuning(&db, h100, {}, s, &t);
    EXPECT_EQ(s.chunk, 32);
    EXPECT_EQ(s.eval_group, 64);
    EXPECT_EQ(t.group_x, 4);
    EXPECT_EQ(a.record[tune::kEvaluateKernel]["source"], "builtin device");
    EXPECT_EQ(a.record[tune::kEvaluateKernel]["layer"], "builtin");
    EXPECT_TRUE(a.record[tune::kTraceKernel]["entry"].contains("measured"));
    EXPECT_NE(a.text.find("brick_evaluate chunk 32 group 64"), std::string::npos) << a.text;
    EXPECT_NE(a.text.find("trace_primary 4x8 (builtin device)"), std::string::npos) << a.text;

    s = {};
    t = {};
    a = tune::apply_tuning(nullptr, h100, {}, s, &t);  // --no-tuning
    EXPECT_EQ(s.chunk, construct::BuildSettings{}.chunk);
    EXPECT_EQ(s.eval_group, construct::BuildSettings{}.eval_group);
    EXPECT_EQ(t.group_x, render::TraceSettings{}.group_x);
    EXPECT_EQ(a.record[tune::kEvaluateKernel]["source"], "default");
    EXPECT_EQ(a.record[tune::kTraceKernel]["source"], "default");
}

TEST(TuneKernels, EveryBuiltinEntryIsValidForItsDeclaration) {
    ASSERT_FALSE(tune::builtin_entries().empty());
    for (const tune::Entry& e : tune::builtin_entries()) {
        const tune::TunedKernel* k = tune::find_kernel(e.kernel);
        ASSERT_NE(k, nullptr) << e.kernel;
        EXPECT_TRUE(k->in_space(e.params)) << e.device << " " << e.kernel;
        EXPECT_EQ(k->refuses(e.params), "") << e.device << " " << e.kernel;
        for (const char* field : {"time_ms", "default_ms", "tuned_at", "measured", "brick_size"})
            EXPECT_TRUE(e.record.contains(field)) << e.device << " " << e.kernel << ": " << field;
        EXPECT_NE(e.record.contains("scene"), e.record.contains("scenes")) << e.device << " " << e.kernel;
        EXPECT_TRUE(k->in_space(e.record.at("default_params").get<tune::Config>())) << e.device << " " << e.kernel;
    }
}

TEST(TuneKernels, DeclarationsGiveSpacesConstraintsAndDefaults) {
    const tune::TunedKernel& ev = tune::evaluate_kernel();
    const tune::TunedKernel& tr = tune::trace_kernel();
    EXPECT_EQ(tune::find_kernel("evaluate"), &ev);
    EXPECT_EQ(tune::find_kernel(tune::kTraceKernel), &tr);
    EXPECT_EQ(tune::find_kernel("shade"), nullptr);
    EXPECT_EQ(ev.space().size(), 160u);  // chunk 16..256 x group 8..1024 x registers 0, 64, 56, 48
    EXPECT_EQ(tr.space().size(), 90u);  // group_x 4..64 x group_y 1..32 x registers 0, 64, 96
    EXPECT_EQ(ev.default_config(), (tune::Config{{"chunk", 64}, {"group", 128}, {"registers", 0}}));
    EXPECT_EQ(tr.default_config(), (tune::Config{{"group_x", 16}, {"group_y", 8}, {"registers", 0}}));
    EXPECT_EQ(ev.objective, (std::vector<measure::Stage>{measure::Stage::count, measure::Stage::evaluate}));
    EXPECT_EQ(tr.objective, std::vector<measure::Stage>{measure::Stage::trace});

    ocl::DeviceInfo d = fake_device("GPU A", "Acme");  // 256 work-items
    EXPECT_EQ(ev.space(&d).size(), 30u) << "the group stops at the device's work-group size";
    EXPECT_EQ(tr.space(&d).size(), 30u) << "shapes too large stay in the space, refused; no register cap without "
                                            "cl_nv_compiler_options";
    EXPECT_NE(tr.refuses({{"group_x", 32}, {"group_y", 16}}, &d), "");
    EXPECT_EQ(tr.refuses({{"group_x", 32}, {"group_y", 16}}), "") << "fits some device";
    EXPECT_NE(tr.refuses({{"group_x", 4}, {"group_y", 2}}), "") << "fewer than 16 work-items";
    EXPECT_NE(ev.refuses({{"chunk", 8}, {"group", 64}}), "") << "BuildSettings::validate";
    EXPECT_NE(ev.refuses({{"chunk", 64}}), "") << "a parameter missing";
    EXPECT_FALSE(ev.in_space({{"chunk", 48}, {"group", 64}}));

    // The declared local-memory cost is the one BuildSettings::validate enforces.
    d.local_mem_bytes = ev.local_mem_bytes({{"chunk", 128}, {"group", 64}});
    EXPECT_EQ(ev.refuses({{"chunk", 128}, {"group", 64}}, &d), "");
    construct::BuildSettings s;
    s.chunk = 128;
    EXPECT_NO_THROW(s.validate(d));
    s.chunk = 129;
    EXPECT_THROW(s.validate(d), InputError);
    EXPECT_NE(ev.refuses({{"chunk", 256}, {"group", 64}}, &d), "");

    render::TraceSettings t;
    tr.apply({{"group_x", 8}, {"group_y", 4}}, s, t);
    EXPECT_EQ(tr.read(s, t), (tune::Config{{"group_x", 8}, {"group_y", 4}, {"registers", 0}}));
    EXPECT_EQ(tr.describe(tr.read(s, t)), "8x4");
    EXPECT_TRUE(tr.in_space({{"group_x", 8}, {"group_y", 4}})) << "a configuration written before the register cap";
    EXPECT_FALSE(tr.in_space({{"group_x", 8}, {"group_y", 4}, {"registers", 72}}));

    d.extensions = {"cl_khr_fp64", "cl_nv_compiler_options"};
    EXPECT_EQ(tr.space(&d).size(), 90u) << "the register cap is searched where the compiler takes it";
    tr.apply({{"group_x", 8}, {"group_y", 16}, {"registers", 64}}, s, t);
    EXPECT_EQ(t.max_registers, 64);
    EXPECT_EQ(tr.describe(tr.read(s, t)), "8x16 registers 64");
}

// A database's register cap is applied unless --max-registers was given; an entry written before the
// cap existed leaves it at 0 (the compiler's choice).
TEST(TuneTuning, ApplyTakesTheRegisterCapUnlessGiven) {
    tune::TuningDb db(tune::Layers::without_builtin);
    db.put({"GPU N", "1.0", "Acme", tune::kTraceKernel, {{"group_x", 8}, {"group_y", 16}, {"registers", 64}}, {}});
    db.put({"GPU O", "1.0", "Acme", tune::kTraceKernel, {{"group_x", 8}, {"group_y", 4}}, {}});
    ocl::DeviceInfo gpu = fake_device("GPU N", "Acme");
    gpu.extensions = {"cl_nv_compiler_options"};
    construct::BuildSettings s;
    render::TraceSettings t;
    tune::apply_tuning(&db, gpu, {}, s, &t);
    EXPECT_EQ(t.max_registers, 64);
    EXPECT_EQ(t.group_y, 16);

    t = {};
    t.max_registers = 96;
    tune::Given given;
    given.trace_registers = true;
    tune::apply_tuning(&db, gpu, given, s, &t);
    EXPECT_EQ(t.max_registers, 96) << "given on the command line";
    EXPECT_EQ(t.group_y, 16);

    t = {};
    tune::apply_tuning(&db, fake_device("GPU O", "Acme"), {}, s, &t);
    EXPECT_EQ(t.max_registers, 0);
    EXPECT_EQ(t.group_y, 4);

    t = {};
    t.max_registers = 64;  // given where the compiler takes no cap
    const tune::Applied a = tune::apply_tuning(&db, fake_device("GPU O", "Acme"), given, s, &t);
    EXPECT_EQ(t.max_registers, 64);
    EXPECT_NE(a.text.find("registers 64 has no effect: GPU O lacks cl_nv_compiler_options"), std::string::npos)
        << a.text;
}

// The evaluation's register cap is looked up and given apart from the trace's.
TEST(TuneTuning, EvaluationRegisterCapIsItsOwnParameter) {
    tune::TuningDb db(tune::Layers::without_builtin);
    db.put({"GPU N", "1.0", "Acme", tune::kEvaluateKernel, {{"chunk", 16}, {"group", 64}, {"registers", 56}}, {}});
    db.put({"GPU N", "1.0", "Acme", tune::kTraceKernel, {{"group_x", 8}, {"group_y", 16}, {"registers", 64}}, {}});
    ocl::DeviceInfo gpu = fake_device("GPU N", "Acme");
    gpu.extensions = {"cl_nv_compiler_options"};
    construct::BuildSettings s;
    render::TraceSettings t;
    tune::Applied a = tune::apply_tuning(&db, gpu, {.trace_registers = true}, s, &t);
    EXPECT_EQ(s.eval_registers, 56) << "the trace's cap given does not hold the evaluation's";
    EXPECT_EQ(t.max_registers, 0);
    EXPECT_NE(a.text.find("chunk 16 group 64 registers 56 (device)"), std::string::npos) << a.text;

    s = {};
    s.eval_registers = 48;
    a = tune::apply_tuning(&db, gpu, {.eval_registers = true}, s, &t);
    EXPECT_EQ(s.eval_registers, 48) << "given";
    EXPECT_EQ(s.chunk, 16);
    EXPECT_EQ(t.max_registers, 64);

    s = {};
    a = tune::apply_tuning(&db, fake_device("GPU N", "Acme"), {.chunk = true, .group = true}, s, &t);
    EXPECT_EQ(s.eval_registers, 0) << "not looked up for a device without the extension";
    EXPECT_NE(a.text.find("brick_evaluate chunk 64 group 128 (command line)"), std::string::npos)
        << "chunk and group are all such a device takes: " << a.text;

    s = {};
    s.eval_registers = 300;
    EXPECT_THROW(s.validate(gpu), SettingError);
}

// A shipped scene to tune over.
tune::TuneScene tune_scene(const std::string& name) {
    const Scene file = load_scene(std::string(SDFBRICK_SOURCE_DIR) + "/scenes/" + name + ".json");
    return {scene_at(file, file.time), name};
}

// Two random configurations, one capture each, a small traced image.
tune::TuneSpec small_spec() {
    tune::TuneSpec spec;
    spec.strategy = "random";
    spec.budget = 2;
    spec.warmup = 0;
    spec.repeat = 1;
    spec.width = 32;
    spec.height = 16;
    return spec;
}

// The tuner measures through the run loop on the test device: both kernels, every configuration
// reported, the default measured.
TEST(TuneTuner, MeasuresEachKernelThroughTheRunner) {
    const tune::TuneScene scene = tune_scene("spheres");
    pipeline::Lane runner(test::device());
    construct::BuildSettings base;
    base.leaf_size = 0.5;
    const tune::TuneSpec spec = small_spec();
    for (const tune::TunedKernel* k : tune::tuned_kernels()) {
        std::vector<tune::Config> seen;
        const tune::TuneResult r = tune::tune_kernel(*k, runner, {&scene, 1}, base, spec,
                                                     [&](std::size_t n, const tune::Config& c, double, std::span<const double>) {
            EXPECT_EQ(n, seen.size() + 1);
            seen.push_back(c);
        });
        EXPECT_EQ(r.kernel, k);
        EXPECT_EQ(r.strategy, tune::Strategy::random);
        ASSERT_EQ(seen.size(), 2u) << k->name;
        EXPECT_EQ(r.result.evaluated.size(), 2u);
        EXPECT_EQ(r.fallback, k->default_config());
        EXPECT_TRUE(std::isfinite(r.fallback_cost) && r.fallback_cost > 0.0) << k->name;
        if (!r.found()) continue;
        const tune::Entry e = tune::make_entry(r, test::device().info(), "now");
        EXPECT_EQ(e.kernel, k->name);
        EXPECT_EQ(e.params, r.result.best);
        EXPECT_EQ(e.record.contains("image"), k->work == pipeline::Work::trace);
    }
}

// Over several scenes a configuration's cost is the geometric mean of its times on each, which the
// report and the entry name.
TEST(TuneTuner, SeveralScenesCostTheGeometricMeanOfTheirTimes) {
    const std::vector<tune::TuneScene> scenes{tune_scene("spheres"), tune_scene("cubes")};
    pipeline::Lane runner(test::device());
    construct::BuildSettings base;
    base.leaf_size = 0.5;
    const tune::TuneSpec spec = small_spec();
    std::vector<double> progress_costs;
    const tune::TuneResult r = tune::tune_kernel(*tune::find_kernel("evaluate"), runner, scenes, base, spec,
                                                 [&](std::size_t, const tune::Config&, double cost, std::span<const double> ms) {
                                                     EXPECT_EQ(ms.size(), 2u);
                                                     progress_costs.push_back(cost);
                                                 });
    ASSERT_EQ(r.scene_ms.size(), r.result.evaluated.size());
    ASSERT_EQ(progress_costs.size(), r.result.evaluated.size());
    for (std::size_t i = 0; i < r.scene_ms.size(); ++i) {
        const std::vector<double>& ms = r.scene_ms[i];
        ASSERT_EQ(ms.size(), 2u);
        EXPECT_TRUE(ms[0] > 0.0 && ms[1] > 0.0);
        EXPECT_DOUBLE_EQ(r.result.evaluated[i].second, std::sqrt(ms[0] * ms[1]));
        EXPECT_EQ(progress_costs[i], r.result.evaluated[i].second);
    }
    ASSERT_TRUE(r.found());
    const tune::Entry e = tune::make_entry(r, test::device().info(), "now");
    EXPECT_EQ(e.record.at("scenes"), nlohmann::json({"spheres", "cubes"}));
    EXPECT_FALSE(e.record.contains("scene"));
    EXPECT_NE(e.record.at("objective").get<std::string>().find("geometric mean"), std::string::npos);
    EXPECT_THROW(tune::tune_kernel(*tune::find_kernel("evaluate"), runner, {}, base, spec), InputError);
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
