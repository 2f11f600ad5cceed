// The stability atlas (docs/stability.md): hard cases (scenes/stability/, `scene generate
// stability/NAME`) x in-brick methods x normal rules x storage formats x uniform/adaptive builds, each
// cell traced and measured against the device reference tracer (reference::compare), with the
// thresholds that make a cell fail stated once, here.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/files.h"
#include "cl/device.h"
#include "construct/brick_layout.h"
#include "reference/accuracy.h"
#include "render/brick_tracer.h"
#include "tune/tuning_db.h"

namespace sdfbrick::sweep {

// A cell fails when any measure exceeds its threshold (docs/stability.md says why each is where it is),
// when any ray stopped at a kernel loop bound (the step cap), or when devices differ.
struct StabilityThresholds {
    double mismatch_fraction = 0.001;  // pixels hit in one image only, of the pixels compared
    double depth_p99_voxels = 1.0;     // depth error, 99th percentile, in the object's finest voxels
    double normal_p99_deg = 10.0;      // angle between the normals, 99th percentile
};
inline constexpr StabilityThresholds kStabilityThresholds{};

// One case: a scene file and the finest brick size it is built at.
struct StabilityCase {
    std::string file;
    double brick_size = 0.125;
};

// "FILE" or "FILE@BRICK_SIZE" (default_brick_size when no size is given); throws InputError naming
// the text for a size that is not a number > 0.
StabilityCase parse_case(const std::string& text, double default_brick_size);

struct StabilitySpec {
    std::vector<StabilityCase> cases;
    std::vector<render::Method> methods;         // empty: render::kMethods
    std::vector<render::NormalMethod> normals;   // empty: render::kNormalMethods
    std::vector<construct::BrickFormat> formats;  // empty: int8, int16, float
    std::vector<bool> adaptive;                  // empty: uniform and adaptive
    double tolerance_voxels = 0.25;              // adaptive builds: tolerance in voxels of the finest brick
    int width = 321, height = 181;               // odd: the centre row and column of rays are exact (face_rays)
    std::optional<std::string> pictures;         // folder for each case's reference, render and difference pictures
    const tune::TuningDb* tuning = nullptr;      // each device's tuned chunk and work-groups (change no bit); null: off
};

// One cell: a case with one method, normal rule, format and build, on every selected device.
struct StabilityCell {
    std::string case_name, file;
    double brick_size = 0.0;
    render::Method method = render::Method::sphere;
    render::NormalMethod normals = render::NormalMethod::continuous;
    construct::BrickFormat format = construct::BrickFormat::int8;
    double tolerance = 0.0;  // geometry units; 0 = uniform
    // On the first device, against its reference tracer; depth in each pixel's object's finest voxel.
    reference::AccuracyMetrics accuracy;
    std::uint64_t capped_rays = 0;      // first device: rays whose search in some brick stopped at a loop bound
    std::vector<std::string> warnings;  // first device: the trace's warnings (render/warnings.h), one line each
    std::uint64_t bricks = 0;
    double build_ms = 0.0, trace_ms = 0.0;  // first device, device time of the construction and the trace
    std::optional<std::uint64_t> device_differences;  // several devices: pixels whose hit or normal differ from the first's
    std::optional<std::string> error;       // the cell could not run (the message); counts as a failure
    // The thresholds exceeded: "mismatch", "depth", "normals", "step cap", "devices", "error".
    std::vector<std::string> failures;

    bool failed() const { return !failures.empty(); }
};

struct StabilityReport {
    StabilityThresholds thresholds;
    std::vector<std::string> devices;  // names; the first one's accuracy is reported
    int width = 0, height = 0;
    double tolerance_voxels = 0.0;
    std::vector<StabilityCell> cells;  // cases outermost, then formats, builds, methods, normals
    double seconds = 0.0;              // wall time of the whole run
    // With spec.pictures, each case's pictures, encoded and ready to write (into that folder) with the
    // report, all or none: run_stability itself writes nothing.
    std::vector<Output> pictures;
};

struct StabilityProgress {
    std::size_t done = 0, total = 0;
    double elapsed_s = 0.0, eta_s = 0.0;  // eta from the mean time per cell so far
    std::string current;                  // the case being run
};

// Runs every cell of spec on devices (all of them run every cell). A cell that throws is recorded with
// its error; bad input that concerns the whole run (a scene file that does not load) is thrown.
StabilityReport run_stability(const StabilitySpec& spec, ocl::DeviceSet& devices,
                              const std::function<void(const StabilityProgress&)>& progress);

// Writes the report's pictures into spec.pictures (made when missing) with `others` (a JSON report)
// as one write_all; when the write fails, a folder it made is taken away again. Check the folder with
// check_output_folder before the run.
void write_stability_outputs(const StabilityReport& report, const StabilitySpec& spec, std::vector<Output> others = {});

// The thresholds exceeded by the accuracy figures of a cell.
std::vector<std::string> threshold_failures(const reference::AccuracyMetrics& a, const StabilityThresholds& t);

// {"command": "stability", "thresholds", "devices", "width", "height", "tolerance_voxels", "seconds",
//  "cells": [...]} (docs/stability.md).
nlohmann::json to_json(const StabilityReport& r);
// A table per case: one line per cell, and the failure rate of each method over its cells.
std::string to_text(const StabilityReport& r);

}  // namespace sdfbrick::sweep
