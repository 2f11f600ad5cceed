#include "measure/gate.h"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <map>
#include <optional>
#include <set>

#include <fmt/format.h>

#include "core/errors.h"
#include "core/quote.h"

namespace sdfbrick::measure {

using nlohmann::json;

namespace {

// ---- rules ----

struct RuleName {
    GateFigure figure;
    std::string_view name;
    bool relative;  // the limit is a fraction of BASE (written as a percentage), else an amount
};

constexpr std::array<RuleName, 6> kRuleNames{{{GateFigure::digest, "digest", false},
                                               {GateFigure::counters, "counters", true},
                                               {GateFigure::mismatch, "mismatch", false},
                                               {GateFigure::depth_p99, "depth_p99", false},
                                               {GateFigure::normal_p99, "normal_p99", false},
                                               {GateFigure::time, "time", true}}};

const RuleName& rule_name(GateFigure figure) {
    return *std::find_if(kRuleNames.begin(), kRuleNames.end(), [&](const RuleName& r) { return r.figure == figure; });
}

std::string_view trimmed(std::string_view s) {
    while (!s.empty() && s.front() == ' ') s.remove_prefix(1);
    while (!s.empty() && s.back() == ' ') s.remove_suffix(1);
    return s;
}

// "<=NUMBER[%]" after a rule's name: a finite number >= 0; a percentage is divided by 100.
double parse_limit(std::string_view text, const auto& fail) {
    const bool percent = !text.empty() && text.back() == '%';
    if (percent) text.remove_suffix(1);
    text = trimmed(text);
    double value = 0.0;
    const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (text.empty() || error != std::errc() || end != text.data() + text.size())
        throw fail("expected a number (or a percentage) after <=");
    if (!std::isfinite(value) || value < 0.0) throw fail("the limit must be a finite number >= 0");
    return percent ? value / 100.0 : value;
}

GateRule parse_rule(std::string_view item) {
    const auto fail = [&](std::string_view what) {
        return InputError(fmt::format("gate rule {}: {}", quoted_input(item), what));
    };
    const std::size_t le = item.find("<=");
    std::string_view name = trimmed(item.substr(0, le));
    GateRule rule;
    rule.optional = !name.empty() && name.back() == '?';
    if (rule.optional) name = trimmed(name.substr(0, name.size() - 1));
    const auto known = std::find_if(kRuleNames.begin(), kRuleNames.end(), [&](const RuleName& r) { return r.name == name; });
    if (known == kRuleNames.end())
        throw fail("unknown rule (expected default, digest, counters, mismatch, depth_p99, normal_p99 or time, "
                   "each with ? to gate only when both reports have the figure and <=LIMIT)");
    rule.figure = known->figure;
    if (le != std::string_view::npos) {
        if (rule.figure == GateFigure::digest) throw fail("a digest takes no limit: it changes or it does not");
        rule.limit = parse_limit(item.substr(le + 2), fail);
    }
    return rule;
}

void add_rule(std::vector<GateRule>& rules, const GateRule& rule) {
    const auto same = std::find_if(rules.begin(), rules.end(), [&](const GateRule& r) { return r.figure == rule.figure; });
    if (same != rules.end()) *same = rule;
    else rules.push_back(rule);
}

// ---- values in messages ----

std::string number_text(double v) {
    if (v == std::floor(v) && std::fabs(v) < 1e15) return fmt::format("{:.0f}", v);
    return fmt::format("{:.6g}", v);
}

std::string value_text(const json& v) {
    if (v.is_null()) return "absent";
    if (v.is_string()) return escaped(v.get<std::string>(), 200);
    if (v.is_number()) return number_text(v.get<double>());
    const auto ms = [&](const char* key) { return v.is_object() && v.contains(key) && v[key].is_number(); };
    if (ms("median_ms") && ms("min_ms") && ms("max_ms"))
        return fmt::format("{:.4g} [{:.4g}, {:.4g}] ms", v["median_ms"].get<double>(), v["min_ms"].get<double>(),
                           v["max_ms"].get<double>());
    return escaped(v.dump(), 200);
}

std::string percent_text(double fraction) { return fmt::format("{:.3g}%", 100.0 * fraction); }

std::string limit_text(const GateRule& rule) {
    return rule_name(rule.figure).relative ? percent_text(rule.limit) : fmt::format("{:g}", rule.limit);
}

// ---- the reports ----

// Reports are a few levels deep; the gate walks, compares and prints them recursively, so a report
// nested deeper than this is refused (an InputError) before it is read.
constexpr std::size_t kMaxReportDepth = 64;

// Refuses what is not a report: not an object, or nested too deep (checked without recursion).
void check_report(const json& report, const std::string& file) {
    if (!report.is_object())
        throw InputError(fmt::format("{}: expected a JSON object (the report of a build or render)", escaped(file, 160)));
    std::vector<std::pair<const json*, std::size_t>> stack{{&report, 1}};
    while (!stack.empty()) {
        const auto [v, depth] = stack.back();
        stack.pop_back();
        if (depth > kMaxReportDepth)
            throw InputError(fmt::format("{}: nested deeper than {} levels: not a report", escaped(file, 160), kMaxReportDepth));
        if (v->is_structured())
            for (const json& child : *v) stack.emplace_back(&child, depth + 1);
    }
}

// ---- the runs' setup: scene and settings ----

// Settings that organise the work and change no bit of the output (docs/construction.md): they may
// differ between the reports, and the differences are noted.
constexpr std::array<std::string_view, 14> kWorkSettings{
    "chunk", "group", "eval_max_registers", "lanes", "count_parts", "count_splits", "count_untested", "cull",
    "cull_siblings", "skip_far", "apron_share_edits", "dependencies", "repeat", "warmup"};

struct Names {
    const std::string& base;
    const std::string& candidate;
};

std::string member_difference(const std::string& where, const json& a, const json& b) {
    return fmt::format("{} {} -> {}", where, value_text(a), value_text(b));
}

// Each member of a's and b's objects at `key` that differs, as "key/member A -> B".
void object_differences(const json& a, const json& b, const std::string& key, std::vector<std::string>& defining,
                        std::vector<std::string>& work) {
    const json none = json::object();
    const json& x = a.is_object() && a.contains(key) && a[key].is_object() ? a[key] : none;
    const json& y = b.is_object() && b.contains(key) && b[key].is_object() ? b[key] : none;
    std::set<std::string> members;
    for (const auto& [k, v] : x.items()) members.insert(k);
    for (const auto& [k, v] : y.items()) members.insert(k);
    for (const std::string& m : members) {
        if (m == "file") continue;  // where the scene file was: the same scene may be run from anywhere
        const json& u = x.contains(m) ? x[m] : json();
        const json& v = y.contains(m) ? y[m] : json();
        if (u == v) continue;
        const bool is_work = key == "settings" && std::find(kWorkSettings.begin(), kWorkSettings.end(), m) != kWorkSettings.end();
        if (is_work) work.push_back(member_difference(key + "/" + escaped(m), u, v) + " (a work setting: changes no bit)");
        else defining.push_back(member_difference(key + "/" + escaped(m), u, v));
    }
}

std::size_t device_count(const json& report) {
    return report.contains("devices") && report["devices"].is_array() ? report["devices"].size() : 0;
}

json device_name(const json& report, std::size_t i) {
    const json& d = report["devices"][i];
    return d.is_object() && d.contains("device") && d["device"].is_object() ? d["device"].value("name", json()) : json();
}

// The devices: how many and how placed must agree; their names may differ (noted).
void device_differences(const json& a, const json& b, std::vector<std::string>& defining, std::vector<std::string>& notes) {
    const std::size_t na = device_count(a), nb = device_count(b);
    if (na != nb) defining.push_back(fmt::format("devices {} -> {}", na, nb));
    const auto placement = [](const json& r) {
        return r.contains("placement") && r["placement"].is_object() ? r["placement"].value("placement", json()) : json();
    };
    if (placement(a) != placement(b)) defining.push_back(member_difference("placement", placement(a), placement(b)));
    for (std::size_t i = 0; i < std::min(na, nb); ++i)
        if (device_name(a, i) != device_name(b, i))
            notes.push_back(member_difference(fmt::format("device {}", i), device_name(a, i), device_name(b, i)));
}

// Refuses reports of different commands, scenes or settings unless allowed; returns the notes.
std::vector<std::string> compare_setup(const json& a, const json& b, const Names& names, const GateOptions& options) {
    std::vector<std::string> defining, notes;
    const json ca = a.value("command", json()), cb = b.value("command", json());
    if (ca != cb) defining.push_back(member_difference("command", ca, cb));
    object_differences(a, b, "scene", defining, notes);
    object_differences(a, b, "settings", defining, notes);
    device_differences(a, b, defining, notes);
    if (!defining.empty() && !options.allow_different) {
        std::string list;
        for (std::size_t i = 0; i < std::min<std::size_t>(defining.size(), 3); ++i) list += (i ? "; " : "") + defining[i];
        if (defining.size() > 3) list += fmt::format("; and {} more", defining.size() - 3);
        throw InputError(fmt::format("{} and {}: reports of different runs: {} (--allow-different gates them anyway)",
                                     escaped(names.base, 160), escaped(names.candidate, 160), list));
    }
    for (const std::string& d : defining) notes.push_back(d + " (a different run, gated by --allow-different)");
    return notes;
}

// ---- figures ----

// A report's figures for one rule: JSON pointer -> value.
using Figures = std::map<std::string, json>;

// Parts of a report that hold no gated figure (launch records, device properties, settings,
// times, the reference tracer's own work).
bool skipped_part(std::string_view key) {
    static const std::set<std::string_view> parts{
        "launches", "kernels",  "device",  "settings", "tuning",   "roofline", "reference",         "placement", "scene",
        "images",   "warnings", "stages",  "captures", "total_ms", "wall_ms",  "wall_breakdown_ms", "build_ms",  "bvh_ms",
        "trace_ms", "seams"};
    return parts.contains(key);
}

// The work counters: brick and leaf counts (per level too), edit list entries and evaluations, BVH
// nodes, node visits and brick steps per pixel, rays stopped at the step bound, and bytes of memory.
bool is_counter(std::string_view parent, std::string_view key) {
    static const std::set<std::string_view> keys{"bricks",      "leaves",     "edit_entries", "max_edits",
                                                 "edit_evaluations", "dependency_entries", "nodes", "tlas_nodes",
                                                 "node_visits", "brick_steps", "capped_rays"};
    return parent == "memory" || keys.contains(key);
}

bool reads(GateFigure rule, std::string_view parent, std::string_view key) {
    switch (rule) {
        case GateFigure::digest: return key == "digest";
        case GateFigure::counters: return is_counter(parent, key);
        case GateFigure::mismatch: return parent == "accuracy" && key == "mismatch_fraction";
        case GateFigure::depth_p99: return parent == "accuracy" && key == "depth_error_p99";
        case GateFigure::normal_p99: return parent == "accuracy" && key == "normal_error_p99_deg";
        case GateFigure::time: return false;
    }
    return false;
}

std::string pointer_token(std::string_view key) {
    std::string t;
    for (char c : key) t += c == '~' ? std::string("~0") : c == '/' ? std::string("~1") : std::string(1, c);
    return t;
}

struct Walk {
    GateFigure rule;
    const std::string& file;
    Figures& out;

