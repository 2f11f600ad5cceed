// The parts of one BrickBuilder::build call (inside construct/): the plan, the levels, the adaptive
// check, the leaf evaluation and the report, each owning its own state. BuildInputs is what every
// part reads: the device and its programs, the settings and plan, the launch recorder, the
// geometry's edits and mesh pool on the device. docs/construction.md explains the stages.
#pragma once

#include <CL/cl.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <fmt/format.h>
#include <glm/glm.hpp>

#include "cl/buffer.h"
#include "cl/cl_error.h"
#include "cl/device.h"
#include "cl/program.h"
#include "construct/brick_builder.h"
#include "construct/domain.h"
#include "construct/edit_deps.h"
#include "construct/scan.h"
#include "core/errors.h"
#include "measure/kernel_attributes.h"
#include "measure/scheduler.h"
#include "scene/scene.h"
#include "sdf_types.h"

namespace sdfbrick::construct::detail {

constexpr std::size_t kGroup1d = 64;

inline std::size_t round_up(std::size_t n, std::size_t m) { return (n + m - 1) / m * m; }

// Allocation that turns "does not fit" into a one-line InputError naming the resource.
template <class T>
ocl::Buffer<T> allocate(ocl::Device& d, std::size_t count, std::string_view what) {
    try {
        return ocl::Buffer<T>(ocl::pooled, d, count);
    } catch (const ocl::ClError& e) {
        throw SettingError("leaf_size",
                           fmt::format("{} needs {} bytes ({} x {} bytes); {} allows at most {} bytes in one buffer and "
                                       "has {} bytes in all: use a larger leaf_size, fewer samples or a smaller "
                                       "format ({})",
                                       what, count * sizeof(T), count, sizeof(T), d.info().name,
                                       d.info().max_alloc_bytes, d.info().global_mem_bytes, e.what()));
    }
}

// A list entry read with the edit it names, prepared (the stages that walk lists read SdfPrepared).
constexpr std::uint64_t kEntryBytes = sizeof(cl_uint) + sizeof(SdfPrepared);

// The edits a kernel stages at once: `wanted`, or as many of per_edit bytes each as the device's
// local_bytes hold beside the used ones (the kernel's own arrays and its other __local arguments);
// 0 when not one fits.
inline std::size_t staged_chunk(std::size_t wanted, std::uint64_t local_bytes, std::uint64_t used,
                                std::size_t per_edit) {
    if (used >= local_bytes) return 0;
    return static_cast<std::size_t>(std::min<std::uint64_t>(wanted, (local_bytes - used) / per_edit));
}

constexpr std::uint32_t kNeverUntested = 0xffffffffu;

// The list length from which the count of `level` keeps a parent's children without a test
// (brick_count's untested_from; kNeverUntested: none). Only where the fold is wide and the children
// cannot be leaves (coarsest_leaf: an untested candidate could pass the check and stand where no
// surface is): the root always; with long_list 0 (automatic), on GPUs the root's children and below
// them a parent with 4,096 edits or more, whose test folds its whole list serially per child while
// culling the extra children's lists is parallel work; CPUs test them. A given long_list applies
// from the root's children down on every device. A child kept that holds no surface keeps none of
// its own at the next test, so the leaves are the same. On the H200 (docs/measurements/roof/d24)
// the root's children untested took sculpt_dense's count from 9.98-9.99 ms to 6.64-6.66 and
// edits_65536's from 7.79-7.80 to 4.58-4.59, with the same digests; on PoCL (2 cores) the cull of
// the root's extra children cost more than the test (sculpt: count and cull 513 -> 526 ms).
inline std::uint32_t untested_from(int level, bool wide, int coarsest_leaf, bool gpu, std::uint32_t long_list) {
    constexpr std::uint32_t kGpuLongList = 4096;
    if (!wide) return kNeverUntested;
    if (level == 0) return 0;
    if (level >= coarsest_leaf) return kNeverUntested;
    if (long_list > 0) return long_list;
    if (!gpu) return kNeverUntested;
    return level == 1 ? 0 : kGpuLongList;
}

// Rounds a positive double up to the next float (the margins below must not shrink).
inline float float_up(double x) {
    const auto f = static_cast<float>(x);
    return static_cast<double>(f) >= x ? f : std::nextafter(f, INFINITY);
}

// Rounds a double down to the float at or below it.
inline float float_down(double x) {
    const auto f = static_cast<float>(x);
    return static_cast<double>(f) <= x ? f : std::nextafter(f, -INFINITY);
}

// The compiled construction programs of one device (BrickBuilder keeps them).
struct BuildPrograms {
    ocl::Program prepare, count, subdivide, cull, aabb, order;
    ocl::Kernel prepare_k, count_k, count_merge_k, mask_counts_k, subdivide_k, words_k, mark_k, mark_siblings_k,
        sibling_groups_k, dependencies_k, write_k, aabb_k, split_k, rank_k, keys_k, place_k, keep_k, put_k;
    std::unique_ptr<DependencyBuilder> dependencies;  // built on first use
    struct Splice {  // brick_splice.cl, built on first use (rebuilds)
        ocl::Program program;
        ocl::Kernel counts, leaves;
    };
    std::unique_ptr<Splice> splice;
    struct Stats {  // brick_stats.cl for one brick layout
        ocl::Program program;
        ocl::Kernel level, leaf;
    };
    std::map<std::string, Stats> stats_by_layout;
    struct Lanes {  // brick_count.cl and brick_cull.cl with SDF_LANES > 1: that many children a work-item
        ocl::Program count, cull;
        ocl::Kernel count_k, siblings_k;
    };
    std::map<int, Lanes> by_lanes;
    const Lanes& lanes(ocl::Device& d, int n) {
        auto it = by_lanes.find(n);
        if (it == by_lanes.end()) {
            const std::string defines = fmt::format("-DSDF_LANES={}", n);
            ocl::Program count_p = ocl::build_program(d, "brick_count.cl", defines);
            ocl::Program cull_p = ocl::build_program(d, "brick_cull.cl", defines);
            ocl::Kernel counts = ocl::make_kernel(count_p, "brick_count");
            ocl::Kernel siblings = ocl::make_kernel(cull_p, "cull_mark_siblings");
            it = by_lanes.emplace(n, Lanes{std::move(count_p), std::move(cull_p), std::move(counts),
                                           std::move(siblings)}).first;
        }
        return it->second;
    }
    // brick_count and cull_mark_siblings for `n` children a work-item (1: count_k, mark_siblings_k).
    const ocl::Kernel& count_kernel(ocl::Device& d, int n) { return n <= 1 ? count_k : lanes(d, n).count_k; }
    const ocl::Kernel& siblings_kernel(ocl::Device& d, int n) { return n <= 1 ? mark_siblings_k : lanes(d, n).siblings_k; }
    const Stats& stats(ocl::Device& d, const BrickLayout& layout) {
        const std::string defines = layout.defines();
        auto it = stats_by_layout.find(defines);
        if (it == stats_by_layout.end()) {
            ocl::Program p = ocl::build_program(d, "brick_stats.cl", defines);
            ocl::Kernel level = ocl::make_kernel(p, "level_stats"), leaf = ocl::make_kernel(p, "leaf_stats");
            it = stats_by_layout.emplace(defines, Stats{std::move(p), std::move(level), std::move(leaf)}).first;
        }
        return it->second;
    }

