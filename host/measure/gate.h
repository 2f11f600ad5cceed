// `sdfbrick compare BASE.json NEW.json --gate RULES`: a verdict on whether a new build or render
// report regressed against a base report, from the figures that are deterministic (digests,
// accuracy against the reference, work counters) and from times only where both reports have
// repeats whose spreads do not overlap. docs/ci-gate.md has the rules and what each one reads.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

namespace sdfbrick::measure {

// What a rule reads.
enum class GateFigure { digest, counters, mismatch, depth_p99, normal_p99, time };
std::string_view to_string(GateFigure figure);

struct GateRule {
    GateFigure figure = GateFigure::digest;
    bool optional = false;  // "name?": gated only when both reports have the figure; else a report without it is bad input
    double limit = 0.0;     // how much worse NEW may be: a fraction of BASE for counters and time, an amount for accuracy
};

// The rules `default` stands for.
inline constexpr std::string_view kDefaultGateRules =
    "digest,counters<=2%,mismatch?<=0.0001,depth_p99?<=0.01,normal_p99?<=0.1,time?";

// Parses a comma-separated list of `NAME[?][<=NUMBER[%]]` (a digest takes no limit) and `default`
// (the list above, in its place); a rule named again replaces the earlier one ("default,time?<=5%").
// Throws InputError naming the item that does not parse.
std::vector<GateRule> parse_gate_rules(std::string_view text);
// The rules written back in the grammar ("counters<=2%", "mismatch?<=0.0001").
std::string gate_rules_text(const std::vector<GateRule>& rules);

struct GateOptions {
    bool allow_digest_change = false;  // a changed digest passes (it is still reported)
    bool allow_different = false;      // gate reports of different scenes or settings (the differences are noted)
};

enum class GateOutcome { pass, fail, skip };
std::string_view to_string(GateOutcome outcome);

// One figure checked by one rule.
struct GateCheck {
    GateFigure rule = GateFigure::digest;
    std::string figure;               // the JSON pointer of the figure in the reports ("/devices/0/edit_evaluations")
    nlohmann::json base, candidate;   // its values in BASE and NEW; null where a report lacks it
    GateOutcome outcome = GateOutcome::pass;
    std::string note;                 // what changed and how it compares with the rule's limit; empty when unchanged
    bool changed() const { return base != candidate; }
};

struct GateVerdict {
    std::string base_name, candidate_name;  // the reports' files
    std::vector<GateRule> rules;
    std::vector<std::string> setup;         // how the reports' runs differ where the gate allows it (work settings, devices)
    std::vector<GateCheck> checks;
    std::size_t count(GateOutcome outcome) const;
    bool passed() const { return count(GateOutcome::fail) == 0; }
};

// Gates NEW (candidate) against BASE. Throws InputError, naming the report and the JSON path, for a
// report that is not an object, a figure of the wrong type, reports of different commands, scenes
// or settings (unless options.allow_different), and a report without the figure a rule that is not
// optional needs.
GateVerdict gate_reports(const nlohmann::json& base, const nlohmann::json& candidate, const std::vector<GateRule>& rules,
                         const GateOptions& options = {}, const std::string& base_name = "BASE",
                         const std::string& candidate_name = "NEW");

// The verdict as JSON: {"passed", "base", "new", "rules", "counts", "setup", "checks": [...]}.
nlohmann::json to_json(const GateVerdict& verdict);
// Markdown: the verdict, a table per rule, then the failed, changed and skipped checks.
std::string to_markdown(const GateVerdict& verdict);
// JUnit XML: one test case per check (failures and skips as JUnit has them).
std::string to_junit(const GateVerdict& verdict);
// One line for a failed verdict: how many checks failed and the first of them.
std::string failure_line(const GateVerdict& verdict);

}  // namespace sdfbrick::measure
