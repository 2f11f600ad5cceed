// Comparing two reports: a stage is flagged only when it moved beyond both runs' spread.
#include <gtest/gtest.h>

#include <string>

#include <nlohmann/json.hpp>

#include "core/errors.h"
#include "measure/compare.h"

namespace sdfbrick {
namespace {

nlohmann::json report(const std::string& device, double count_lo, double count_hi, double eval_lo, double eval_hi) {
    const auto stage = [](const char* name, double lo, double hi) {
        return nlohmann::json{{"name", name}, {"median_ms", (lo + hi) / 2}, {"min_ms", lo}, {"max_ms", hi}};
    };
    return {{"devices", {{{"device", {{"name", device}}},
                          {"stages", {stage("count", count_lo, count_hi), stage("evaluate", eval_lo, eval_hi)}}}}}};
}

TEST(MeasureCompare, FlagsOnlyChangesBeyondTheRunsSpread) {
    const auto deltas = measure::compare_reports(report("G", 1.0, 1.2, 10.0, 10.4), report("G", 1.1, 1.3, 12.0, 12.2));
    ASSERT_EQ(deltas.size(), 3u);  // count, evaluate, total
    EXPECT_EQ(deltas[0].stage, "count");
    EXPECT_FALSE(deltas[0].significant()) << "ranges overlap";
    EXPECT_EQ(deltas[1].stage, "evaluate");
    EXPECT_TRUE(deltas[1].significant());
    EXPECT_NEAR(deltas[1].delta_ms(), 1.9, 1e-12);
    EXPECT_EQ(deltas[2].stage, "total");
    EXPECT_TRUE(deltas[2].significant());
    const std::string text = measure::compare_text(deltas);
    EXPECT_NE(text.find("SLOWER"), std::string::npos) << text;
    EXPECT_NE(text.find("1 stage(s)"), std::string::npos) << text;
    EXPECT_THROW(measure::compare_reports(nlohmann::json::object(), report("G", 1, 1, 1, 1)), InputError);
    // One device each: paired whatever the names (a vendor comparison).
    EXPECT_EQ(measure::compare_reports(report("G", 1, 1, 1, 1), report("C", 2, 2, 2, 2))[0].device, "G -> C");
}

// Stages pair by name in one pass over each report: two reports of 30,000 stages (each a quarter
// only in one report) compare in linear time (pairwise matching took 103 s), in A's order, then B's own.
TEST(MeasureCompare, PairsManyStagesByName) {
    nlohmann::json a = nlohmann::json::array(), b = nlohmann::json::array();
    for (int i = 0; i < 30000; ++i) {
        if (i % 4 != 3) a.push_back({{"name", "s" + std::to_string(i)}, {"median_ms", 1.0}});
        if (i % 4 != 0) b.push_back({{"name", "s" + std::to_string(i)}, {"median_ms", 2.0}});
    }
    const auto deltas = measure::compare_reports({{"stages", a}}, {{"stages", b}});
    ASSERT_EQ(deltas.size(), 30001u);
    EXPECT_EQ(deltas[0].stage, "s0");
    EXPECT_TRUE(deltas[0].in_a && !deltas[0].in_b);
    EXPECT_EQ(deltas[1].stage, "s1");
    EXPECT_TRUE(deltas[1].in_a && deltas[1].in_b);
    EXPECT_EQ(deltas[22500].stage, "s3");  // B's own come after A's
    EXPECT_TRUE(!deltas[22500].in_a && deltas[22500].in_b);
    EXPECT_DOUBLE_EQ(deltas.back().a_median, 22500.0);
    EXPECT_DOUBLE_EQ(deltas.back().b_median, 45000.0);
}

}  // namespace
}  // namespace sdfbrick
