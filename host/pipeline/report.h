// The figures a report gives about one device's measured run (a pipeline::Run): construction per
// geometry and in total, the stages and their spreads over the captures, the kernels, digests, and
// for a traced run the BVH, memory, rays per second and work per pixel. Plain data, filled once from
// the run; `sdfbrick build` and `render` print them (one to_json, one to_text each) inside their
// command reports, and the sweep takes its row's columns from them.
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <glm/vec3.hpp>
#include <nlohmann/json.hpp>

#include "cl/device.h"
#include "construct/brick_builder.h"
#include "measure/peaks.h"
#include "measure/statistics.h"
#include "pipeline/executor.h"
#include "pipeline/run.h"
#include "render/pictures.h"

namespace sdfbrick::pipeline {

using Memory = std::map<std::string, std::uint64_t>;  // bytes per resource

// Where a capture's wall time went (medians over the captures; pipeline::Run's *_wall_ms): beside the
// device time, what explains a gap between the two.
struct WallBreakdown {
    double total = 0.0, construct = 0.0, bvh = 0.0, trace = 0.0, digests = 0.0;
    double setup = 0.0;  // once, before the first pass: Run::setup_ms
};
WallBreakdown wall_breakdown(const Run& run);
// {"total", "construct", "bvh", "trace", "digests", "setup_once"} in ms
nlohmann::json to_json(const WallBreakdown& w);
// "wall 8.36 ms a capture (construct 6.86, digests 1.50)": the parts that took time
std::string to_text(const WallBreakdown& w);

// One geometry's construction in the last capture (a GeometryBuild without its device buffers).
struct GeometryFigures {
    std::string name;
    glm::vec3 origin{0.0f};
    float leaf_size = 0.0f;
    int levels = 0;
    float clamp_c = 0.0f, band = 0.0f;
    std::vector<construct::LevelReport> level_table;
    double tolerance = 0.0;  // adaptive builds; 0: uniform
    double check_error_max = 0.0, check_error_p99 = 0.0;  // the check points' worst error over the leaves
    std::uint64_t brick_bytes = 0;                         // one brick's samples
    std::uint64_t bricks = 0;
    double edits_per_leaf_mean = 0.0;
    std::uint32_t edits_per_leaf_max = 0;
    std::uint64_t edit_evaluations = 0, dependency_entries = 0;
    std::uint64_t pool_bytes = 0;
    Memory memory;
    std::map<measure::Stage, construct::StageWork> work;
    double device_ms = 0.0, host_ms = 0.0;
    measure::Capture launches;  // this geometry's launches in the last capture
};

// Construction summed over the geometries.
struct ConstructionFigures {
    std::vector<GeometryFigures> geometries;
    std::uint64_t bricks = 0, edit_evaluations = 0, pool_bytes = 0;
    std::uint64_t leaf_edit_entries = 0;  // sum of the leaf bricks' edit-list lengths
    std::uint32_t edits_per_leaf_max = 0;
    int levels = 0;  // the deepest geometry's
    double host_ms = 0.0;
    Memory memory;
    std::map<measure::Stage, construct::StageWork> work;  // summed over the geometries

    double edits_per_leaf_mean() const;
};
ConstructionFigures construction_figures(const Run& run);

// One stage on the roofline: its work (construct/work.h) over its median device time.
struct RooflineRow {
    measure::Stage stage{};
    double ms = 0.0, flop = 0.0, bytes = 0.0;
    double gflops() const { return ms > 0.0 ? flop / (ms * 1e6) : 0.0; }
    double gbps() const { return ms > 0.0 ? bytes / (ms * 1e6) : 0.0; }
};

// `sdfbrick build` on one device: a construction run with brick digests.
struct BuildFigures {
    ConstructionFigures construction;
    std::vector<measure::StageStats> stages;
    measure::Spread total_ms;
    measure::Spread wall_ms;  // each capture's wall time (pipeline::Run::wall_ms)
    WallBreakdown wall;
    std::size_t captures = 0;
    bool identical = true;  // every capture gave the same bricks, pools and edit lists
    std::vector<measure::KernelRow> kernels;
    std::string digest, list_digest;  // bricks and pools; edit lists
    std::vector<RooflineRow> roofline;        // count, cull, evaluate
    std::optional<measure::DevicePeaks> peaks;  // the device's cached peaks (`devices --peaks`), if any

