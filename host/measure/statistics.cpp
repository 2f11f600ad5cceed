#include "measure/statistics.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>

#include <fmt/format.h>

#include "core/stats.h"

namespace sdfbrick::measure {

Spread spread_of(std::vector<double> samples) {
    Spread s;
    s.samples = std::move(samples);
    if (s.samples.empty()) return s;
    s.median = median(s.samples);
    const auto [lo, hi] = std::minmax_element(s.samples.begin(), s.samples.end());
    s.min = *lo;
    s.max = *hi;
    const double n = static_cast<double>(s.samples.size());
    s.mean = std::accumulate(s.samples.begin(), s.samples.end(), 0.0) / n;
    if (s.samples.size() > 1 && s.mean > 0.0) {
        double ss = 0.0;
        for (double x : s.samples) ss += (x - s.mean) * (x - s.mean);
        s.cv = std::sqrt(ss / (n - 1.0)) / s.mean;
    }
    return s;
}

nlohmann::json to_json(const Spread& s) {
    return {{"median_ms", s.median}, {"min_ms", s.min}, {"max_ms", s.max}, {"cv", s.cv}, {"samples_ms", s.samples}};
}

std::vector<StageStats> stage_stats(const std::vector<Capture>& captures) {
    std::vector<Stage> order;
    for (const Capture& c : captures)
        for (const Launch& l : c)
            if (std::find(order.begin(), order.end(), l.stage) == order.end()) order.push_back(l.stage);
    std::vector<StageStats> out;
    for (const Stage name : order) {
        std::vector<double> ms;
        std::size_t launches = 0;
        for (const Capture& c : captures) {
            double t = 0.0;
            launches = 0;
            for (const Launch& l : c)
                if (l.stage == name) {
                    t += l.device_ms;
                    ++launches;
                }
            ms.push_back(t);
        }
        out.push_back({name, launches, spread_of(std::move(ms))});
    }
    return out;
}

Spread total_stats(const std::vector<Capture>& captures) {
    std::vector<double> ms;
    for (const Capture& c : captures) {
        double t = 0.0;
        for (const Launch& l : c) t += l.device_ms;
        ms.push_back(t);
    }
    return spread_of(std::move(ms));
}

Spread stages_stats(const std::vector<Capture>& captures, std::span<const Stage> stages) {
    std::vector<double> ms;
    for (const Capture& c : captures) {
        double t = 0.0;
        for (const Launch& l : c)
            if (std::find(stages.begin(), stages.end(), l.stage) != stages.end()) t += l.device_ms;
        ms.push_back(t);
    }
    return spread_of(std::move(ms));
}

nlohmann::json to_json(const std::vector<StageStats>& stages) {
    nlohmann::json out = nlohmann::json::array();
    for (const StageStats& s : stages) {
        nlohmann::json j = to_json(s.ms);
        j["name"] = to_string(s.stage);
        j["device_ms"] = s.ms.median;
        j["launches"] = s.launches;
        out.push_back(std::move(j));
    }
    return out;
}

std::string stage_table_text(const std::vector<StageStats>& stages, bool identical) {
    const std::size_t n = stages.empty() ? 0 : stages.front().ms.samples.size();
    std::string s = fmt::format("  {} captures (outputs identical: {})\n  {:<14} {:>8} {:>10} {:>10} {:>10} {:>7}\n", n,
                                identical ? "yes" : "NO", "stage", "launches", "median ms", "min ms", "max ms", "cv");
    for (const StageStats& st : stages)
        s += fmt::format("  {:<14} {:>8} {:>10.4f} {:>10.4f} {:>10.4f} {:>6.2f}%\n", to_string(st.stage), st.launches, st.ms.median,
                         st.ms.min, st.ms.max, 100.0 * st.ms.cv);
    return s;
}

double stage_median(const std::vector<StageStats>& stages, Stage stage) {
    for (const StageStats& s : stages)
        if (s.stage == stage) return s.ms.median;
    return 0.0;
}

std::vector<KernelRow> kernel_rows(const std::vector<Capture>& captures, const ocl::DeviceInfo& device) {
    std::map<std::string, KernelRow> rows;
    std::map<std::string, std::map<int, LevelRow>> levels;
    double all_ms = 0.0;
    for (const Capture& c : captures)
        for (const Launch& l : c) {
            KernelRow& r = rows[l.kernel];
            if (r.launches == 0) {
                r.kernel = l.kernel;
                r.min_ms = l.device_ms;
                r.largest = l;
            }
            const std::string_view stage = to_string(l.stage);
            if (r.stages.find(stage) == std::string::npos) r.stages += std::string(r.stages.empty() ? "" : ",") + std::string(stage);
            ++r.launches;
            r.total_ms += l.device_ms;
            r.min_ms = std::min(r.min_ms, l.device_ms);
            r.max_ms = std::max(r.max_ms, l.device_ms);
            if (l.work_items() > r.largest.work_items()) r.largest = l;
            all_ms += l.device_ms;
            if (l.level >= 0) {
                LevelRow& at = levels[l.kernel][l.level];
                at.level = l.level;
                ++at.launches;
                at.total_ms += l.device_ms;
                at.max_ms = std::max(at.max_ms, l.device_ms);
            }
        }
    std::vector<KernelRow> out;
    for (auto& [name, r] : rows) {
        for (auto& [level, row] : levels[name]) {
            row.mean_ms = row.total_ms / static_cast<double>(row.launches);
            r.levels.push_back(row);
        }
        r.mean_ms = r.total_ms / static_cast<double>(r.launches);
        r.share = all_ms > 0.0 ? r.total_ms / all_ms : 0.0;
        r.occupancy = occupancy(device, r.largest.attributes, r.largest.group_size(), r.largest.groups());
        out.push_back(std::move(r));
    }
    std::stable_sort(out.begin(), out.end(), [](const KernelRow& a, const KernelRow& b) { return a.total_ms > b.total_ms; });
    return out;
}

namespace {

template <class T>
std::string known(const std::optional<T>& v, const char* spec = "{}") {
    return v ? fmt::format(fmt::runtime(spec), *v) : "unknown";
}

}  // namespace

std::string kernel_table_text(const std::vector<KernelRow>& rows) {
    std::string s = fmt::format("  {:<18} {:<14} {:>8} {:>10} {:>6} {:>9} {:>9} {:>9} {:>6} {:>8} {:>5} {:>10} {:>9} {:>8}\n",
                                "kernel", "stage", "launches", "total ms", "share", "mean ms", "min ms", "max ms", "group",
                                "local B", "regs", "groups/CU", "occupancy", "waves");
    for (const KernelRow& r : rows) {
        const Occupancy& o = r.occupancy;
        s += fmt::format("  {:<18} {:<14} {:>8} {:>10.3f} {:>5.1f}% {:>9.4f} {:>9.4f} {:>9.4f} {:>6} {:>8} {:>5} {:>10} {:>9} {:>8}\n",
                         r.kernel, r.stages, r.launches, r.total_ms, 100.0 * r.share, r.mean_ms, r.min_ms, r.max_ms,
                         r.largest.group_size() ? std::to_string(r.largest.group_size()) : "driver",
                         r.largest.attributes.local_mem_bytes, known(r.largest.attributes.registers),
                         known(o.groups_per_cu_by_local), o.theoretical ? fmt::format("{:.1f}%", 100.0 * *o.theoretical) : "unknown",
                         known(o.waves, "{:.2f}"));
        if (r.levels.size() > 1)
            for (const LevelRow& l : r.levels)
                s += fmt::format("    {:<31} {:>8} {:>10.3f} {:>6} {:>9.4f} {:>9} {:>9.4f}\n", fmt::format("level {}", l.level),
                                 l.launches, l.total_ms, "", l.mean_ms, "", l.max_ms);
    }
    return s;
}

nlohmann::json to_json(const std::vector<KernelRow>& rows) {
    nlohmann::json out = nlohmann::json::array();
    for (const KernelRow& r : rows) {
        nlohmann::json levels = nlohmann::json::array();
        for (const LevelRow& l : r.levels)
            levels.push_back({{"level", l.level}, {"launches", l.launches}, {"total_ms", l.total_ms},
                              {"mean_ms", l.mean_ms}, {"max_ms", l.max_ms}});
        out.push_back({{"kernel", r.kernel},
                       {"stages", r.stages},
                       {"launches", r.launches},
                       {"total_ms", r.total_ms},
                       {"share", r.share},
                       {"mean_ms", r.mean_ms},
                       {"min_ms", r.min_ms},
                       {"max_ms", r.max_ms},
                       {"largest_launch", {{"global", r.largest.global}, {"group_size", r.largest.group_size()},
                                           {"groups", r.largest.groups()}}},
                       {"attributes", to_json(r.largest.attributes)},
                       {"occupancy", to_json(r.occupancy)},
                       {"levels", levels}});
    }
    return out;
}

}  // namespace sdfbrick::measure
