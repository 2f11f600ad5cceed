// A sweep point's result: one row of the sweep's CSV and one object of its JSON "points"
// (docs/sweep.md). The columns are one list of (name, accessor): the CSV header and cells, the JSON
// object, and reading a row back (the resume cache, merge) all go through it.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "measure/stage.h"
#include "measure/statistics.h"

namespace sdfbrick::sweep {

// brick_evaluate's occupancy proxies (measure::KernelRow); empty = unknown.
struct EvaluateOccupancy {
    std::uint64_t local_bytes = 0;
    std::optional<int> registers;
    std::optional<std::uint64_t> groups_per_cu, resident_groups;
    std::optional<double> occupancy, waves;
};

// Brick-pool bytes per second of the evaluate stage.
struct WriteBandwidth {
    double gbps = 0.0;
    double fraction = 0.0;  // of the device's measured bandwidth
};

// Against the reference tracer (reference::AccuracyMetrics): fraction; voxels; degrees; dB.
struct PointAccuracy {
    double mismatch = 0.0, depth_mean = 0.0, depth_p99 = 0.0, normal_mean = 0.0, normal_p99 = 0.0;
    std::optional<double> psnr;  // empty when infinite (identical images)
};

// What a point that ran measured.
struct PointResults {
    bool identical = true;  // every capture gave the same bricks and image
    std::uint64_t bricks = 0;
    int levels = 0;
    std::uint64_t edit_evaluations = 0;
    std::uint64_t memory_bytes = 0;      // construction and BVH, every resource
    std::uint64_t pool_bytes = 0;        // the brick pools
    double check_error_max = 0.0;        // adaptive: the check points' worst error (geometry units)
    measure::Spread build_ms, trace_ms;  // the columns keep median, min, max and cv
    double bvh_ms = 0.0;
    std::array<double, measure::kConstructionStages.size()> stage_ms{};  // medians, kConstructionStages' order
    std::optional<EvaluateOccupancy> evaluate;                            // when brick_evaluate ran
    double evaluations_per_second = 0.0;
    std::optional<WriteBandwidth> write;  // when the evaluate stage took time
    double peak_bandwidth_gbps = 0.0, peak_fma_gflops = 0.0;
    std::optional<PointAccuracy> accuracy;  // with the sweep's accuracy on
};

struct SweepRow {
    // What ran where, and the parameters: chunk, group and trace group are the values used, empty
    // ("auto") only for a point that failed before they were resolved.
    std::size_t index = 0;  // position in the full grid
    std::string scene, scene_file, device, vendor, driver, platform;
    double brick_size = 0.0;
    double tolerance = 0.0;  // adaptive leaves; 0: uniform
    std::optional<int> chunk, group;
    std::optional<std::string> trace_group;
    bool cull = true;
    std::string format, method, normals;
    int samples = 0;
    int width = 0, height = 0, repeats = 0;
    std::string key;  // SweepPoint::key: the point's identity for the resume cache and merge
    // The outcome.
    std::string status = "ok";  // "ok" or "error"
    std::optional<std::string> error;
    std::optional<PointResults> results;  // with status "ok"

    bool ok() const { return status == "ok"; }
};

// One column: its name and how it reads from a row and writes into one.
struct Column {
    std::string name;
    bool csv = true;  // false: in the JSON only
    // The value (null: unknown or "auto"); nullopt: the row has no such value (a part it lacks), so
    // the JSON object leaves the key out.
    std::function<std::optional<nlohmann::json>(const SweepRow&)> get;
    // Sets the value (null: empty), creating the part of the row that holds it.
    std::function<void(SweepRow&, const nlohmann::json&)> set;
};

// Every column: parameters, outcome, results, in CSV order; then the JSON-only key.
const std::vector<Column>& columns();
// The names of the CSV's columns, in order.
std::vector<std::string> csv_columns();

// Every column the row has.
nlohmann::json to_json(const SweepRow& row);
nlohmann::json to_json(const std::vector<SweepRow>& rows);
// The columns present in j (others keep their defaults; unknown keys are ignored). Throws InputError
// ("/COLUMN: expected ...") for anything but an object, and for a value of the wrong type or range.
SweepRow row_from_json(const nlohmann::json& j);

// A header line of the CSV columns, then one line per row; an absent or null value is an empty cell;
// text is quoted when it holds a comma, a quote or a line break.
std::string to_csv(const std::vector<SweepRow>& rows);

}  // namespace sdfbrick::sweep
