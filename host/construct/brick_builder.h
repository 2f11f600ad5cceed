// Sparse brick construction on the device: per geometry, top-down levels of count -> scan ->
// subdivide -> cull, then evaluate the leaf bricks into the brick pool and their AABBs. Every launch
// goes through a measure::Scheduler; docs/construction.md explains the stages, the band-limited field
// that makes culling exact, and every margin used below.
#pragma once

#include <CL/cl.h>

#include <cstddef>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "construct/brick_layout.h"
#include "construct/scan.h"
#include "construct/work.h"
#include "measure/scheduler.h"
#include "cl/buffer.h"
#include "cl/device.h"
#include "cl/digest.h"
#include "cl/program.h"
#include "scene/scene.h"
#include "sdf_types.h"

namespace sdfbrick::construct {

namespace detail {
struct BuildPrograms;
}

struct BuildSettings {
    double leaf_size = 0.0625;    // side of a leaf brick (geometry units)
    int levels = 0;               // 0: the fewest that cover the geometry; else exactly this many
    int branching = 4;            // children per axis: 4 or 2
    int samples = 8;              // samples per axis: 8 (one-voxel apron) or 10 (two-voxel apron)
    BrickFormat format = BrickFormat::int8;
    double band_voxels = 4.0;     // stored distances are clamped to +-band_voxels voxels
    double guard = 2.0;           // C = band + guard * (largest blend radius); see sdf_build.h
    int chunk = 64;               // edits staged per __local chunk (16..256)
    int eval_group = 128;         // work-group size of the leaf evaluation
    // Registers per work-item the leaf evaluation may use, on NVIDIA's compiler only
    // (-cl-nv-maxrregcount; changes no bit): 0 = the compiler's choice.
    int eval_registers = 0;
    // Samples per SIMD value of the leaf evaluation and the check, and new children per work-item of
    // the count (where a child has one work-item) and of the sibling cull (1, 2, 4, 8 or 16; changes
    // no bit): 0 = the device's native float width on CPU devices, 1 elsewhere (GPUs run work-items
    // as SIMD lanes).
    int eval_lanes = 0;
    // Work-items per candidate child in the count stage (1, 2, 4, 8 or 16; changes no bit): several
    // compute a long list's values in turn and one folds them. 0 = automatic: on GPUs as many as fill
    // the device at levels with few parents, 1 on CPUs (whose cores hide no latency that way).
    int count_parts = 0;
    // Work-groups per parent in the count stage (a power of two up to 64, at most a parent's children;
    // changes no bit): each takes a share of the children and stages the whole list. 0 = automatic:
    // as few as hold count_parts work-items per child within the count kernel's work-group limit; on
    // CPUs, at levels with fewer parents than compute units, as many as the units (4 children each
    // at least).
    int count_splits = 0;
    // The count keeps a parent's children without a test where its list has at least this many
    // edits, at levels whose fold is wide and whose bricks cannot be leaves (the leaves stay the
    // same bits; the levels above them hold more bricks). 0 = automatic: on GPUs every child of the
    // root and, below, lists of 4,096 edits or more (a long list's test is a serial fold per child);
    // on CPUs none below the root.
    int count_untested = 0;
    bool cull = true;
    // The cull stage tests a level's new bricks one work-group per parent, its list staged once for
    // all its children, where the level has at least this many parents per compute unit (and 8
    // children or more per parent on average; on GPUs, lists of 256 edits or more); elsewhere it
    // spreads each brick's list over the device (the top levels: few parents, long lists, which one
    // work-group each would walk serially). 0 = never. Changes no bit.
    int cull_siblings = 2;
    // In the leaf evaluation with one lane (GPUs), sphere and capsule edits (adds and subtracts) skip
    // the samples where they cannot change the fold, found from the running value before the square
    // root (kernels/sdf_build.h: sdf_fold_radial). Changes no bit.
    bool skip_far = true;
    // A leaf with at least this many edits copies the apron samples that lie in a neighbour leaf's
    // interior from it instead of evaluating them again (kernels/sdf_apron.h; changes no bit). 0: no
    // leaf shares. Off by default: on an H200 no scene measured builds faster with it since the
    // evaluation skips far edits (docs/performance.md).
    int apron_share_edits = 0;
    bool dependencies = false;    // add the dependencies of kept smooth edits to every list
    // Adaptive leaves (docs/construction.md, "Adaptive leaves"): with tolerance > 0, leaf_size is the
    // finest brick, and a brick of a coarser level whose samples reproduce the field within
    // tolerance (geometry units) at every check point is a leaf; 0 = uniform (every leaf leaf_size).
    double tolerance = 0.0;
    double max_leaf_size = 0.0;   // adaptive: the largest leaf brick (0: the largest whose rounding fits the tolerance)
    // Host bytes the caller will hold per leaf brick once the build is done (an export's copy and
    // grids); 0: none. With it, a build whose projected leaves would not fit in the host memory
    // available (ocl::host_memory_available) is refused at the level that shows it, before the leaves.
    double host_bytes_per_leaf = 0.0;