    double bricks_per_second() const;
    double edit_evaluations_per_second() const;
};
BuildFigures build_figures(const Run& run, const ocl::DeviceInfo& device);
// Fills every level's reference_cells with the host reference's surface cells of that level
// (reference::count_surface_cells over the same domain). scene: the one that was built.
void add_reference_levels(ConstructionFigures& c, const Scene& scene, const construct::BuildSettings& s);
// {"bricks", "digest", "list_digest", "stages", "device_ms", "host_ms", "total_ms", "wall_ms", "wall_breakdown_ms", "captures",
//  "kernels", "memory", "edits_per_leaf", "edit_evaluations", "bricks_per_second",
//  "edit_evaluations_per_second", "geometries", "roofline"} (docs/measurement.md)
nlohmann::json to_json(const BuildFigures& f);
// Per geometry its level table and memory, then the stages, repeat statistics, the kernel table
// (with kernel_table) and the digests; lines indented for a device's section.
std::string to_text(const BuildFigures& f, bool kernel_table);

struct BvhFigures {
    std::uint64_t nodes = 0, tlas_nodes = 0;
    std::uint64_t leaves = 0;  // bricks in the trees: those that can hold a hit
    std::size_t instances = 0;
    double device_ms = 0.0;  // the last capture's
    Memory memory;
};

// `sdfbrick render` on one device (and a sweep point): construction, BVH and trace.
struct RenderFigures {
    ConstructionFigures construction;
    BvhFigures bvh;
    std::optional<std::uint64_t> combined_pool_bytes;  // several geometries: their pools in one
    double voxel_world = 0.0;
    std::vector<measure::StageStats> stages;
    measure::Spread build_ms, bvh_ms, trace_ms;
    measure::Spread total_ms, wall_ms;  // device time of all launches, and wall time, per capture
    WallBreakdown wall;
    int warmup = 0;
    std::size_t captures = 0;
    bool identical = true;  // every capture gave the same bricks and image
    std::vector<measure::KernelRow> kernels;
    int width = 0, height = 0;
    int group_x = 0, group_y = 0;  // the trace work-group
    bool shade = false;
    render::WorkCounts work;  // per pixel
    std::string digest;       // of the traced image
    std::vector<render::TraceWarning> warnings;  // the last capture's

    Memory memory() const;  // construction, BVH and the combined pool
    double rays_per_second() const;
};
// run: a Work::trace run of spec.
RenderFigures render_figures(const Run& run, const RunSpec& spec, const ocl::DeviceInfo& device);
// {"trace_group", "stages", "build_ms", "bvh_ms", "trace_ms", "total_ms", "wall_ms", "wall_breakdown_ms", "captures", "bricks", "bvh", "memory",
//  "rays_per_second", "work_per_pixel", "capped_rays", "warnings", "digest", "voxel_world", "kernels"}
// (docs/measurement.md)
nlohmann::json to_json(const RenderFigures& f);
// The build/bvh/trace line, one "warning:" line per warning, the stage table (several captures) and
// the kernel table (kernel_table).
std::string to_text(const RenderFigures& f, bool kernel_table);

// The job's figures of an execution, on its home lane's device. A split's launches run on several
// devices: its kernel table and roofline are per lane (LaneFigures), and left empty here.
BuildFigures build_figures(const Execution& e);
RenderFigures render_figures(const Execution& e);

// One lane of a split job: its own launches over the captures and its share of each stage.
struct LaneFigures {
    std::vector<measure::StageStats> stages;
    measure::Spread total_ms;  // device time of its launches, per capture
    std::size_t captures = 0;
    std::vector<measure::KernelRow> kernels;
    std::optional<DeviceShare> construct, trace;  // its share of the last capture's stages
};
LaneFigures lane_figures(const Execution& e, std::size_t lane);
// {"stages", "total_ms", "captures", "kernels", "construct_share", "trace_share"}
nlohmann::json to_json(const LaneFigures& f);
std::string to_text(const LaneFigures& f, bool kernel_table);

// A report's placement section: {"placement", "home" (the device index holding the job's bricks),
// "construct" and "trace" (split: each stage's shares, StageSplit)}.
nlohmann::json placement_json(const Execution& e);
// The split's stage lines ("" for other placements).
std::string placement_text(const Execution& e);

// "12.5 KiB", "3.00 MiB", ...
std::string bytes_text(std::uint64_t bytes);

}  // namespace sdfbrick::pipeline