    explicit BuildPrograms(ocl::Device& d)
        : prepare(ocl::build_program(d, "edit_prepare.cl")), count(ocl::build_program(d, "brick_count.cl")),
          subdivide(ocl::build_program(d, "brick_subdivide.cl")),
          cull(ocl::build_program(d, "brick_cull.cl")), aabb(ocl::build_program(d, "brick_aabb.cl")),
          order(ocl::build_program(d, "brick_order.cl")),
          prepare_k(ocl::make_kernel(prepare, "edit_prepare")), count_k(ocl::make_kernel(count, "brick_count")),
          count_merge_k(ocl::make_kernel(count, "brick_count_merge")),
          mask_counts_k(ocl::make_kernel(count, "brick_mask_counts")),
          subdivide_k(ocl::make_kernel(subdivide, "brick_subdivide")),
          words_k(ocl::make_kernel(cull, "cull_words")), mark_k(ocl::make_kernel(cull, "cull_mark")),
          mark_siblings_k(ocl::make_kernel(cull, "cull_mark_siblings")),
          sibling_groups_k(ocl::make_kernel(cull, "sibling_groups")),
          dependencies_k(ocl::make_kernel(cull, "cull_dependencies")),
          write_k(ocl::make_kernel(cull, "cull_write")), aabb_k(ocl::make_kernel(aabb, "brick_aabb")),
          split_k(ocl::make_kernel(order, "brick_split")), rank_k(ocl::make_kernel(order, "brick_rank")),
          keys_k(ocl::make_kernel(order, "brick_keys")), place_k(ocl::make_kernel(order, "brick_place")),
          keep_k(ocl::make_kernel(order, "brick_keep")), put_k(ocl::make_kernel(order, "brick_put")) {}
};

// The thresholds, saturation and margins of one geometry's build (docs/construction.md).
struct BuildPlan {
    Domain domain;
    cl_uint log2b = 2;          // log2 of the branching factor
    std::size_t per_parent = 64;  // children per parent: B^3
    double magnitude = 0.0;     // largest |coordinate| of the domain
    double voxel = 0.0;
    float band = 0.0f, clamp_c = 0.0f;
    int apron = 1;      // samples outside a brick's cell on each side
    bool hard = false;  // no edit blends: clamping the fold commutes with every combine

