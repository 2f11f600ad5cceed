// T4 auto-tuning results (tune/t4.h): a real tuning run written with `tune --t4` holds what the T4
// results schema 1.0.0 demands of it (checked here rule by rule: the schema's required properties,
// their types and the invalidity enumeration), and `tune-import` takes the best valid result of a T4
// file for a device the database has no entry for.
#include <filesystem>
#include <regex>
#include <set>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli/cli_run.h"
#include "core/errors.h"
#include "core/files.h"
#include "test_support.h"
#include "tune/kernels.h"
#include "tune/t4.h"
#include "tune/tuning_db.h"

namespace sdfbrick {
namespace {

namespace fs = std::filesystem;

// The T4 results schema's rules (schema_version's pattern; each result an object with configuration,
// times, invalidity and correctness; the types of every property the schema names).
::testing::AssertionResult valid_t4(const nlohmann::json& doc) {
    const auto fail = [](const std::string& why) { return ::testing::AssertionFailure() << why; };
    if (!doc.is_object()) return fail("not an object");
    if (!doc.contains("schema_version") || !doc["schema_version"].is_string() ||
        !std::regex_match(doc["schema_version"].get<std::string>(), std::regex("^[0-9]{1,}.[0-9]{1,}.[0-9]{1,}$")))
        return fail("schema_version");
    if (!doc.contains("results") || !doc["results"].is_array()) return fail("results");
    const std::set<std::string> invalidity = {"timeout", "compile", "runtime", "correctness", "constraints", "correct"};
    for (const nlohmann::json& r : doc["results"]) {
        if (!r.is_object()) return fail("a result is not an object");
        for (const char* key : {"configuration", "times", "invalidity", "correctness"})
            if (!r.contains(key)) return fail(std::string("a result without ") + key);
        if (!r["configuration"].is_object() || !r["times"].is_object() || !r["correctness"].is_number())
            return fail("a result's configuration, times or correctness: " + r.dump());
        if (!r["invalidity"].is_string() || !invalidity.count(r["invalidity"].get<std::string>())) return fail("invalidity");
        if (r.contains("timestamp") && !r["timestamp"].is_string()) return fail("timestamp");
        if (r.contains("objectives") && !r["objectives"].is_array()) return fail("objectives");
        const nlohmann::json& t = r["times"];
        for (const char* key : {"compilation_time", "framework", "search_algorithm", "validation"})
            if (t.contains(key) && !t[key].is_number()) return fail(std::string("times/") + key);
        if (t.contains("runtimes") && !t["runtimes"].is_array()) return fail("times/runtimes");
        if (r.contains("measurements")) {
            if (!r["measurements"].is_array()) return fail("measurements");
            for (const nlohmann::json& m : r["measurements"])
                if (!m.is_object() || (m.contains("name") && !m["name"].is_string()) ||
                    (m.contains("unit") && !m["unit"].is_string()) ||
                    (m.contains("value") && !(m["value"].is_number() || m["value"].is_string() || m["value"].is_array())))
                    return fail("a measurement: " + m.dump());
        }
    }
    return ::testing::AssertionSuccess();
}

TEST(TuneT4, ARealTuningRunIsValidT4Results) {
    const fs::path dir = test::temp_dir("tune_t4_run");
    const test::CliRun r = test::sdfbrick(
        "tune " + test::scene_path("spheres") + " " + test::scene_path("cubes") + " --brick-size 0.25 --strategy random --budget 3 --repeat 1 --warmup 0 "
        "--width 32 --height 24 --t4 " + (dir / "run.t4.json").string() + " --json " + (dir / "r.json").string(),
        test::device_env() + " SDFBRICK_TUNING_DB=" + (dir / "db.json").string());
    ASSERT_EQ(r.status, 0) << r.err;
    const nlohmann::json doc = nlohmann::json::parse(read_file(dir / "run.t4.json"));
    EXPECT_TRUE(valid_t4(doc));
    EXPECT_EQ(doc["schema_version"], "1.0.0");
    const nlohmann::json report = nlohmann::json::parse(read_file(dir / "r.json"));
    std::size_t measured = 0;
    for (const auto& d : report["devices"])
        for (const auto& [kernel, rec] : d.items())
            if (rec.is_object() && rec.contains("evaluated_configurations")) measured += rec["evaluated_configurations"].size();
    EXPECT_EQ(doc["results"].size(), measured);
    EXPECT_GE(measured, 2u);
}

// A result of Kernel Tuner's kind (no kernel named) for the evaluation kernel.
nlohmann::json result(int chunk, int group, double ms, const char* invalidity = "correct") {
    return {{"configuration", {{"chunk", chunk}, {"group", group}}},
            {"times", {{"runtimes", {ms}}}},
            {"invalidity", invalidity},
            {"correctness", 1},
            {"measurements", {{{"name", "time"}, {"value", ms}, {"unit", "ms"}}}}};
}

TEST(TuneT4, ImportTakesTheBestValidResultForADeviceWithoutAnEntry) {
    const fs::path dir = test::temp_dir("tune_t4_import");
    nlohmann::json doc = {{"schema_version", "1.0.0"}, {"results", nlohmann::json::array()}};
    doc["results"].push_back(result(64, 128, 3.0));
    doc["results"].push_back(result(32, 64, 1.0, "compile"));           // not valid
    doc["results"].push_back(result(128, 64, 2.0));                     // the best valid one
    doc["results"].push_back(result(7, 64, 0.5));                       // a chunk the kernel refuses
    doc["results"].push_back({{"configuration", {{"block_size_x", 32}}}, {"times", nlohmann::json::object()},
                              {"invalidity", "correct"}, {"correctness", 1}});  // another kernel's parameters
    EXPECT_TRUE(valid_t4(doc));
    test::write_text(dir / "kt.json", doc.dump());
    const std::string env = test::device_env() + " SDFBRICK_TUNING_DB=" + (dir / "db.json").string();
    const test::CliRun first = test::sdfbrick("tune-import " + (dir / "kt.json").string() + " --kernels evaluate", env);
    ASSERT_EQ(first.status, 0) << first.err;
    EXPECT_NE(first.out.find("imported 1 entry"), std::string::npos) << first.out;
    const tune::TuningDb db = tune::TuningDb::load(dir / "db.json", tune::Layers::without_builtin);
    ASSERT_EQ(db.entries().size(), 1u);
    EXPECT_EQ(db.entries()[0].kernel, tune::kEvaluateKernel);
    EXPECT_EQ(db.entries()[0].params, (tune::Config{{"chunk", 128}, {"group", 64}, {"registers", 0}}));
    EXPECT_EQ(db.entries()[0].record["source"], "T4");
    const test::CliRun again = test::sdfbrick("tune-import " + (dir / "kt.json").string() + " --kernels evaluate", env);
    ASSERT_EQ(again.status, 0) << again.err;
    EXPECT_NE(again.out.find("already has an entry; kept"), std::string::npos) << again.out;
    test::write_text(dir / "bad.json", R"({"results": {"x": 1}})");
    const test::CliRun bad = test::sdfbrick("tune-import " + (dir / "bad.json").string(), env);
    EXPECT_EQ(bad.status, 2) << bad.err;
    EXPECT_TRUE(test::one_clean_line(bad));
    EXPECT_NE(bad.err.find("not T4 tuning results"), std::string::npos) << bad.err;
}

}  // namespace
}  // namespace sdfbrick
