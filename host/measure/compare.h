// `sdfbrick compare A.json B.json`: per-stage deltas between two reports of build or render (or any
// report with per-device "stages" carrying median/min/max), flagging a delta when the two runs'
// [min, max] ranges do not overlap: the change is larger than the runs' own spread.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace sdfbrick::measure {

struct StageDelta {
    std::string device;  // "A name" or "A name -> B name" when the devices differ
    std::string stage;   // a stage name, or "total"
    double a_median = 0, a_min = 0, a_max = 0;
    double b_median = 0, b_min = 0, b_max = 0;
    bool in_a = true, in_b = true;  // a stage present in one report only has zeros in the other
    double delta_ms() const { return b_median - a_median; }
    double delta_fraction() const { return a_median > 0 ? delta_ms() / a_median : 0.0; }
    bool significant() const { return in_a && in_b && (b_min > a_max || b_max < a_min); }
};

// Devices are paired by name; when each report has exactly one device they are paired whatever their
// names (a vendor comparison). name_a and name_b name the reports (their files) in errors: an
// InputError names the report and the JSON path of a stage list that is missing or wrongly typed.
std::vector<StageDelta> compare_reports(const nlohmann::json& a, const nlohmann::json& b, const std::string& name_a = "A",
                                        const std::string& name_b = "B");
std::string compare_text(const std::vector<StageDelta>& deltas);

}  // namespace sdfbrick::measure