    // The keep threshold of a cell of `level`: its half diagonal with margins for float rounding.
    float threshold(int level) const {
        return float_up(domain.half_diagonal(level) * (1.0 + 1.0 / 1024.0) + magnitude * std::ldexp(1.0, -16));
    }
    // The cull test's radius at `level`: a child's cell plus the apron samples around it.
    float cull_radius(int level) const {
        return float_up(std::sqrt(3.0) * (0.5 * domain.cell_size(level) + (apron - 0.5) * voxel) * (1.0 + 1e-6));
    }
    // The saturation the count test of `level` folds with: C where its threshold is below C, else
    // C + threshold (the wide fold of a coarse level; docs/construction.md, "Sparse coarse levels").
    // Past the leaves (the evaluation) it is C. Never increases with the level.
    float saturation(int level) const {
        if (level >= domain.levels) return clamp_c;
        const float t = threshold(level);
        return t < clamp_c ? clamp_c : float_up(double(clamp_c) + double(t));
    }
    // A coarse cell whose bound on |F_C - clamp(W)| reaches this cannot be rejected: C minus the
    // leaf threshold, rounded down with a margin for the kernel's float sums.
    float reject_slack() const {
        const double slack = (double(clamp_c) - double(threshold(domain.levels - 1))) * (1.0 - 1.0 / 1024.0);
        return std::max(0.0f, float_down(slack));
    }

