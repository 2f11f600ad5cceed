// The reports of a build and a render command: the scene, the settings as given, the job's figures
// (pipeline/report.h), every device's part and whether the devices agree bit for bit. One to_json
// (the schema of `sdfbrick build --json` and `render --json`, docs/measurement.md) and one to_text
// each. The CLI's verbs and the Python module fill them from an execution alike, so that both give
// one schema.
#pragma once

#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "construct/brick_builder.h"
#include "image/image.h"
#include "image/render_buffer.h"
#include "pipeline/executor.h"
#include "pipeline/report.h"
#include "reference/accuracy.h"
#include "render/brick_tracer.h"
#include "render/seams.h"
#include "scene/scene.h"

namespace sdfbrick::pipeline {

// A build's settings as reports record them ("brick_size", "chunk", "group", ...).
nlohmann::json settings_json(const construct::BuildSettings& s);

// ---- build ----

// One device's part of the build report: its run of the job (whole, replicate) or its launches and
// shares of the job (split).
struct DeviceBuildReport {
    ocl::DeviceInfo device;
    LaneSettings settings;  // with the tuning applied
    std::optional<BuildFigures> figures;
    std::optional<LaneFigures> lane;
};

// The whole build command's report.
struct BuildCommandReport {
    std::string file, scene;  // file: where the scene came from ("" = not from a file)
    double time = 0.0;
    std::size_t geometries = 0;
    construct::BuildSettings settings;  // as given (each device applies its tuning)
    std::optional<std::filesystem::path> tuning_db;
    int repeat = 1, warmup = 0;
    BuildFigures job;
    nlohmann::json placement;
    std::string placement_text;
    std::vector<DeviceBuildReport> devices;
    bool devices_agree = true, edit_lists_agree = true;
    std::optional<std::string> json_path;  // where the JSON report was written
};

// The report's job, devices and agreement from an execution of a Work::construct job on scene (the
// scene as built: at its time). reference_levels: also count each level's surface cells with the
// host reference (slow).
void add_execution(BuildCommandReport& report, const Execution& e, const Scene& scene, bool reference_levels);
nlohmann::json to_json(const BuildCommandReport& r);
std::string to_text(const BuildCommandReport& r, bool kernel_table);

// ---- render ----

// The render command's modes: what its picture shows.
inline constexpr std::string_view kRenderModes[] = {"normals", "depth", "shaded", "steps", "bricks"};
bool is_render_mode(std::string_view mode);

// What a render was asked for, as its report records it.
struct RenderRequest {
    std::string file;  // the scene's file ("" = not from a file)
    std::string mode = "normals";
    render::TraceSettings trace;  // size, method, normals, shading rays (shade: mode "shaded")
    bool reference = false;       // the reference tracer alone, no bricks
    bool compare = false;         // also the reference, and the accuracy against it
    int repeat = 1, warmup = 0;
};

// A device's BVH read back and checked against its bricks: with several devices the trees must
// agree too, and be valid.
struct TreeCheck {
    std::string digest;
    std::string problems;  // "" when every geometry's tree is valid
};

// The reference tracer's figures (its image goes to the pictures, not the report).
struct ReferenceFigures {
    double device_ms = 0.0;
    std::uint64_t march_steps = 0, hit_pixels = 0, unconverged_pixels = 0, fallback_points = 0, overflow_points = 0;
};

// A brick render: the run's figures and what was checked.
struct BrickRender {
    RenderFigures figures;
    std::optional<TreeCheck> tree;                       // several devices
    std::optional<reference::AccuracyMetrics> accuracy;  // compare
    std::optional<render::SeamMismatches> seams;         // compare, of an adaptive build
};

// One device's part of the render report: its run of the job (whole, replicate) or its launches and
// shares of the job (split).
struct DeviceRenderReport {
    ocl::DeviceInfo device;
    LaneSettings settings;                      // with the tuning applied
    std::optional<BrickRender> bricks;          // whole, replicate; not with the reference alone
    std::optional<LaneFigures> lane;            // split
    std::optional<ReferenceFigures> reference;  // the lanes that ran the reference tracer
    std::string digest;                         // of the image (hit and aux buffers)
    std::string difference;                     // from the first device; "" when bit-identical
};

// The whole render command's report.
struct RenderCommandReport {
    std::string file, scene;
    double time = 0.0;
    std::size_t objects = 0, geometries = 0;
    construct::BuildSettings settings;  // as given (each device applies its tuning)
    int width = 0, height = 0;
    std::string mode, method, normals;
    bool reference = false;
    int repeat = 1, warmup = 0;
    std::optional<std::pair<int, int>> shade_rays;  // shaded mode: shadow and ambient occlusion rays per pixel
    std::optional<BrickRender> job;                 // the job's render (not with the reference alone)
    std::string digest;                             // of the job's image
    std::size_t home = 0;                           // the device that holds the job's bricks
    nlohmann::json placement;
    std::string placement_text;
    std::vector<DeviceRenderReport> devices;
    bool devices_agree = true;
    std::optional<std::string> image;                                      // the picture's file (null in JSON when none)
    std::optional<std::pair<std::string, std::string>> comparison_images;  // compare: reference, difference
    std::optional<std::string> json_path;
};

// The report's scene and setup, before any device ran. scene: at time.
RenderCommandReport render_report(const RenderRequest& request, const Scene& scene, double time,
                                  const construct::BuildSettings& settings);

// The job's image and the reference's.
struct RenderImages {
    RenderBuffer buffer;
    Image shaded;  // shaded mode
    std::optional<RenderBuffer> reference;
};

// The report's job, devices and agreement from an execution of a Work::trace job on scene (at its
// time); gives the images of the job (moved out of the execution).
RenderImages add_execution(RenderCommandReport& report, Execution& e, const Scene& scene, const RenderRequest& request);
nlohmann::json to_json(const RenderCommandReport& r);
std::string to_text(const RenderCommandReport& r, bool kernel_table);

// The picture of a mode: normals (3 channels), depth (raw_depth: 1 channel, the depth on hits and 0
// on misses; else 3 channels, near surfaces bright, far ones dark, misses black), shaded (the shaded
// colour), steps (heat map), bricks (brick ids).
Image mode_picture(std::string_view mode, const RenderBuffer& buffer, const Image& shaded, bool raw_depth);

}  // namespace sdfbrick::pipeline