    bool adaptive() const { return tolerance > 0.0; }
    BrickLayout layout() const { return {samples, format}; }
    int lanes(const ocl::DeviceInfo& device) const;
    double voxel() const { return leaf_size / layout().interior(); }
    // Whether the leaf evaluation keeps skip records beside the staged edits: with CPU lanes, where
    // they made drops' evaluation 13% shorter on PoCL; not with one lane, where an H100's evaluation
    // of drops took 3.47 ms with them against 3.00 without (kernels/brick_evaluate.cl).
    static bool skip_records(int lanes) { return lanes > 1; }
    // The leaf evaluation's __local memory for a chunk, at most: the staged edits, their skip records
    // (two float4 each; kept with CPU lanes only) and 64 uints of bookkeeping. Validation and the tuner
    // count the records on every device: even chunk 256 fits a GPU's 48 KiB with them.
    static std::uint64_t evaluation_local_bytes(int chunk) {
        return static_cast<std::uint64_t>(chunk) * (sizeof(SdfPrepared) + 2 * sizeof(cl_float4)) + 64 * sizeof(cl_uint);
    }
    // Throws SettingError naming the setting ("chunk") for a value out of range.
    void validate(const ocl::DeviceInfo& device) const;
};

// The finest brick an adaptive build needs for a tolerance when no size is given: voxels of at most
// 2 x tolerance (so that a feature 4 tolerances thick spans two samples), rounded down to a power
// of two of the leaf side.
double auto_leaf_size(double tolerance, const BrickLayout& layout);

struct LevelReport {
    int level = 0;
    double cell_size = 0.0;
    std::uint64_t bricks = 0;
    std::uint64_t edit_entries = 0;  // sum of the bricks' list lengths
    std::uint32_t max_edits = 0;
    double count_ms = 0.0, scan_ms = 0.0, subdivide_ms = 0.0, cull_ms = 0.0;
    std::uint64_t leaves = 0;  // bricks of this level that are leaves (adaptive builds: checked ones)
    std::uint64_t plane_leaves = 0;  // adaptive builds: of those, the ones passed as planes, unchecked
    // The host reference's surface cells of this level (reference/surface_cells.h), when asked for.
    std::optional<std::uint64_t> reference_cells;
};

// What one geometry's construction is, without its arrays: plain data, copied as a whole where a
// build moves between host and devices (a split's parts, their merge).
struct GeometryBuildInfo {
    std::string name;
    // Domain: a cube of side leaf * B^(levels-1) from origin (floats as the kernels use them).
    glm::vec3 origin{0.0f};
    float leaf_size = 0.0f;
    int levels = 0;
    int branching = 4;
    float clamp_c = 0.0f;      // saturation C of the band-limited field
    float band = 0.0f;         // stored range: +-band
    std::vector<LevelReport> level_reports;
    std::uint64_t leaf_count = 0;
    double edits_per_leaf_mean = 0.0;
    std::uint32_t edits_per_leaf_max = 0;
    std::uint64_t edit_evaluations = 0;  // count + cull + evaluate
    // FLOPs and bytes of count, cull and evaluate (construct/work.h). Evaluate's FLOPs are exact
    // (every leaf list entry's edit_flops); count and cull use the mean of the leaf entries.
    std::map<measure::Stage, StageWork> work;
    std::uint64_t dependency_entries = 0;
    std::map<std::string, std::uint64_t> memory;  // bytes per resource
    // This build's launches in the recorder it was given: [first_launch, end_launch).
    std::size_t first_launch = 0, end_launch = 0;
    double device_ms = 0.0;  // all launches
    double host_ms = 0.0;    // wall time of build(), including read-backs
    std::uint64_t leaves_built = 0;  // leaves evaluated: leaf_count, or a rebuild's leaves built again

    // Adaptive builds: the check's worst error over the leaves (geometry units), and its 99th
    // percentile over the leaves (each leaf's worst check point); 0 for uniform builds (unchecked).
    double tolerance = 0.0;  // 0: uniform
    double check_error_max = 0.0, check_error_p99 = 0.0;
    int coarsest_leaf_level = 0;  // levels - 1 for uniform builds
};

// One geometry's construction: the leaves and pool stay on the device.
struct GeometryBuild : GeometryBuildInfo {
    const GeometryBuildInfo& info() const { return *this; }
    GeometryBuildInfo& info() { return *this; }