    // Adaptive leaves: bricks of levels coarsest_leaf .. levels-1 may be leaves. A level-l leaf has
    // the finest voxel and band times 2^shift(l), and folds with saturation level_clamp[l] (the
    // finest level's is C). Uniform builds: coarsest_leaf = levels - 1.
    int coarsest_leaf = 0;
    float tolerance = 0.0f;
    std::vector<float> level_clamp;
    int finest() const { return domain.levels - 1; }
    int shift(int level) const { return (finest() - level) * static_cast<int>(log2b); }
    // What a list culled with cull_radius must hold for the evaluation of a leaf of level m: C_m,
    // and where m is coarser than the finest, further out by the part of its apron (apron - 1/2 of
    // its own voxels outside its cell) that cull_radius, in finest voxels, does not count.
    float leaf_saturation(int m) const {
        const double wider = std::sqrt(3.0) * (apron - 0.5) * (std::ldexp(voxel, shift(m)) - voxel);
        return m >= finest() ? level_clamp[m] : float_up((double(level_clamp[m]) + wider) * (1.0 + 1e-6));
    }
    // The saturation that culling at `level` keeps exact: the children's count test, and the
    // evaluation of this level's bricks (and every finer level's) as leaves.
    float cull_saturation(int level) const {
        return std::max(saturation(level + 1), leaf_saturation(std::max(level, coarsest_leaf)));
    }
    // The saturation that a checked level's parents (the bricks that did not pass) are culled again
    // with: their children's count test and the children's own cull, not their own evaluation as
    // leaves, which needs the wider level_clamp[level].
    float parent_saturation(int level) const { return std::max(saturation(level + 1), cull_saturation(level + 1)); }
};

// The domain (levels as settings ask), then the thresholds and C (and the leaf levels of an adaptive
// build). Throws InputError for levels that cannot cover the geometry or exceed 2^30 leaf bricks per
// axis, SettingError for a tolerance below float precision.
BuildPlan plan_build(const Geometry& g, const Aabb& box, const BuildSettings& s);

// What every part of one build reads.
struct BuildInputs {
    // prepared: g's edits in device form when the caller keeps them (to_device(g)); null: converted here.
    BuildInputs(ocl::Device& d, BuildPrograms& programs, Scan& scan, const Geometry& g, const BuildSettings& s,
                const BuildPlan& plan, measure::Scheduler& scheduler, GeometryBuild& out,
                const std::vector<SdfEdit>* prepared = nullptr);
    ocl::Device& device;
    BuildPrograms& programs;
    Scan& scan;
    const Geometry& geometry;
    const BuildSettings& settings;
    const BuildPlan& plan;
    measure::Scheduler& scheduler;
    GeometryBuild& out;
    std::vector<SdfEdit> converted;       // g's edits in device form, unless prepared
    std::span<const SdfEdit> edits_host;  // prepared or converted
    ocl::Buffer<SdfEdit> edits;
    ocl::Buffer<SdfPrepared> prepared_edits;  // edits as the folds read them (edit_prepare.cl), for the stages that stage lists
    ocl::Buffer<float> edit_reaches;          // their sizes for the cull's limits (sdf_edit_reach)
    ocl::Buffer<float> meshes;  // the mesh pool (construct/mesh_pool.h)
    glm::vec3 origin;
    ocl::Buffer<cl_uint> empty_uints;
};

class AdaptiveLeaves;

// A rebuild's confinement of the levels (construct/build_splice.cpp): after each level's cull but the
// finest's, which of the level's bricks the levels go on with (indices, ascending); the subtrees of
// the others are the earlier build's, or empty.
struct Region {
    std::function<std::vector<std::uint32_t>(int level, const std::vector<SdfBrick>& records)> keep;
};

// Levels 0 .. levels-1 top-down: count -> scan -> subdivide -> cull, from the root's list (every
// edit) to the leaves' lists; in a split, from the range of the split level's bricks it keeps.
// Owns the current level's parents and lists, every level's records, and the scratch reused across
// levels.
class Levels {
public:
    Levels(BuildInputs& in, const Subtrees* subtrees, AdaptiveLeaves* adaptive, const Region* region = nullptr);
    // The root's list (every edit, ascending), the pseudo-parent of level 0, the dependencies.
    void start();
    // Runs the levels; stops early when a level keeps nothing. Returns whether the last level was
    // reached with bricks (then the parents are the leaves). Adaptive builds check each brick of the
    // leaf levels (AdaptiveLeaves::check_and_split).
    bool run();