    // key: the member's name (an array's elements keep the array's); parent: the enclosing member's.
    void visit(const json& v, const std::string& pointer, std::string_view parent, std::string_view key) const {
        if (v.is_object()) {
            for (const auto& [k, child] : v.items())
                if (!skipped_part(k)) visit(child, pointer + "/" + pointer_token(k), key, k);
        } else if (v.is_array()) {
            for (std::size_t i = 0; i < v.size(); ++i) visit(v[i], fmt::format("{}/{}", pointer, i), parent, key);
        } else if (reads(rule, parent, key)) {
            const bool digest = rule == GateFigure::digest;
            if (digest ? !v.is_string() : !v.is_number())
                throw InputError(fmt::format("{}: {}: expected a {}", escaped(file, 160), shortened_path(pointer),
                                             digest ? "string" : "number"));
            out[pointer] = v;
        }
    }
};

Figures figures_of(const json& report, GateFigure rule, const std::string& file) {
    Figures out;
    Walk{rule, file, out}.visit(report, "", "", "");
    return out;
}

// A device's entry repeats the job's figures (the top level): a figure at /devices/N/P whose values
// in both reports equal those at /P is checked once, at /P.
void drop_repeats(Figures& a, Figures& b) {
    for (auto it = a.begin(); it != a.end();) {
        const std::string& p = it->first;
        const std::size_t rest = p.rfind("/devices/", 0) == 0 ? p.find('/', 9) : std::string::npos;
        const auto top_a = rest == std::string::npos ? a.end() : a.find(p.substr(rest));
        const auto top_b = rest == std::string::npos ? b.end() : b.find(p.substr(rest));
        const auto here_b = b.find(p);
        if (top_a != a.end() && top_b != b.end() && here_b != b.end() && top_a->second == it->second &&
            top_b->second == here_b->second) {
            b.erase(here_b);
            it = a.erase(it);
        } else {
            ++it;
        }
    }
}

// ---- checks ----

GateCheck check_of(GateFigure rule, const std::string& pointer, const json& a, const json& b) {
    GateCheck c;
    c.rule = rule;
    c.figure = pointer;
    c.base = a;
    c.candidate = b;
    return c;
}

void judge_digest(GateCheck& c, const GateOptions& options) {
    if (!c.changed()) return;
    c.outcome = options.allow_digest_change ? GateOutcome::pass : GateOutcome::fail;
    c.note = options.allow_digest_change ? "changed (allowed by --allow-digest-change)"
                                         : "changed: the output is not bit-identical (--allow-digest-change accepts it)";
}

void judge_counter(GateCheck& c, const GateRule& rule) {
    const double a = c.base.get<double>(), b = c.candidate.get<double>();
    if (a == b) return;
    if (b < a) {
        c.note = a > 0 ? fmt::format("shrank {}", percent_text((a - b) / a)) : "shrank";
        return;
    }
    const double growth = a > 0 ? (b - a) / a : INFINITY;
    const std::string grew = a > 0 ? fmt::format("grew {}", percent_text(growth)) : std::string("grew from 0");
    c.outcome = growth > rule.limit ? GateOutcome::fail : GateOutcome::pass;
    c.note = fmt::format("{}, {} the limit of {}", grew, c.outcome == GateOutcome::fail ? "over" : "within", limit_text(rule));
}

// Accuracy figures are errors: lower is better; NEW may exceed BASE by the rule's limit.
void judge_accuracy(GateCheck& c, const GateRule& rule) {
    const double a = c.base.get<double>(), b = c.candidate.get<double>();
    if (a == b) return;
    if (b < a) {
        c.note = fmt::format("better by {}", number_text(a - b));
        return;
    }
    c.outcome = b - a > rule.limit ? GateOutcome::fail : GateOutcome::pass;
    c.note = fmt::format("worse by {}, {} the tolerance of {}", number_text(b - a),
                         c.outcome == GateOutcome::fail ? "beyond" : "within", limit_text(rule));
}

// One check per figure in either report (a figure in one report only is skipped, and said so).
void check_figures(const Figures& a, const Figures& b, const GateRule& rule, const GateOptions& options,
                   std::vector<GateCheck>& out) {
    std::set<std::string> pointers;
    for (const auto& [p, v] : a) pointers.insert(p);
    for (const auto& [p, v] : b) pointers.insert(p);
    for (const std::string& p : pointers) {
        const auto x = a.find(p), y = b.find(p);
        GateCheck c = check_of(rule.figure, p, x == a.end() ? json() : x->second, y == b.end() ? json() : y->second);
        if (x == a.end() || y == b.end()) {
            c.outcome = GateOutcome::skip;
            c.note = x == a.end() ? "only in NEW" : "only in BASE";
        } else if (rule.figure == GateFigure::digest) {
            judge_digest(c, options);
        } else if (rule.figure == GateFigure::counters) {
            judge_counter(c, rule);
        } else {
            judge_accuracy(c, rule);
        }
        out.push_back(std::move(c));
    }
}

// Where a rule's figure lives (the counters: which figures they are).
std::string figure_pointer(GateFigure rule) {
    switch (rule) {
        case GateFigure::digest: return "/digest";
        case GateFigure::counters: return "work counters (bricks, edit_evaluations, memory, work_per_pixel, ...)";
        case GateFigure::mismatch: return "/accuracy/mismatch_fraction";
        case GateFigure::depth_p99: return "/accuracy/depth_error_p99";
        case GateFigure::normal_p99: return "/accuracy/normal_error_p99_deg";
        case GateFigure::time: return "/captures/repeat";
    }
    return "";
}

std::string what_has_it(GateFigure rule) {
    switch (rule) {
        case GateFigure::digest:
        case GateFigure::counters: return "the JSON report of a build or render";
        case GateFigure::mismatch:
        case GateFigure::depth_p99:
        case GateFigure::normal_p99: return "a render --compare report";
        case GateFigure::time: return "--repeat 2 or more, with total_ms";
    }
    return "";
}

InputError missing_figure(GateFigure rule, const std::string& file) {
    const std::string_view name = to_string(rule);
    const std::string_view what = rule == GateFigure::counters ? "them" : rule == GateFigure::time ? "repeats" : "it";
    return InputError(fmt::format("{}: {}: {} (rule {} needs {} in both reports: {}; {}? gates only when both have {})",
                                  escaped(file, 160), figure_pointer(rule), rule == GateFigure::time ? "one capture" : "missing",
                                  name, what, what_has_it(rule), name, what));
}

// A rule whose figure one report (or both) lacks: an error unless the rule is optional, then one
// skipped check. Returns whether both reports have it.
bool both_have(bool in_a, bool in_b, const GateRule& rule, const Names& names, std::vector<GateCheck>& out) {
    if (in_a && in_b) return true;
    if (!rule.optional) throw missing_figure(rule.figure, in_a ? names.candidate : names.base);
    GateCheck c = check_of(rule.figure, figure_pointer(rule.figure), json(), json());
    c.outcome = GateOutcome::skip;
    const std::string_view what = rule.figure == GateFigure::time ? "no repeats" : "not there";
    c.note = fmt::format("{}: {}", !in_a && !in_b ? "BASE and NEW" : in_a ? "NEW" : "BASE", what);
    out.push_back(std::move(c));
    return false;
}

// ---- time ----

// The job's device time over the captures ({"median_ms", "min_ms", "max_ms"}), null for a report
// of one capture.
json time_spread(const json& report, const std::string& file) {
    const auto fail = [&](const std::string& at, std::string_view what) {
        return InputError(fmt::format("{}: {}: {}", escaped(file, 160), at, what));
    };
    if (!report.contains("captures")) return json();
    const json& captures = report["captures"];
    const json repeat = captures.is_object() ? captures.value("repeat", json()) : json();
    if (!repeat.is_number_integer()) throw fail("/captures/repeat", "expected an integer");
    if (repeat.get<long long>() < 2) return json();
    if (!report.contains("total_ms") || !report["total_ms"].is_object()) throw fail("/total_ms", "expected an object");
    json spread = json::object();
    for (const char* key : {"median_ms", "min_ms", "max_ms"}) {
        const json& v = report["total_ms"].value(key, json());
        if (!v.is_number()) throw fail(std::string("/total_ms/") + key, "expected a number");
        spread[key] = v;
    }
    return spread;
}

void check_time(const json& a, const json& b, const GateRule& rule, const Names& names, std::vector<GateCheck>& out) {
    const json x = time_spread(a, names.base), y = time_spread(b, names.candidate);
    if (!both_have(!x.is_null(), !y.is_null(), rule, names, out)) return;
    GateCheck c = check_of(GateFigure::time, "/total_ms", x, y);
    const auto ms = [](const json& s, const char* key) { return s[key].get<double>(); };
    const double a_med = ms(x, "median_ms"), a_lo = ms(x, "min_ms"), a_hi = ms(x, "max_ms");
    const double b_med = ms(y, "median_ms"), b_lo = ms(y, "min_ms"), b_hi = ms(y, "max_ms");
    const double growth = a_med > 0 ? (b_med - a_med) / a_med : 0.0;
    if (b_lo > a_hi) {
        c.outcome = growth > rule.limit ? GateOutcome::fail : GateOutcome::pass;
        c.note = fmt::format("slower beyond both runs' spread (the [min, max] ranges do not overlap), median +{}, {} "
                             "the limit of {}", percent_text(growth), c.outcome == GateOutcome::fail ? "over" : "within",
                             limit_text(rule));
    } else if (b_hi < a_lo) {
        c.note = fmt::format("faster beyond both runs' spread, median {}", percent_text(growth));
    } else if (x != y) {
        c.note = "the runs' [min, max] ranges overlap: no change beyond their spread";
    }
    out.push_back(std::move(c));
}

// ---- renderings ----

// How many checks of a rule (all rules: nullopt) have an outcome, and how many changed.
struct Counts {
    std::size_t checks = 0, passed = 0, failed = 0, skipped = 0, changed = 0;
};

Counts counts_of(const GateVerdict& v, std::optional<GateFigure> rule) {
    Counts n;
    for (const GateCheck& c : v.checks) {
        if (rule && c.rule != *rule) continue;
        ++n.checks;
        n.passed += c.outcome == GateOutcome::pass;
        n.failed += c.outcome == GateOutcome::fail;
        n.skipped += c.outcome == GateOutcome::skip;
        n.changed += c.changed();
    }
    return n;
}

json check_json(const GateCheck& c) {
    return {{"rule", to_string(c.rule)}, {"figure", c.figure},   {"base", c.base},
            {"new", c.candidate},        {"outcome", to_string(c.outcome)}, {"note", c.note}};
}

// Markdown text: printable ASCII; in a table cell no cell separator; outside code no HTML tag.
std::string md_text(std::string_view text, bool code, bool cell) {
    std::string out;
    for (const char c : escaped(text, 300)) {
        if (c == '|' && cell) out += "\\|";
        else if (c == '`' && code) out += '\'';
        else if (c == '<' && !code) out += "&lt;";
        else out += c;
    }
    return out;
}

std::string md_cell(std::string_view text) { return md_text(text, false, true); }
std::string md_code(std::string_view text, bool cell) { return '`' + md_text(text, true, cell) + '`'; }

// The checks `keep` selects, as a table under a heading (at most 200 rows; the JSON verdict has all).
std::string md_checks(const GateVerdict& v, std::string_view title, const auto& keep) {
    constexpr std::size_t kRows = 200;
    std::string rows;
    std::size_t n = 0;
    for (const GateCheck& c : v.checks) {
        if (!keep(c)) continue;
        if (++n <= kRows)
            rows += fmt::format("| {} | {} | {} | {} | {} |\n", to_string(c.rule), md_code(c.figure, true),
                                md_cell(value_text(c.base)), md_cell(value_text(c.candidate)), md_cell(c.note));
    }
    if (n == 0) return "";
    if (n > kRows) rows += fmt::format("\n... and {} more (the JSON verdict, --json, has every check)\n", n - kRows);
    return fmt::format("\n### {} ({})\n\n| rule | figure | BASE | NEW | |\n| --- | --- | ---: | ---: | --- |\n{}", title, n,
                       rows);
}

std::string xml_text(std::string_view text) {
    std::string out;
    for (const char c : escaped(text, 1000)) {
        switch (c) {
            case '&': out += "&amp;"; break;
            case '<': out += "&lt;"; break;
            case '>': out += "&gt;"; break;
            case '"': out += "&quot;"; break;
            case '\'': out += "&apos;"; break;
            default: out += c;
        }
    }
    return out;
}

std::string check_line(const GateCheck& c) {
    return fmt::format("{} -> {}: {}", value_text(c.base), value_text(c.candidate), c.note);
}

std::string junit_case(const GateCheck& c) {
    const std::string head = fmt::format("    <testcase classname=\"gate.{}\" name=\"{}\"", to_string(c.rule), xml_text(c.figure));
    switch (c.outcome) {
        case GateOutcome::fail:
            return fmt::format("{}>\n      <failure type=\"regression\" message=\"{}\"/>\n    </testcase>\n", head,
                               xml_text(check_line(c)));
        case GateOutcome::skip:
            return fmt::format("{}>\n      <skipped message=\"{}\"/>\n    </testcase>\n", head, xml_text(c.note));
        case GateOutcome::pass: break;
    }
    return head + "/>\n";
}

}  // namespace

// ---- public ----

std::string_view to_string(GateFigure figure) { return rule_name(figure).name; }

std::string_view to_string(GateOutcome outcome) {
    switch (outcome) {
        case GateOutcome::pass: return "pass";
        case GateOutcome::fail: return "fail";
        case GateOutcome::skip: return "skip";
    }
    return "";
}

std::vector<GateRule> parse_gate_rules(std::string_view text) {
    std::vector<GateRule> rules;
    if (trimmed(text).empty()) throw InputError("gate rules: empty (expected default or a list such as digest,counters<=2%)");
    std::size_t start = 0;
    while (start <= text.size()) {
        const std::size_t comma = std::min(text.find(',', start), text.size());
        const std::string_view item = trimmed(text.substr(start, comma - start));
        if (item.empty()) throw InputError(fmt::format("gate rules {}: an empty item", quoted_input(text)));
        if (item == "default") {
            for (const GateRule& r : parse_gate_rules(kDefaultGateRules)) add_rule(rules, r);
        } else {
            add_rule(rules, parse_rule(item));
        }
        start = comma + 1;
    }
    return rules;
}

std::string gate_rules_text(const std::vector<GateRule>& rules) {
    std::string s;
    for (const GateRule& r : rules) {
        s += fmt::format("{}{}{}", s.empty() ? "" : ",", to_string(r.figure), r.optional ? "?" : "");
        if (r.limit > 0.0) s += "<=" + limit_text(r);
    }
    return s;
}

std::size_t GateVerdict::count(GateOutcome outcome) const {
    return static_cast<std::size_t>(
        std::count_if(checks.begin(), checks.end(), [&](const GateCheck& c) { return c.outcome == outcome; }));
}

GateVerdict gate_reports(const json& base, const json& candidate, const std::vector<GateRule>& rules,
                         const GateOptions& options, const std::string& base_name, const std::string& candidate_name) {
    const Names names{base_name, candidate_name};
    check_report(base, base_name);
    check_report(candidate, candidate_name);
    GateVerdict v{base_name, candidate_name, rules, compare_setup(base, candidate, names, options), {}};
    for (const GateRule& rule : rules) {
        if (rule.figure == GateFigure::time) {
            check_time(base, candidate, rule, names, v.checks);
            continue;
        }
        Figures a = figures_of(base, rule.figure, base_name), b = figures_of(candidate, rule.figure, candidate_name);
        if (!both_have(!a.empty(), !b.empty(), rule, names, v.checks)) continue;
        drop_repeats(a, b);
        check_figures(a, b, rule, options, v.checks);
    }
    return v;
}

}  // namespace sdfbrick::measure

