// The performance gate on crafted report pairs: each rule failing and passing, the rules' grammar,
// the refusals (different runs, a figure a rule needs), and the three renderings of a verdict.
#include <gtest/gtest.h>

#include <string>

#include <nlohmann/json.hpp>

#include "core/errors.h"
#include "measure/gate.h"
#include "test_support.h"

namespace sdfbrick {
namespace {

using nlohmann::json;
using measure::GateCheck;
using measure::GateFigure;
using measure::GateOutcome;
using measure::GateVerdict;

// A build report as `build --json` writes one, cut to what the gate reads (one device whose entry
// repeats the job's figures, as a run on one device does, plus a figure of its own).
json report() {
    json device = {{"device", {{"name", "pthread-cpu"}}},
                   {"digest", "fd3bb34f812387af"},
                   {"bricks", 8568},
                   {"edit_evaluations", 8282952},
                   {"work_per_pixel", {{"node_visits", 6.84}, {"brick_steps", 2.21}}}};
    return {{"command", "build"},
            {"scene", {{"file", "scenes/spheres.json"}, {"name", "spheres"}, {"time", 0.0}, {"geometries", 1}}},
            {"settings", {{"brick_size", 0.0625}, {"format", "int8"}, {"cull", true}, {"chunk", 64}}},
            {"placement", {{"placement", "whole"}, {"home", 0}}},
            {"digest", "fd3bb34f812387af"},
            {"bricks", 8568},
            {"edit_evaluations", 8282952},
            {"geometries", {{{"levels", {{{"bricks", 1}, {"edit_entries", 2}}, {{"bricks", 33}, {"edit_entries", 65}}}}}}},
            {"memory", {{"brick pool", 4386816}, {"edit lists", 68508}}},
            {"captures", {{"repeat", 1}, {"identical", true}}},
            {"total_ms", {{"median_ms", 86.9}, {"min_ms", 86.9}, {"max_ms", 86.9}}},
            {"devices", {device}}};
}

// A render --compare report's accuracy figures added to report().
json render_report() {
    json r = report();
    r["command"] = "render";
    r["accuracy"] = {{"mismatch_fraction", 0.0}, {"depth_error_p99", 0.0814}, {"normal_error_p99_deg", 0.80}};
    return r;
}

// With repeats: the job's device time over the captures.
json timed(json r, double median, double lo, double hi) {
    r["captures"]["repeat"] = 5;
    r["total_ms"] = {{"median_ms", median}, {"min_ms", lo}, {"max_ms", hi}};
    return r;
}

GateVerdict gate(const json& base, const json& candidate, const std::string& rules = "default",
                 measure::GateOptions options = {}) {
    return measure::gate_reports(base, candidate, measure::parse_gate_rules(rules), options, "base.json", "new.json");
}

const GateCheck* find(const GateVerdict& v, const std::string& figure) {
    for (const GateCheck& c : v.checks)
        if (c.figure == figure) return &c;
    return nullptr;
}

// The InputError's message of f(), or "" when it does not throw one.
TEST(MeasureGate, RulesParseAndDefaultExpands) {
    EXPECT_EQ(measure::gate_rules_text(measure::parse_gate_rules("default")), measure::kDefaultGateRules);
    const auto rules = measure::parse_gate_rules(" default , counters<=5% ,time?<=0.1");
    EXPECT_EQ(measure::gate_rules_text(rules),
              "digest,counters<=5%,mismatch?<=0.0001,depth_p99?<=0.01,normal_p99?<=0.1,time?<=10%");
    ASSERT_EQ(rules.size(), 6u);
    EXPECT_DOUBLE_EQ(rules[1].limit, 0.05);
    EXPECT_FALSE(rules[1].optional);
    EXPECT_TRUE(rules[5].optional);
    EXPECT_EQ(measure::gate_rules_text(measure::parse_gate_rules("digest?,mismatch")), "digest?,mismatch");
    const std::pair<const char*, const char*> bad[] = {
        {"", "empty"},
        {"digest,,counters", "an empty item"},
        {"countrs<=2%", "\"countrs<=2%\": unknown rule"},
        {"digest<=1", "a digest takes no limit"},
        {"counters<=two", "expected a number"},
        {"counters<=-1%", "finite number >= 0"},
        {"counters<=2%%", "expected a number"},
        {"time?<=", "expected a number"},
        {"counters <= 1e999", "expected a number"},
    };
    for (const auto& [text, message] : bad) {
        const std::string e = test::input_error_of([&] { measure::parse_gate_rules(text); });
        EXPECT_NE(e.find(message), std::string::npos) << text << ": " << e;
    }
}

TEST(MeasureGate, TheSameReportPasses) {
    const GateVerdict v = gate(render_report(), render_report());
    EXPECT_TRUE(v.passed());
    EXPECT_EQ(v.count(GateOutcome::fail), 0u);
    EXPECT_EQ(v.count(GateOutcome::skip), 1u) << "time: no repeats";
    // The device's entry repeats the job's figures: checked once, at the top; its own figures are checked there.
    EXPECT_EQ(find(v, "/devices/0/bricks"), nullptr);
    EXPECT_NE(find(v, "/bricks"), nullptr);
    EXPECT_NE(find(v, "/devices/0/work_per_pixel/node_visits"), nullptr);
    EXPECT_NE(find(v, "/geometries/0/levels/1/edit_entries"), nullptr);
    EXPECT_NE(find(v, "/memory/brick pool"), nullptr);
}

TEST(MeasureGate, DifferentScenesOrSettingsAreRefusedUnlessAllowed) {
    json other = report();
    other["scene"]["name"] = "drops";
    std::string e = test::input_error_of([&] { gate(report(), other); });
    EXPECT_NE(e.find("base.json and new.json: reports of different runs: scene/name spheres -> drops"), std::string::npos) << e;
    EXPECT_NE(e.find("--allow-different"), std::string::npos) << e;
    json coarse = report();
    coarse["settings"]["brick_size"] = 0.125;
    e = test::input_error_of([&] { gate(report(), coarse); });
    EXPECT_NE(e.find("settings/brick_size 0.0625 -> 0.125"), std::string::npos) << e;
    e = test::input_error_of([&] { gate(report(), render_report()); });
    EXPECT_NE(e.find("command build -> render"), std::string::npos) << e;

    const GateVerdict allowed = gate(report(), coarse, "default", {false, true});
    EXPECT_TRUE(allowed.passed());
    ASSERT_EQ(allowed.setup.size(), 1u);
    EXPECT_NE(allowed.setup[0].find("settings/brick_size"), std::string::npos) << allowed.setup[0];

    // Work settings change no bit: they may differ, and are noted; so may the file's path and the device's name.
    json work = report();
    work["settings"]["cull"] = false;
    work["scene"]["file"] = "/elsewhere/spheres.json";
    work["devices"][0]["device"]["name"] = "another-cpu";
    const GateVerdict v = gate(report(), work);
    EXPECT_TRUE(v.passed());
    ASSERT_EQ(v.setup.size(), 2u);
    EXPECT_NE(v.setup[0].find("settings/cull true -> false (a work setting"), std::string::npos) << v.setup[0];
    EXPECT_NE(v.setup[1].find("device 0 pthread-cpu -> another-cpu"), std::string::npos) << v.setup[1];
}

TEST(MeasureGate, AFigureARequiredRuleNeedsMustBeInBothReports) {
    json plain = render_report();
    plain.erase("accuracy");
    std::string e = test::input_error_of([&] { gate(render_report(), plain, "mismatch"); });
    EXPECT_NE(e.find("new.json: /accuracy/mismatch_fraction: missing (rule mismatch needs it in both reports"),
              std::string::npos) << e;
    // Optional: skipped, and said so.
    const GateVerdict v = gate(report(), report(), "mismatch?,digest");
    EXPECT_TRUE(v.passed());
    ASSERT_EQ(v.checks.size(), 2u);
    EXPECT_EQ(v.checks[0].outcome, GateOutcome::skip);
    EXPECT_EQ(v.checks[0].note, "BASE and NEW: not there");
    e = test::input_error_of([&] { gate(report(), report(), "time"); });
    EXPECT_NE(e.find("base.json: /captures/repeat: one capture (rule time needs repeats"), std::string::npos) << e;
    json bare = report();
    bare.erase("digest");
    bare["devices"][0].erase("digest");
    e = test::input_error_of([&] { gate(report(), bare, "digest"); });
    EXPECT_NE(e.find("new.json: /digest: missing"), std::string::npos) << e;
    e = test::input_error_of([&] { gate(json::object(), report(), "counters", {false, true}); });
    EXPECT_NE(e.find("base.json: work counters"), std::string::npos) << e;
    // Not a report, or a figure of the wrong type: the place is named.
    e = test::input_error_of([&] { gate(json::array(), report()); });
    EXPECT_NE(e.find("base.json: expected a JSON object"), std::string::npos) << e;
    json deep = report();
    json* at = &deep["settings"];
    for (int i = 0; i < 100000; ++i) at = &((*at)["x"] = json::object());
    e = test::input_error_of([&] { gate(report(), deep); });
    EXPECT_NE(e.find("new.json: nested deeper than 64 levels"), std::string::npos) << e;
    json typed = report();
    typed["geometries"][0]["levels"][1]["bricks"] = "33";
    e = test::input_error_of([&] { gate(report(), typed); });
    EXPECT_NE(e.find("new.json: /geometries/0/levels/1/bricks: expected a number"), std::string::npos) << e;
}

TEST(MeasureGate, AChangedDigestFailsUnlessAllowed) {
    json changed = report();
    changed["digest"] = changed["devices"][0]["digest"] = "0123456789abcdef";
    const GateVerdict v = gate(report(), changed);
    EXPECT_FALSE(v.passed());
    const GateCheck* c = find(v, "/digest");
    ASSERT_NE(c, nullptr);
    EXPECT_EQ(c->outcome, GateOutcome::fail);
    EXPECT_EQ(find(v, "/devices/0/digest"), nullptr) << "the device repeats the job's digest: one check";
    EXPECT_NE(measure::failure_line(v).find("digest /digest: fd3bb34f812387af -> 0123456789abcdef: changed"),
              std::string::npos) << measure::failure_line(v);

    const GateVerdict allowed = gate(report(), changed, "default", {true, false});
    EXPECT_TRUE(allowed.passed());
    EXPECT_TRUE(find(allowed, "/digest")->changed());
    EXPECT_NE(find(allowed, "/digest")->note.find("allowed"), std::string::npos);
}

TEST(MeasureGate, CountersMayNotGrowBeyondTheThreshold) {
    json within = report(), over = report();
    within["edit_evaluations"] = within["devices"][0]["edit_evaluations"] = 8282952 + 8282952 / 100;  // +1%
    over["edit_evaluations"] = over["devices"][0]["edit_evaluations"] = 8282952 + 8282952 / 20;       // +5%
    const GateVerdict ok = gate(report(), within);
    EXPECT_TRUE(ok.passed());
    EXPECT_EQ(find(ok, "/edit_evaluations")->note, "grew 1%, within the limit of 2%");
    const GateVerdict bad = gate(report(), over);
    EXPECT_FALSE(bad.passed());
    EXPECT_EQ(find(bad, "/edit_evaluations")->outcome, GateOutcome::fail);
    EXPECT_EQ(find(bad, "/edit_evaluations")->note, "grew 5%, over the limit of 2%");
    EXPECT_TRUE(gate(report(), over, "counters<=5%").passed()) << "the threshold is the rule's";
    EXPECT_FALSE(gate(report(), within, "counters").passed()) << "no limit: may not grow at all";

    // Per-device figures, per level, bytes; shrinking passes, growing from 0 fails.
    json device = report(), level = report(), bytes = report();
    device["devices"][0]["work_per_pixel"]["node_visits"] = 7.5;
    level["geometries"][0]["levels"][0]["bricks"] = 2;
    bytes["memory"]["edit lists"] = 8;
    bytes["memory"]["scratch"] = 1024;
    EXPECT_EQ(find(gate(report(), device), "/devices/0/work_per_pixel/node_visits")->outcome, GateOutcome::fail);
    EXPECT_EQ(find(gate(report(), level), "/geometries/0/levels/0/bricks")->outcome, GateOutcome::fail);
    const GateVerdict b = gate(report(), bytes);
    EXPECT_EQ(find(b, "/memory/edit lists")->outcome, GateOutcome::pass);
    EXPECT_EQ(find(b, "/memory/scratch")->outcome, GateOutcome::skip) << "only in NEW";
    json zero = report(), grown = report();
    zero["memory"]["scratch"] = 0;
    grown["memory"]["scratch"] = 1;
    EXPECT_EQ(find(gate(zero, grown), "/memory/scratch")->note, "grew from 0, over the limit of 2%");
}

TEST(MeasureGate, AccuracyMayNotGetWorseBeyondTheTolerance) {
    const auto worse = [](const char* key, double by) {
        json r = render_report();
        r["accuracy"][key] = r["accuracy"][key].get<double>() + by;
        return r;
    };
    EXPECT_TRUE(gate(render_report(), worse("mismatch_fraction", 0.00005)).passed());
    EXPECT_FALSE(gate(render_report(), worse("mismatch_fraction", 0.0002)).passed());
    EXPECT_TRUE(gate(render_report(), worse("depth_error_p99", 0.005)).passed());
    EXPECT_FALSE(gate(render_report(), worse("depth_error_p99", 0.02)).passed());
    EXPECT_TRUE(gate(render_report(), worse("normal_error_p99_deg", 0.05)).passed());
    const GateVerdict v = gate(render_report(), worse("normal_error_p99_deg", 0.5));
    EXPECT_FALSE(v.passed());
    EXPECT_EQ(find(v, "/accuracy/normal_error_p99_deg")->note, "worse by 0.5, beyond the tolerance of 0.1");
    EXPECT_TRUE(gate(render_report(), worse("depth_error_p99", -0.05)).passed()) << "better";
    EXPECT_TRUE(gate(render_report(), worse("depth_error_p99", 0.02), "default,depth_p99?<=0.05").passed());
}

TEST(MeasureGate, TimesAreGatedOnlyWhereBothHaveRepeatsAndTheSpreadsDoNotOverlap) {
    const json base = timed(report(), 86.0, 84.0, 88.0);
    const GateVerdict slower = gate(base, timed(report(), 95.0, 93.0, 97.0));
    EXPECT_FALSE(slower.passed());
    EXPECT_EQ(find(slower, "/total_ms")->outcome, GateOutcome::fail);
    EXPECT_TRUE(gate(base, timed(report(), 95.0, 93.0, 97.0), "default,time?<=20%").passed()) << "within the limit";
    const GateVerdict overlapping = gate(base, timed(report(), 95.0, 87.0, 120.0));
    EXPECT_TRUE(overlapping.passed());
    EXPECT_NE(find(overlapping, "/total_ms")->note.find("overlap"), std::string::npos);
    EXPECT_TRUE(gate(base, timed(report(), 60.0, 59.0, 61.0)).passed()) << "faster";
    // One capture in either report: no spread, no time check (time? skips it).
    const GateVerdict single = gate(base, report());
    EXPECT_TRUE(single.passed());
    EXPECT_EQ(find(single, "/captures/repeat")->note, "NEW: no repeats");
}

TEST(MeasureGate, TheVerdictRendersAsJsonMarkdownAndJUnit) {
    json over = report();
    over["edit_evaluations"] = over["devices"][0]["edit_evaluations"] = 8847234;
    over["memory"]["a<b>&\"c|`"] = 1;  // a hostile figure name
    const GateVerdict v = gate(report(), over);
    const json j = measure::to_json(v);
    EXPECT_FALSE(j["passed"].get<bool>());
    EXPECT_EQ(j["rules"], std::string(measure::kDefaultGateRules));
    EXPECT_EQ(j["counts"]["failed"], 1);
    EXPECT_EQ(j["counts"]["checks"], v.checks.size());
    const std::string md = measure::to_markdown(v);
    EXPECT_NE(md.find("## sdfbrick compare --gate: FAIL"), std::string::npos) << md;
    EXPECT_NE(md.find("| counters | `/edit_evaluations` | 8282952 | 8847234 | grew 6.81%, over the limit of 2% |"),
              std::string::npos) << md;
    EXPECT_NE(md.find("`/memory/a<b>&\"c\\|'`"), std::string::npos) << md;
    const std::string xml = measure::to_junit(v);
    EXPECT_NE(xml.find("failures=\"1\""), std::string::npos) << xml;
    EXPECT_NE(xml.find("<testcase classname=\"gate.counters\" name=\"/edit_evaluations\">\n      <failure type=\"regression\""),
              std::string::npos) << xml;
    EXPECT_NE(xml.find("name=\"/memory/a&lt;b&gt;&amp;&quot;c|`\""), std::string::npos) << xml;
    EXPECT_NE(xml.find("<skipped message="), std::string::npos) << xml;
    EXPECT_EQ(measure::failure_line(gate(report(), report())), "gate: PASS");
}

}  // namespace
}  // namespace sdfbrick