    std::size_t parent_count() const { return parent_count_; }
    ocl::Buffer<SdfBrick>& parents() { return *parents_; }
    void set_parents(std::unique_ptr<ocl::Buffer<SdfBrick>> parents) { parents_ = std::move(parents); }
    // The current lists: the parents' during the loop, the leaves' after it.
    const ocl::Buffer<cl_uint>& lists() const { return *parent_lists_; }
    void set_lists(std::unique_ptr<ocl::Buffer<cl_uint>> lists) { parent_lists_ = std::move(lists); }
    std::unique_ptr<ocl::Buffer<cl_uint>> take_lists() { return std::move(parent_lists_); }
    // Scratch of at least n per-brick offsets (kept across levels).
    ocl::Buffer<cl_uint>& offsets(std::size_t n, std::string_view what);
    // The count of level + 1 over this level's bricks as they stand (every candidate of a checked
    // level), into `bricks` (a copy of parents(): the child masks are written there) and counts.
    void count_children(int level, ocl::Buffer<SdfBrick>& bricks, ocl::Buffer<cl_uint>& counts);
    // The parents set next carry their child masks already (count_children): the next level's
    // count only adds up their bits.
    void parents_counted() { parents_counted_ = true; }
    // Whether culling this level's bricks again for their children pays (recull_pays), and that
    // cull: the bricks (parents()) then point into shorter lists; returns the lists replaced. Run
    // before the check, it stands for the cull of the parents after it.
    bool recull_pays(int level) const;
    std::unique_ptr<ocl::Buffer<cl_uint>> recull(int level);
    // Every level's records (adaptive: its parents); the last is the leaf level's after run().
    const std::vector<std::unique_ptr<ocl::Buffer<SdfBrick>>>& level_bricks() const { return level_bricks_; }
    std::unique_ptr<ocl::Buffer<SdfBrick>> take_last_level() { return std::move(level_bricks_.back()); }
    const std::vector<std::uint64_t>& kept() const { return kept_; }                // every level's kept bricks
    const std::vector<std::uint64_t>& list_entries() const { return list_entries_; }  // every level's list entries
    // Every level's entries that the next level's count reads: its parents' lists (re-culled ones in
    // adaptive builds).
    const std::vector<std::uint64_t>& parent_entries() const { return parent_entries_; }

    // Bytes of the build's records, lists and largest scratch (the memory report).
    struct Bytes {
        std::uint64_t bricks = 0, lists = 0, scratch = 0;
    };
    Bytes bytes;

private:
    struct CountShape {
        std::size_t parts = 1;   // work-items per child
        std::size_t splits = 1;  // work-groups per parent
        std::size_t chunk = 0;   // edits staged at once
        int lanes = 1;           // children a work-item folds at once (CPU lanes, with one part)
    };
    CountShape count_shape(std::size_t children, std::uint64_t mean_list) const;
    // The count stage of `level` over parents (parent_count_ of them): child masks and counts.
    void count(int level, ocl::Buffer<SdfBrick>& parents, ocl::Buffer<cl_uint>& counts);
    std::uint32_t untested_from(int level) const;  // detail::untested_from for this build
    std::uint64_t count_and_scan(int level);
    // Refuses (SettingError "leaf_size") projected leaves whose host bytes (settings.host_bytes_per_leaf)
    // exceed the host memory available.
    void check_host_projection(int level, std::uint64_t children, double projected) const;
    void subdivide(int level, std::uint64_t children);
    void cull(int level, std::uint64_t children);
    // Culls the lists of this level's n bricks (parents_) at `saturation`; returns the lists replaced.
    // siblings: they are the children subdivide just wrote (offsets_ and counts_ place them).
    std::unique_ptr<ocl::Buffer<cl_uint>> cull_lists(int level, std::uint64_t n, float saturation, bool siblings);
    // cull_lists' bits (bits_, sources_) of total_words words.
    void cull_mark(int level, std::uint64_t n, float saturation, std::uint64_t total_words, bool siblings);
    // cull_mark_siblings for cull_mark (group: work-items per parent, at least its children), and its
    // work-group limit.
    void mark_siblings(int level, std::uint64_t n, float saturation, std::uint64_t total_words, std::size_t lanes,
                       std::size_t group);
    std::size_t siblings_limit() const;
    std::uint64_t keep_subtrees(std::uint64_t children);
    std::uint64_t keep_region(int level, std::uint64_t children);
    std::uint64_t resident_items(std::size_t work_group_limit) const;
    std::uint64_t bits_per_item(std::uint64_t words, cl_kernel kernel, std::string_view name) const;
    cl_uint level_log2b(int level) const { return level == 0 ? 0u : in_.plan.log2b; }
    float cell(int level) const { return static_cast<float>(in_.plan.domain.cell_size(level)); }