namespace sdfbrick::measure {

json to_json(const GateVerdict& v) {
    const Counts n = counts_of(v, std::nullopt);
    json checks = json::array();
    for (const GateCheck& c : v.checks) checks.push_back(check_json(c));
    return {{"passed", v.passed()},
            {"base", v.base_name},
            {"new", v.candidate_name},
            {"rules", gate_rules_text(v.rules)},
            {"counts", {{"checks", n.checks}, {"passed", n.passed}, {"failed", n.failed}, {"skipped", n.skipped},
                        {"changed", n.changed}}},
            {"setup", v.setup},
            {"checks", checks}};
}

std::string to_markdown(const GateVerdict& v) {
    const Counts all = counts_of(v, std::nullopt);
    std::string s = fmt::format("## sdfbrick compare --gate: {}\n\nBASE {}, NEW {}, rules {}: {} checks, {} passed, "
                                "{} failed, {} skipped.\n\n| rule | checks | passed | failed | skipped | changed |\n"
                                "| --- | ---: | ---: | ---: | ---: | ---: |\n",
                                v.passed() ? "PASS" : "FAIL", md_code(v.base_name, false), md_code(v.candidate_name, false),
                                md_code(gate_rules_text(v.rules), false), all.checks, all.passed, all.failed, all.skipped);
    for (const GateRule& r : v.rules) {
        const Counts n = counts_of(v, r.figure);
        s += fmt::format("| {} | {} | {} | {} | {} | {} |\n", to_string(r.figure), n.checks, n.passed, n.failed, n.skipped,
                         n.changed);
    }
    s += md_checks(v, "Failed", [](const GateCheck& c) { return c.outcome == GateOutcome::fail; });
    s += md_checks(v, "Changed within the rules",
                   [](const GateCheck& c) { return c.outcome == GateOutcome::pass && c.changed(); });
    s += md_checks(v, "Skipped", [](const GateCheck& c) { return c.outcome == GateOutcome::skip; });
    if (!v.setup.empty()) {
        s += "\n### Runs\n\n";
        for (const std::string& note : v.setup) s += "- " + md_text(note, false, false) + "\n";
    }
    return s;
}

std::string to_junit(const GateVerdict& v) {
    const Counts n = counts_of(v, std::nullopt);
    const std::string totals =
        fmt::format("tests=\"{}\" failures=\"{}\" skipped=\"{}\" errors=\"0\"", n.checks, n.failed, n.skipped);
    std::string s = fmt::format("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<testsuites name=\"sdfbrick compare --gate\" {}>\n"
                                "  <testsuite name=\"{}\" {}>\n    <properties>\n"
                                "      <property name=\"rules\" value=\"{}\"/>\n",
                                totals, xml_text(v.base_name + " -> " + v.candidate_name), totals,
                                xml_text(gate_rules_text(v.rules)));
    for (const std::string& note : v.setup) s += fmt::format("      <property name=\"run\" value=\"{}\"/>\n", xml_text(note));
    s += "    </properties>\n";
    for (const GateCheck& c : v.checks) s += junit_case(c);
    return s + "  </testsuite>\n</testsuites>\n";
}

std::string failure_line(const GateVerdict& v) {
    const auto first = std::find_if(v.checks.begin(), v.checks.end(), [](const GateCheck& c) { return c.outcome == GateOutcome::fail; });
    if (first == v.checks.end()) return "gate: PASS";
    return escaped(fmt::format("gate: FAIL: {} of {} checks failed; the first: {} {}: {}", v.count(GateOutcome::fail),
                               v.checks.size(), to_string(first->rule), first->figure, check_line(*first)),
                   400);
}

}  // namespace sdfbrick::measure