    std::unique_ptr<ocl::Buffer<SdfBrick>> leaves;  // Morton order; a leaf's level gives its size
    std::unique_ptr<ocl::Buffer<cl_uint>> shifts;   // per leaf: (levels - 1 - level) * log2(B), 0 when uniform
    std::unique_ptr<ocl::Buffer<cl_uint>> leaf_edit_indices;
    std::unique_ptr<ocl::Buffer<std::uint8_t>> pool;  // leaf_count * samples^3 values of the format
    std::unique_ptr<ocl::Buffer<SdfBounds>> aabbs;
};

// A share of a split build: the descendants of a contiguous range of one level's bricks. The split
// level is the first with at least min_bricks bricks (or the leaf level); pick(its records) gives the
// range [first, end) to keep, and the build goes on from those bricks alone. Bricks stay in order
// inside each parent, so the leaves of consecutive ranges, concatenated in order, are the whole
// build's leaves (docs/multi-device.md).
struct Subtrees {
    std::uint64_t min_bricks = 1;
    std::function<std::pair<std::uint64_t, std::uint64_t>(const std::vector<SdfBrick>&)> pick;

    // Whether a level of `bricks` bricks is the split level: min_bricks or more, or the coarsest leaf
    // level (the finest for uniform builds). Adaptive builds split there at the latest, so that no
    // leaf lies above the split and every leaf belongs to exactly one part.
    bool splits_at(int level, std::uint64_t bricks, int coarsest_leaf) const {
        return bricks >= min_bricks || level >= coarsest_leaf;
    }
};

// What changed in a geometry since an earlier build of it (an edit log's operations): the edits that
// left or changed, as they were (before), the edits that came or changed, as they are (after), and
// the old indices of the edits that left (ascending). Every other edit kept its value and its order
// among the others.
struct EditChange {
    std::vector<Edit> before, after;
    std::vector<std::uint32_t> removed;
};

class BrickBuilder {
public:
    explicit BrickBuilder(ocl::Device& device);
    ~BrickBuilder();
    ocl::Device& device() { return device_; }

    // Builds one geometry (already at the scene's time). An empty geometry (no add edit) gives an
    // empty, valid result. Throws InputError for settings or sizes the device cannot hold.
    // Every launch is recorded in scheduler (the run's launch recorder); build() waits for its own.
    // With subtrees, only the descendants of the range it picks are built. prepared: g's edits in
    // device form (to_device(g)) when the caller keeps them from build to build; null: converted here.
    GeometryBuild build(const Geometry& g, const BuildSettings& settings, measure::Scheduler& scheduler,
                        const Subtrees* subtrees = nullptr, const std::vector<SdfEdit>* prepared = nullptr);

    // The build of g after change, from `before` (this builder's build of the geometry before the
    // change, with the same settings) and `records` (before's leaf records, read back): only the
    // subtrees the changed edits can reach are built again, the other leaves are copied, and the
    // result equals build(g, settings) bit for bit (leaves, pool, lists; docs/frames.md). records
    // becomes the result's. Returns nothing when the change cannot be confined and the caller must
    // build in full: adaptive, dependency, unculled or apron-sharing builds; an intersect or mesh
    // edit among the changed ones; a domain, band or saturation that the change moved. The result's
    // report figures (levels, work, memory) are before's; leaf_count, device_ms, host_ms and
    // leaves_built (the leaves built again) are its own.
    std::optional<GeometryBuild> rebuild(const Geometry& g, const BuildSettings& settings, const GeometryBuild& before,
                                         std::vector<SdfBrick>& records, const EditChange& change,
                                         measure::Scheduler& scheduler, const std::vector<SdfEdit>* prepared = nullptr);

private:
    ocl::Device& device_;
    Scan scan_;
    std::unique_ptr<detail::BuildPrograms> programs_;  // construct/build_parts.h
};

// Digest of a build's output: domain, layout, and the tree digests (core/hash.h) of the leaf
// coordinates (and levels, when adaptive) and of every pool byte. Equal iff the bricks and pools are
// bit-identical. Edit lists are not part of it (culling changes them by design); list_digest covers
// them (the tree digest of each leaf's FNV-1a 64 of its coordinate and list). These two read the
// buffers back and hash them on the host (the tests' twin); build_digests computes the same values
// on the device (8 bytes cross), for every build with one wait: {output, list} per build.
std::string output_digest(const GeometryBuild& b, const BuildSettings& s);
std::string list_digest(const GeometryBuild& b);
std::vector<std::pair<std::string, std::string>> build_digests(std::span<const GeometryBuild> builds,
                                                               const BuildSettings& s, ocl::DeviceDigest& digest);

}  // namespace sdfbrick::construct
