// Repeat statistics (docs/measurement.md): a command's measured work runs W warm-up times, then N
// captures; each capture is the list of its launches. Per stage: median, min, max and coefficient
// of variation over the captures. Per kernel: launches, total time, share, mean/min/max per launch,
// and the attributes and occupancy of its largest launch.
#pragma once

#include <cstddef>
#include <span>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cl/device.h"
#include "measure/occupancy.h"
#include "measure/scheduler.h"

namespace sdfbrick::measure {

struct Spread {
    std::vector<double> samples;
    double median = 0.0, min = 0.0, max = 0.0, mean = 0.0;
    double cv = 0.0;  // sample standard deviation / mean; 0 for fewer than two samples or a zero mean
};
Spread spread_of(std::vector<double> samples);
// {"median_ms", "min_ms", "max_ms", "cv", "samples_ms"}
nlohmann::json to_json(const Spread& s);

using Capture = std::vector<Launch>;

struct StageStats {
    Stage stage = Stage::trace;
    std::size_t launches = 0;  // per capture (the last one)
    Spread ms;                 // the stage's device time per capture
};
// Stages in order of first appearance; a stage missing from a capture counts 0 ms there.
std::vector<StageStats> stage_stats(const std::vector<Capture>& captures);
// Total device time per capture.
Spread total_stats(const std::vector<Capture>& captures);
// Device time of the given stages per capture.
Spread stages_stats(const std::vector<Capture>& captures, std::span<const Stage> stages);
// [{"name", "device_ms" (the median), "launches", "median_ms", "min_ms", "max_ms", "cv", "samples_ms"}]
nlohmann::json to_json(const std::vector<StageStats>& stages);
// One line per stage: median, min, max, cv over the captures, and whether the outputs were identical.
std::string stage_table_text(const std::vector<StageStats>& stages, bool identical);
// The median of a stage's time; 0 when the stage is absent.
double stage_median(const std::vector<StageStats>& stages, Stage stage);

// A kernel's launches at one construction level.
struct LevelRow {
    int level = 0;
    std::size_t launches = 0;
    double total_ms = 0.0, mean_ms = 0.0, max_ms = 0.0;
};

struct KernelRow {
    std::string kernel;
    std::string stages;  // the stages that launched it, comma-separated
    std::size_t launches = 0;
    double total_ms = 0.0, share = 0.0, mean_ms = 0.0, min_ms = 0.0, max_ms = 0.0;
    Launch largest;  // the launch with the most work-items
    Occupancy occupancy;
    std::vector<LevelRow> levels;  // per level it ran at, ascending (launches of no level are not in it)
};
// Over every launch of every capture; sorted by total time, largest first. The text gives a line
// per level under a kernel that ran at more than one.
std::vector<KernelRow> kernel_rows(const std::vector<Capture>& captures, const ocl::DeviceInfo& device);
std::string kernel_table_text(const std::vector<KernelRow>& rows);
nlohmann::json to_json(const std::vector<KernelRow>& rows);

}  // namespace sdfbrick::measure
