#include "measure/compare.h"

#include <algorithm>
#include <unordered_map>

#include <fmt/format.h>

#include "core/errors.h"

namespace sdfbrick::measure {

namespace {

struct Side {
    std::string device;
    nlohmann::json stages;
};

// Refuses (InputError naming the file and the JSON path) a stage list that is not an array of
// objects with a string "name" and numeric times.
void check_stages(const nlohmann::json& stages, const std::string& which, const std::string& path) {
    const auto fail = [&](const std::string& at, std::string_view what) {
        return InputError(fmt::format("{}: {}: {}", which, at, what));
    };
    if (!stages.is_array()) throw fail(path, "expected an array of stages");
    for (std::size_t i = 0; i < stages.size(); ++i) {
        const nlohmann::json& s = stages[i];
        const std::string at = fmt::format("{}/{}", path, i);
        if (!s.is_object()) throw fail(at, "expected a stage object");
        if (!s.contains("name") || !s["name"].is_string()) throw fail(at + "/name", "expected a string");
        for (const char* key : {"median_ms", "device_ms", "min_ms", "max_ms"})
            if (s.contains(key) && !s[key].is_number()) throw fail(at + "/" + key, "expected a number");
    }
}

std::vector<Side> sides(const nlohmann::json& report, const std::string& which) {
    std::vector<Side> out;
    if (report.contains("devices") && report["devices"].is_array())
        for (std::size_t i = 0; i < report["devices"].size(); ++i) {
            const nlohmann::json& d = report["devices"][i];
            if (!d.is_object() || !d.contains("stages")) continue;
            check_stages(d["stages"], which, fmt::format("/devices/{}/stages", i));
            const bool named = d.contains("device") && d["device"].is_object() && d["device"].contains("name") &&
                               d["device"]["name"].is_string();
            out.push_back({named ? d["device"]["name"].get<std::string>() : "?", d["stages"]});
        }
    if (out.empty() && report.is_object() && report.contains("stages")) {
        check_stages(report["stages"], which, "/stages");
        out.push_back({"", report["stages"]});
    }
    if (out.empty()) throw InputError(fmt::format("{}: no per-stage times (expected the JSON report of a build or render)", which));
    return out;
}

void range(const nlohmann::json& s, double& median, double& lo, double& hi) {
    median = s.value("median_ms", s.value("device_ms", 0.0));
    lo = s.value("min_ms", median);
    hi = s.value("max_ms", median);
}

void add_pair(const Side& a, const Side& b, std::vector<StageDelta>& out) {
    const std::string device = a.device == b.device ? a.device : a.device + " -> " + b.device;
    // Stages by name in order of first appearance (A's, then B's own); a name given twice in a report
    // takes its last entry. One pass over each report: large reports compare in linear time.
    std::vector<StageDelta> deltas;
    std::unordered_map<std::string, std::size_t> index;
    const auto entry = [&](const std::string& name) -> StageDelta& {
        const auto [it, added] = index.try_emplace(name, deltas.size());
        if (added) {
            deltas.push_back({device, name});
            deltas.back().in_a = deltas.back().in_b = false;
        }
        return deltas[it->second];
    };
    for (const auto& s : a.stages) {
        StageDelta& d = entry(s.value("name", ""));
        range(s, d.a_median, d.a_min, d.a_max);
        d.in_a = true;
    }
    for (const auto& s : b.stages) {
        StageDelta& d = entry(s.value("name", ""));
        range(s, d.b_median, d.b_min, d.b_max);
        d.in_b = true;
    }
    StageDelta total{device, "total"};
    for (const StageDelta& d : deltas) {
        total.a_median += d.a_median;
        total.b_median += d.b_median;
        total.a_min += d.a_min;
        total.a_max += d.a_max;
        total.b_min += d.b_min;
        total.b_max += d.b_max;
        out.push_back(d);
    }
    out.push_back(total);  // the sum of ranges bounds the total's range
}

}  // namespace

std::vector<StageDelta> compare_reports(const nlohmann::json& a, const nlohmann::json& b, const std::string& name_a,
                                        const std::string& name_b) {
    const std::vector<Side> sa = sides(a, name_a), sb = sides(b, name_b);
    std::vector<StageDelta> out;
    if (sa.size() == 1 && sb.size() == 1) {
        add_pair(sa[0], sb[0], out);
        return out;
    }
    for (const Side& x : sa)
        for (const Side& y : sb)
            if (x.device == y.device) add_pair(x, y, out);
    if (out.empty()) throw InputError("compare: the reports share no device name");
    return out;
}

std::string compare_text(const std::vector<StageDelta>& deltas) {
    std::string s = fmt::format("{:<14} {:>22} {:>22} {:>10} {:>8}  {}\n", "stage", "A median [min, max] ms",
                                "B median [min, max] ms", "delta ms", "delta", "");
    std::string device = "\x01";
    std::size_t flagged = 0;
    for (const StageDelta& d : deltas) {
        if (d.device != device) {
            device = d.device;
            if (!device.empty()) s += fmt::format("device {}\n", device);
        }
        const auto side = [](bool present, double m, double lo, double hi) {
            return present ? fmt::format("{:.4f} [{:.4f}, {:.4f}]", m, lo, hi) : std::string("absent");
        };
        const char* mark = !d.in_a || !d.in_b ? "only in one report" : d.significant() ? (d.delta_ms() > 0 ? "SLOWER" : "FASTER") : "";
        flagged += d.stage != "total" && d.significant();
        s += fmt::format("{:<14} {:>22} {:>22} {:>+10.4f} {:>+7.1f}%  {}\n", d.stage, side(d.in_a, d.a_median, d.a_min, d.a_max),
                         side(d.in_b, d.b_median, d.b_min, d.b_max), d.delta_ms(), 100.0 * d.delta_fraction(), mark);
    }
    s += fmt::format("{} stage(s) changed by more than the runs' own spread (their [min, max] ranges do not overlap); "
                     "a report of one capture has no spread: repeat the captures\n", flagged);
    return s;
}

}  // namespace sdfbrick::measure