    BuildInputs& in_;
    const Subtrees* subtrees_;  // until applied
    AdaptiveLeaves* adaptive_;  // null for uniform builds
    const Region* region_;      // a rebuild's; null for whole builds
    std::optional<EditDependencies> deps_;
    SdfBrick pseudo_{};  // level -1: one parent whose single child (branching 1) is the root
    std::unique_ptr<ocl::Buffer<SdfBrick>> parents_;  // the current level's parents, then its bricks
    std::unique_ptr<ocl::Buffer<cl_uint>> parent_lists_;
    std::size_t parent_count_ = 1;
    bool parents_counted_ = false;
    bool reculled_ = false;  // this level's bricks were culled again before the check
    std::vector<std::unique_ptr<ocl::Buffer<SdfBrick>>> level_bricks_;
    std::vector<std::uint64_t> list_entries_;
    std::vector<std::uint64_t> parent_entries_;  // every level's, as parent_entries() says
    std::vector<std::uint64_t> kept_;
    ocl::Buffer<cl_uint> counts_, offsets_, words_, bits_;
    ocl::Buffer<cl_uint> sources_, kept_words_;  // per cull word: its first parent entry, kept count
    ocl::Buffer<cl_uint> split_words_;           // per split count work-group: its mask words and count
    ocl::Buffer<cl_uint> sibling_groups_;        // per parent: its first cull_mark_siblings work-group
};

// Adaptive builds: each brick of a leaf level (coarsest_leaf .. finest - 1) is checked against the
// tolerance; those that pass are that level's leaves, the others the next level's parents. After the
// levels, the leaves of every level are merged into one Morton-ordered list with their edit lists.
// Owns each level's leaves, check results and lists, and the merged leaves.
class AdaptiveLeaves {
public:
    explicit AdaptiveLeaves(BuildInputs& in) : in_(in) {}
    // Checks this level's bricks (levels.parents()); the passing ones become leaves, the others stay
    // as the parents. Returns the parents left.
    std::uint64_t check_and_split(int level, Levels& levels);
    // The lists of the last checked level, once a cull has replaced them (the first lists given are
    // its leaves').
    void keep_lists(int level, std::unique_ptr<ocl::Buffer<cl_uint>> lists);
    // The finest level's bricks are leaves, unchecked (nothing is finer): they stay in the levels.
    void add_finest(std::uint64_t count);
    // Merges the leaves of every level (levels.lists() becomes the merged lists). Returns the leaf count.
    std::uint64_t assemble(Levels& levels);
    // Leaves of a level (0 when none of it are leaves).
    std::uint64_t leaves_of(int level) const;
    // The check's worst error of every checked leaf, and per checked level the leaves it passed as
    // planes, unchecked (reads the check results back, for the report).
    struct CheckedLeaves {
        std::vector<double> errors;
        std::map<int, std::uint64_t> planes;
    };
    CheckedLeaves check_errors() const;
    const ocl::Buffer<SdfBrick>& merged() const { return *merged_; }
    std::unique_ptr<ocl::Buffer<SdfBrick>> take_merged() { return std::move(merged_); }
    // The merged leaves as the leaf evaluation reads them: those of checked levels have no edits,
    // since their samples are the check's (put_samples places them).
    const ocl::Buffer<SdfBrick>& evaluated() const { return *evaluated_; }
    // The checked levels' leaf samples into the pool (after the leaf evaluation, before apron copies).
    void put_samples(ocl::Buffer<std::uint8_t>& pool) const;

private:
    struct LevelLeaves {
        int level = 0;
        std::uint64_t count = 0;
        std::unique_ptr<ocl::Buffer<SdfBrick>> leaves;  // null: the finest level's, in the levels' last records
        ocl::Buffer<float> errors;    // per checked brick of the level
        ocl::Buffer<cl_uint> passed;  // per checked brick of the level
        std::unique_ptr<ocl::Buffer<cl_uint>> lists;
        std::unique_ptr<ocl::Buffer<std::uint8_t>> samples;  // the leaves' samples, as the check evaluated them
    };
    struct CheckShape {
        std::size_t group = 0;  // brick_check's work-items a brick
        std::size_t chunk = 0;  // edits staged at once
    };
    CheckShape check_shape(const ocl::Kernel& kernel, std::uint64_t n) const;
    // One level's candidates as the check reads them: their records and lists (re-culled copies
    // where that pays), the records and lists its points fold, and at the last checked level their
    // counted copies and child counts.
    struct Candidates {
        explicit Candidates(Levels& l) : levels(l) {}
        Levels& levels;
        bool last = false;         // the last checked level (the next is the finest)
        bool short_folds = false;  // the points fold the re-culled lists
        float fold_clamp = 0.0f;
        std::optional<ocl::Buffer<SdfBrick>> own_records;
        std::unique_ptr<ocl::Buffer<cl_uint>> own_lists;
        std::optional<ocl::Buffer<SdfBrick>> counted;
        std::optional<ocl::Buffer<cl_uint>> children;
        const ocl::Buffer<SdfBrick>& bricks() const { return own_records ? *own_records : levels.parents(); }
        const ocl::Buffer<cl_uint>& lists() const { return own_lists ? *own_lists : levels.lists(); }
        const ocl::Buffer<SdfBrick>& fold_bricks() const { return short_folds ? levels.parents() : bricks(); }
        const ocl::Buffer<cl_uint>& fold_lists() const { return short_folds ? levels.lists() : lists(); }
    };
    Candidates candidates(int level, Levels& levels, float window) const;
    void split(Levels& levels, LevelLeaves& out, const Candidates& c, const ocl::Buffer<std::uint8_t>& samples);
    BuildInputs& in_;
    std::vector<LevelLeaves> checked_;  // the checked levels (and the finest), coarsest first
    std::unique_ptr<ocl::Buffer<SdfBrick>> merged_, evaluated_;
    std::unique_ptr<ocl::Buffer<cl_uint>> positions_;  // each leaf's merged position, level after level
    std::vector<cl_uint> first_;                       // each checked level's first leaf in positions_
    std::uint64_t kept_bytes_ = 0;                     // the leaves' samples kept so far
};

// Whether a launch of `groups` work-groups of `group` work-items of kernel fills at most two waves of
// the device, by the occupancy model (measure/occupancy.h: known on NVIDIA, elsewhere false), with
// unset_local_bytes of __local arguments not set yet. The adaptive check's levels with few candidates
// then run the candidates' evaluation and brick_check with twice the work-items a brick: such a
// level's time is that of its longest lists, which each work-item then folds over half the points.
// On an H100 (docs/measurements/roof/d79.txt) engraved_slab's level of 1,232 candidates (1.04 waves
// of brick_check) took 0.086 -> 0.060 ms to evaluate and 0.128 -> 0.100 to check; levels of 9.9 waves
// and more were 13-27% slower with the wider groups. Changes no bit.
bool fills_few_waves(const ocl::Device& device, cl_kernel kernel, std::uint64_t unset_local_bytes, std::size_t group,
                     std::uint64_t groups);
// The same from the device's description and the kernel's attributes (local memory included).
bool fills_few_waves(const ocl::DeviceInfo& device, const measure::KernelAttributes& k, std::size_t group,
                     std::uint64_t groups);

// The samples of `count` bricks (their records and lists) into pool, as brick_evaluate stores them;
// owned: per brick, the regions it evaluates (null: all). Launched as stage at level.
void evaluate_samples(BuildInputs& in, const ocl::Buffer<SdfBrick>& bricks, const ocl::Buffer<cl_uint>& lists,
                      std::uint64_t count, const ocl::Buffer<cl_uint>* owned, ocl::Buffer<std::uint8_t>& pool,
                      measure::Stage stage, int level);

// The leaf evaluation: every leaf's samples into the brick pool, then the leaves' boxes and shifts
// (out.pool, out.aabbs, out.shifts). Owns the apron masks where leaves share apron samples.
class LeafEvaluation {
public:
    explicit LeafEvaluation(BuildInputs& in) : in_(in) {}
    // leaves: the leaf records (Morton order); lists: their edit lists. Updates bytes.scratch.
    // adaptive: where the check evaluated leaves already (their samples are put, not evaluated).
    void evaluate(const ocl::Buffer<SdfBrick>& leaves, const ocl::Buffer<cl_uint>& lists, std::uint64_t leaf_count,
                  Levels::Bytes& bytes, const AdaptiveLeaves* adaptive = nullptr);
    // Per leaf, the regions of its samples it evaluates; null when no leaf shares.
    const ocl::Buffer<cl_uint>* owned() const { return owned_.get(); }

private:
    struct ApronSharing {
        ocl::Buffer<cl_uint> neighbours;        // per leaf, 27: the leaf it copies each region from
        std::optional<ocl::Program> program;   // brick_apron.cl, when sharing is on
        std::optional<ocl::Kernel> copy;
    };
    ApronSharing share_aprons(const ocl::Buffer<SdfBrick>& leaves, std::uint64_t leaf_count, Levels::Bytes& bytes);
    BuildInputs& in_;
    std::unique_ptr<ocl::Buffer<cl_uint>> owned_;
};

// The build's report: bricks, list lengths, work and times per level, memory, and for adaptive
// builds the check's errors, from counters reduced on the device (kernels/brick_stats.cl, one read).
class BuildReport {
public:
    BuildReport(BuildInputs& in, const Levels& levels, const AdaptiveLeaves* adaptive, const LeafEvaluation& leaves)
        : in_(in), levels_(levels), adaptive_(adaptive), evaluation_(leaves) {}
    // Fills in.out's figures; leaves and lists are the final leaf records and their lists.
    void fill(const ocl::Buffer<SdfBrick>& leaves, const ocl::Buffer<cl_uint>& lists, std::uint64_t leaf_count);

private:
    struct Counters {
        std::vector<std::uint64_t> records, longest, tests;
        std::uint64_t entries = 0, longest_leaf = 0, entry_flops = 0, flops = 0, evaluations = 0;
    };
    Counters count_on_device(const ocl::Buffer<SdfBrick>& leaves, const ocl::Buffer<cl_uint>& lists,
                             std::uint64_t leaf_count);
    void report_flops(std::uint64_t leaf_count, const Counters& c);
    void add_work(measure::Stage stage, std::uint64_t evaluations, std::uint64_t bytes);
    BuildInputs& in_;
    const Levels& levels_;
    const AdaptiveLeaves* adaptive_;
    const LeafEvaluation& evaluation_;
};

}  // namespace sdfbrick::construct::detail
