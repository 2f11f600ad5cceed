#include "construct/brick_builder.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <bit>
#include <cstddef>
#include <numeric>
#include <stdexcept>

#include <fmt/format.h>

#include "construct/edit_deps.h"
#include "construct/mesh_pool.h"
#include "cl/cl_error.h"
#include "cl/launch.h"
#include "core/errors.h"
#include "core/hash.h"
#include "construct/domain.h"
#include "scene/to_device.h"

namespace sdfbrick::construct {

void BuildSettings::validate(const ocl::DeviceInfo& device) const {
    if (!(leaf_size > 0.0) || !std::isfinite(leaf_size))
        throw SettingError("leaf_size", fmt::format("leaf_size must be a positive number, got {}", leaf_size));
    if (branching != 2 && branching != 4)
        throw SettingError("branching", fmt::format("branching must be 2 or 4, got {}", branching));
    if (samples != 8 && samples != 10) throw SettingError("samples", fmt::format("samples must be 8 or 10, got {}", samples));
    if (levels < 0 || levels > 31)
        throw SettingError("levels", fmt::format("levels must lie in 1..31 (0 = automatic), got {}", levels));
    if (chunk < 16 || chunk > 256) throw SettingError("chunk", fmt::format("chunk must lie in 16..256, got {}", chunk));
    if (count_parts < 0 || count_parts > 16 || (count_parts & (count_parts - 1)) != 0)
        throw SettingError("count_parts", fmt::format("count_parts must be 1, 2, 4, 8 or 16 (0 = automatic), got {}",
                                                      count_parts));
    if (apron_share_edits < 0)
        throw SettingError("apron_share_edits", fmt::format("apron_share_edits must be 0 or more, got {}", apron_share_edits));
    if (eval_group < 1 || eval_group > 1024 || (eval_group & (eval_group - 1)) != 0)
        throw SettingError("eval_group", fmt::format("eval_group must be a power of two in 1..1024, got {}", eval_group));
    if (static_cast<std::size_t>(eval_group) > device.max_work_group_size)
        throw SettingError("eval_group", fmt::format("eval_group {} is larger than the {} work-items per work-group {} "
                                                     "allows", eval_group, device.max_work_group_size, device.name));
    if (eval_lanes < 0 || eval_lanes > 16 || (eval_lanes & (eval_lanes - 1)) != 0)
        throw SettingError("eval_lanes", fmt::format("eval_lanes must be 1, 2, 4, 8 or 16 (0 = the device's), got {}",
                                                     eval_lanes));
    if (!(band_voxels > 0.0) || band_voxels > 64.0)
        throw SettingError("band_voxels", fmt::format("band_voxels must lie in (0, 64], got {}", band_voxels));
    if (!(guard >= 0.0) || guard > 64.0) throw SettingError("guard", fmt::format("guard must lie in [0, 64], got {}", guard));
    if (!(tolerance >= 0.0) || !std::isfinite(tolerance))
        throw SettingError("tolerance", fmt::format("tolerance must be a positive number, got {}", tolerance));
    if (!(max_leaf_size >= 0.0) || !std::isfinite(max_leaf_size))
        throw SettingError("max_leaf_size", fmt::format("max_leaf_size must be a positive number, got {}", max_leaf_size));
    const std::uint64_t local = static_cast<std::uint64_t>(chunk) * sizeof(SdfEdit) + 64 * sizeof(cl_uint);
    if (local > device.local_mem_bytes)
        throw SettingError("chunk", fmt::format("chunk {} needs {} bytes of local memory; {} has {}", chunk, local,
                                                device.name, device.local_mem_bytes));
}

int BuildSettings::lanes(const ocl::DeviceInfo& device) const {
    if (eval_lanes != 0) return eval_lanes;
    const std::uint32_t w = device.native_float_width;
    return device.type == "cpu" && w >= 2 && w <= 16 && (w & (w - 1)) == 0 ? static_cast<int>(w) : 1;
}

double auto_leaf_size(double tolerance, const BrickLayout& layout) {
    if (!(tolerance > 0.0) || !std::isfinite(tolerance))
        throw SettingError("tolerance", fmt::format("tolerance must be a positive number, got {}", tolerance));
    return std::exp2(std::floor(std::log2(2.0 * tolerance * layout.interior())));
}

struct BrickBuilder::Programs {
    ocl::Program count, subdivide, cull, aabb, order;
    ocl::Kernel count_k, subdivide_k, mark_k, cull_count_k, write_k, aabb_k, split_k, rank_k, place_k;
    std::unique_ptr<DependencyBuilder> dependencies;  // built on first use
    struct Stats {  // brick_stats.cl for one brick layout
        ocl::Program program;
        ocl::Kernel level, leaf;
    };
    std::map<std::string, Stats> stats_by_layout;
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

    explicit Programs(ocl::Device& d)
        : count(ocl::build_program(d, "brick_count.cl")), subdivide(ocl::build_program(d, "brick_subdivide.cl")),
          cull(ocl::build_program(d, "brick_cull.cl")), aabb(ocl::build_program(d, "brick_aabb.cl")),
          order(ocl::build_program(d, "brick_order.cl")),
          count_k(ocl::make_kernel(count, "brick_count")), subdivide_k(ocl::make_kernel(subdivide, "brick_subdivide")),
          mark_k(ocl::make_kernel(cull, "cull_mark")),
          cull_count_k(ocl::make_kernel(cull, "cull_count")),
          write_k(ocl::make_kernel(cull, "cull_write")), aabb_k(ocl::make_kernel(aabb, "brick_aabb")),
          split_k(ocl::make_kernel(order, "brick_split")), rank_k(ocl::make_kernel(order, "brick_rank")),
          place_k(ocl::make_kernel(order, "brick_place")) {}
};

BrickBuilder::BrickBuilder(ocl::Device& device)
    : device_(device), scan_(device), programs_(std::make_unique<Programs>(device)) {}

BrickBuilder::~BrickBuilder() = default;

namespace {

constexpr std::size_t kGroup1d = 64;

std::size_t round_up(std::size_t n, std::size_t m) { return (n + m - 1) / m * m; }

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

double largest_blend(const Geometry& g) {
    double k = 0.0;
    for (const Edit& e : g.edits) k = std::max(k, e.blend);
    return k;
}

// A list entry read with the edit it names.
constexpr std::uint64_t kEntryBytes = sizeof(cl_uint) + sizeof(SdfEdit);

// Rounds a positive double up to the next float (the margins below must not shrink).
float float_up(double x) {
    const auto f = static_cast<float>(x);
    return static_cast<double>(f) >= x ? f : std::nextafter(f, INFINITY);
}

// Rounds a double down to the float at or below it.
float float_down(double x) {
    const auto f = static_cast<float>(x);
    return static_cast<double>(f) <= x ? f : std::nextafter(f, -INFINITY);
}

}  // namespace

// The thresholds, saturation and margins of one geometry's build (docs/construction.md).
struct BuildPlan {
    Domain domain;
    cl_uint log2b = 2;          // log2 of the branching factor
    std::size_t per_parent = 64;  // children per parent: B^3
    double magnitude = 0.0;     // largest |coordinate| of the domain
    double voxel = 0.0;
    float band = 0.0f, clamp_c = 0.0f;

    // The keep threshold of a cell of `level`: its half diagonal with margins for float rounding.
    float threshold(int level) const {
        return float_up(domain.half_diagonal(level) * (1.0 + 1.0 / 1024.0) + magnitude * std::ldexp(1.0, -16));
    }
    // The cull test's radius at `level`: a child's cell plus the apron samples around it.
    float cull_radius(int level, int apron) const {
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
    // The saturation that culling at `level` keeps exact: the children's count test, and the
    // evaluation of this level's bricks (and every finer level's) as leaves.
    float cull_saturation(int level) const {
        return std::max(saturation(level + 1), level_clamp[std::max(level, coarsest_leaf)]);
    }
};

namespace {

// The coarsest leaf level and each leaf level's C; refuses a tolerance below float precision at the
// domain's coordinates and a finest level too fine for the 63-bit Morton keys of the merge.
void plan_adaptive(BuildPlan& p, const Aabb& box, const BuildSettings& s, double blend) {
    const double precision = p.magnitude * std::ldexp(1.0, -20);
    if (s.tolerance < precision)
        throw SettingError("tolerance", fmt::format("tolerance {} is finer than float precision allows at coordinates "
                                                    "up to {} (about {:.3g}): use a larger tolerance",
                                                    s.tolerance, p.magnitude, precision));
    if (p.domain.cells_per_axis(p.finest()) > (std::int64_t{1} << 21))
        throw SettingError("leaf_size", fmt::format("an adaptive build allows at most 2^21 finest bricks per axis; "
                                                    "leaf_size {} needs {}", s.leaf_size,
                                                    p.domain.cells_per_axis(p.finest())));
    const glm::dvec3 extent = box.hi - box.lo;
    const double largest = s.max_leaf_size > 0.0 ? s.max_leaf_size : 0.25 * std::max({extent.x, extent.y, extent.z});
    p.coarsest_leaf = p.finest();
    while (p.coarsest_leaf > 1 && p.domain.cell_size(p.coarsest_leaf - 1) <= largest) --p.coarsest_leaf;
    p.tolerance = static_cast<float>(s.tolerance);
    for (int l = p.coarsest_leaf; l < p.finest(); ++l) {
        const double band = std::ldexp(double(p.band), p.shift(l));
        p.level_clamp[static_cast<std::size_t>(l)] =
            float_up(std::max<double>(band, p.threshold(l)) * (1.0 + 1.0 / 256.0) + blend);
    }
}

// The domain (levels as settings ask), then the thresholds and C. Throws InputError for levels that
// cannot cover the geometry or exceed 2^30 leaf bricks per axis.
BuildPlan plan_build(const Geometry& g, const Aabb& box, const BuildSettings& s) {
    BuildPlan p;
    p.domain = make_domain(box, s.leaf_size, s.branching);
    if (s.levels > 0) {
        if (s.levels < p.domain.levels)
            throw SettingError("levels", fmt::format("levels {} cannot cover geometry \"{}\" at leaf_size {}: it needs "
                                                     "at least {}", s.levels, g.name, s.leaf_size, p.domain.levels));
        const int bits_per_level = s.branching == 4 ? 2 : 1;
        if ((s.levels - 1) * bits_per_level > 30)
            throw SettingError("levels", fmt::format("levels {} with branching {} exceeds 2^30 leaf bricks per axis",
                                                     s.levels, s.branching));
        p.domain.levels = s.levels;
    }
    p.log2b = s.branching == 4 ? 2 : 1;
    p.per_parent = std::size_t{1} << (3 * p.log2b);
    const glm::dvec3 lo = p.domain.origin, hi = p.domain.origin + p.domain.side();
    p.magnitude = std::max({glm::abs(lo).x, glm::abs(lo).y, glm::abs(lo).z, std::abs(hi.x), std::abs(hi.y), std::abs(hi.z)});
    p.voxel = s.voxel();
    p.band = static_cast<float>(s.band_voxels * p.voxel);
    const double blend = s.guard * largest_blend(g);
    p.clamp_c = float_up(std::max<double>(p.band, p.threshold(p.domain.levels - 1)) * (1.0 + 1.0 / 256.0) + blend);
    p.coarsest_leaf = p.finest();
    p.level_clamp.assign(static_cast<std::size_t>(p.domain.levels), p.clamp_c);
    if (s.adaptive()) plan_adaptive(p, box, s, blend);
    return p;
}

}  // namespace

// One build() call: the geometry's edits and lists on the device, the current level's parents, the
// scratch buffers reused across levels, and the steps of the build.
class BrickBuilder::Job {
public:
    Job(BrickBuilder& b, const Geometry& g, const BuildSettings& s, const BuildPlan& plan, measure::Scheduler& scheduler,
        GeometryBuild& out, const Subtrees* subtrees)
        : b_(b), d_(b.device_), g_(g), s_(s), plan_(plan), scheduler_(scheduler), out_(out), subtrees_(subtrees),
          edits_host_(to_device(g)),
          edits_(d_, edits_host_, CL_MEM_READ_ONLY),
          meshes_(d_, std::span<const float>(mesh_pool(std::span<const Geometry>(&g, 1), d_, scheduler)), CL_MEM_READ_ONLY),
          origin_(plan.domain.origin) {}

    // The root's list (every edit, ascending), the pseudo-parent of level 0, the dependencies.
    void start() {
        std::vector<cl_uint> all(edits_host_.size());
        std::iota(all.begin(), all.end(), 0u);
        pseudo_.level = 0xffffffffu;
        pseudo_.edit_offset = 0;
        pseudo_.edit_count = static_cast<sdf_u32>(all.size());
        parents_ = std::make_unique<ocl::Buffer<SdfBrick>>(d_, std::span<const SdfBrick>(&pseudo_, 1));
        parent_lists_ = std::make_unique<ocl::Buffer<cl_uint>>(d_, std::span<const cl_uint>(all));
        list_bytes_ = parent_lists_->bytes();
        if (s_.cull && s_.dependencies) {
            if (!b_.programs_->dependencies)
                b_.programs_->dependencies = std::make_unique<DependencyBuilder>(d_, b_.scan_);
            deps_ = b_.programs_->dependencies->compute(edits_, edits_host_.size(), scheduler_);
            out_.dependency_entries = deps_->total;
            out_.memory["dependency lists"] = deps_->bytes();
        }
    }

    // Levels 0 .. levels-1 top-down; stops early when a level keeps nothing. Returns whether the last
    // level was reached with bricks (then the parents are the leaves).
    // Adaptive builds check each brick of the leaf levels: those that pass are leaves, the others the
    // next level's parents; the leaves of every level are then merged (assemble_leaves).
    bool run_levels() {
        for (int level = 0; level < plan_.domain.levels; ++level) {
            std::uint64_t children = count_and_scan(level);
            subdivide(level, children);
            cull(level, children);
            // Adaptive builds split at the coarsest leaf level at the latest: no leaf lies above the
            // split level, so every leaf belongs to exactly one part, in Morton order within it.
            if (subtrees_ && (children >= subtrees_->min_bricks || level + 1 == plan_.domain.levels ||
                              (s_.adaptive() && level >= plan_.coarsest_leaf))) {
                children = keep_subtrees(children);
                subtrees_ = nullptr;
            }
            scratch_bytes_ = std::max<std::uint64_t>(scratch_bytes_, counts_.bytes() + offsets_.bytes() + words_.bytes() +
                                                                         bits_.bytes() + sources_.bytes() +
                                                                         kept_words_.bytes());
            kept_.push_back(children);
            parent_count_ = children;
            if (s_.adaptive() && level >= plan_.coarsest_leaf && level < plan_.finest() && children > 0)
                parent_count_ = check_and_split(level);
            if (parent_count_ == 0) break;
        }
        const bool complete =
            level_bricks_.size() + 1 == static_cast<std::size_t>(plan_.domain.levels) && parent_count_ > 0;
        level_bricks_.push_back(std::move(parents_));
        if (s_.adaptive() && complete)  // the finest level's bricks are leaves, unchecked: nothing is finer
            level_leaves_.push_back({plan_.finest(), parent_count_, nullptr, ocl::Buffer<float>(d_, 0),
                                     ocl::Buffer<cl_uint>(d_, 0), nullptr});
        return complete;
    }

    // Adaptive builds: the leaves of every level in one Morton-ordered list, with their edit lists
    // in one buffer. Returns the leaf count.
    std::uint64_t assemble_leaves();
    void evaluate_leaves(std::uint64_t leaf_count);
    struct ApronSharing {
        ocl::Buffer<cl_uint> neighbours;        // per leaf, 27: the leaf it copies each region from
        std::optional<ocl::Program> program;   // brick_apron.cl, when sharing is on
        std::optional<ocl::Kernel> copy;
    };
    ApronSharing share_aprons(std::uint64_t leaf_count, int share_edits);
    // The report's counters (count_on_device): per level its records, longest list and cull tests of
    // its children; over the leaves their list entries, longest list, FLOPs and evaluations.
    struct Counters {
        std::vector<std::uint64_t> records, longest, tests;
        std::uint64_t entries = 0, longest_leaf = 0, entry_flops = 0, flops = 0, evaluations = 0;
    };
    Counters count_on_device(std::uint64_t leaf_count);
    void report(std::uint64_t leaf_count);
    void report_flops(std::uint64_t leaf_count, const Counters& c);
    void add_work(measure::Stage stage, std::uint64_t evaluations, std::uint64_t bytes);

    std::size_t parent_count() const { return parent_count_; }
    std::unique_ptr<ocl::Buffer<SdfBrick>> take_leaves() {
        return merged_leaves_ ? std::move(merged_leaves_) : std::move(level_bricks_.back());
    }
    std::unique_ptr<ocl::Buffer<cl_uint>> take_lists() { return std::move(parent_lists_); }

private:
    std::uint64_t count_and_scan(int level);
    void subdivide(int level, std::uint64_t children);
    void cull(int level, std::uint64_t children);
    void cull_lists(int level, std::uint64_t children);
    std::uint64_t check_and_split(int level);
    void check_errors(std::vector<double>& leaf_errors) const;
    const ocl::Buffer<SdfBrick>& leaves() const { return merged_leaves_ ? *merged_leaves_ : *level_bricks_.back(); }
    std::uint64_t keep_subtrees(std::uint64_t children);
    cl_uint level_log2b(int level) const { return level == 0 ? 0u : plan_.log2b; }
    float cell(int level) const { return static_cast<float>(plan_.domain.cell_size(level)); }
    std::size_t chunk_bytes() const { return static_cast<std::size_t>(s_.chunk) * sizeof(SdfEdit); }
    struct CountShape {
        std::size_t parts = 1;  // work-items per child
        std::size_t chunk = 0;  // edits staged at once
    };
    CountShape count_shape(std::size_t children, std::uint64_t mean_list) const;
    std::uint64_t resident_items(std::size_t work_group_limit) const;
    std::uint64_t bits_per_item(std::uint64_t words, cl_kernel kernel, std::string_view name) const;
    BrickBuilder& b_;
    ocl::Device& d_;
    const Geometry& g_;
    const BuildSettings& s_;
    const BuildPlan& plan_;
    measure::Scheduler& scheduler_;
    GeometryBuild& out_;
    const Subtrees* subtrees_;  // until applied
    std::vector<SdfEdit> edits_host_;
    ocl::Buffer<SdfEdit> edits_;
    ocl::Buffer<float> meshes_;  // the mesh pool (construct/mesh_pool.h)
    glm::vec3 origin_;
    std::optional<EditDependencies> deps_;
    ocl::Buffer<cl_uint> empty_uints_{d_, 0};
    SdfBrick pseudo_{};  // level -1: one parent whose single child (branching 1) is the root
    std::unique_ptr<ocl::Buffer<SdfBrick>> parents_;  // the current level's parents, then its bricks
    std::unique_ptr<ocl::Buffer<cl_uint>> parent_lists_;
    // Where leaves share aprons, per leaf: the sample regions it evaluates (kernels/sdf_apron.h).
    std::unique_ptr<ocl::Buffer<cl_uint>> owned_;
    std::size_t parent_count_ = 1;
    std::vector<std::unique_ptr<ocl::Buffer<SdfBrick>>> level_bricks_;  // every level's records
    std::vector<std::uint64_t> list_entries_;                            // every level's list entries
    ocl::Buffer<cl_uint> counts_{d_, 0}, offsets_{d_, 0}, words_{d_, 0}, bits_{d_, 0};
    ocl::Buffer<cl_uint> sources_{d_, 0}, kept_words_{d_, 0};  // per cull word: its first parent entry, kept count
    std::uint64_t brick_bytes_ = 0, list_bytes_ = 0, scratch_bytes_ = 0;
    std::vector<std::uint64_t> kept_;  // every level's kept bricks (adaptive: leaves and parents)
    // Adaptive builds: each checked level's leaves, their check results and (once the next level's
    // cull has replaced them as the parents' lists) the level's edit lists.
    struct LevelLeaves {
        int level = 0;
        std::uint64_t count = 0;
        std::unique_ptr<ocl::Buffer<SdfBrick>> leaves;  // null: the finest level's, in level_bricks_.back()
        ocl::Buffer<float> errors;    // per checked brick of the level
        ocl::Buffer<cl_uint> passed;  // per checked brick of the level
        std::unique_ptr<ocl::Buffer<cl_uint>> lists;
    };
    std::vector<LevelLeaves> level_leaves_;
    std::unique_ptr<ocl::Buffer<SdfBrick>> merged_leaves_;
};

// The count stage's work-group: BuildSettings::count_parts work-items per child. Automatic: on GPUs
// as many as keep the level within resident_items (the top levels: long lists folded by few
// work-groups, bound by latency), where the values fit in __local memory. Edits are staged in chunks of the parents' mean list, rounded up to 16, up to 256 (fewer
// barriers) as local memory allows (a larger chunk than lists need costs occupancy). Neither
// changes a bit: the fold is in list order either way.
BrickBuilder::Job::CountShape BrickBuilder::Job::count_shape(std::size_t children, std::uint64_t mean_list) const {
    // A staged edit: its prepared form (no larger than SdfEdit), its excess terms and fold parameters.
    constexpr std::size_t kStaged = sizeof(SdfEdit) + 2 * sizeof(cl_float4), kMinChunk = 16, kMaxParts = 16;
    const std::size_t local = d_.info().local_mem_bytes - children * sizeof(cl_uint);
    const std::size_t limit = ocl::kernel_work_group_limit(d_, b_.programs_->count_k.get(), "brick_count");
    const std::uint64_t resident = resident_items(limit);
    const auto fits = [&](std::size_t parts) {
        return children * parts <= limit && (parts == 1 || kMinChunk * (kStaged + children * sizeof(float)) <= local);
    };
    CountShape shape;
    if (s_.count_parts > 0) {
        shape.parts = static_cast<std::size_t>(s_.count_parts);
        if (!fits(shape.parts))
            throw SettingError("count_parts", fmt::format("count_parts {} does not fit brick_count's work-group on {} "
                                                          "({} work-items, {} bytes of local memory)",
                                                          s_.count_parts, d_.info().name, limit, local));
    } else if (d_.info().type == "gpu") {
        while (shape.parts * 2 <= kMaxParts && fits(shape.parts * 2) &&
               parent_count_ * children * shape.parts * 2 <= resident)
            shape.parts *= 2;
    }
    const std::size_t per_edit = kStaged + (shape.parts > 1 ? children * sizeof(float) : 0);
    const std::size_t wanted =
        round_up(static_cast<std::size_t>(std::clamp<std::uint64_t>(mean_list, 1, 256)), kMinChunk);
    shape.chunk = std::min({wanted, std::size_t{256}, local / per_edit});
    return shape;
}

std::uint64_t BrickBuilder::Job::count_and_scan(int level) {
    const cl_uint lb = level_log2b(level);
    const std::size_t per_parent = std::size_t{1} << (3 * lb);
    const std::uint64_t entries = list_entries_.empty() ? edits_host_.size() : list_entries_.back();
    const CountShape shape =
        count_shape(per_parent, (entries + parent_count_ - 1) / std::max<std::size_t>(parent_count_, 1));
    if (counts_.size() < parent_count_) counts_ = allocate<cl_uint>(d_, parent_count_, "the child counts");
    if (offsets_.size() < parent_count_) offsets_ = allocate<cl_uint>(d_, parent_count_, "the child offsets");
    const std::size_t values = shape.parts > 1 ? shape.chunk * per_parent : 1;
    ocl::set_args(b_.programs_->count_k.get(), edits_, meshes_, *parent_lists_, *parents_, lb, origin_.x, origin_.y, origin_.z,
                  cell(level), plan_.threshold(level), plan_.clamp_c, plan_.saturation(level), plan_.reject_slack(),
                  static_cast<float>(plan_.magnitude), counts_, ocl::LocalMemory{shape.chunk * sizeof(SdfEdit)},
                  ocl::LocalMemory{shape.chunk * sizeof(cl_float4)}, ocl::LocalMemory{shape.chunk * sizeof(cl_float4)},
                  static_cast<cl_uint>(shape.chunk),
                  ocl::LocalMemory{values * sizeof(float)}, ocl::LocalMemory{per_parent * sizeof(cl_uint)});
    scheduler_.launch(measure::Stage::count, level, b_.programs_->count_k.get(), parent_count_ * per_parent * shape.parts,
                      per_parent * shape.parts);
    const std::uint64_t children =
        b_.scan_.exclusive(counts_, offsets_, parent_count_, scheduler_, measure::Stage::scan, level);
    // Refuse early (not after minutes of work) a build whose pool cannot fit: a surface's brick count
    // grows about B^2 per level, so project the leaves from this level's count (generously).
    const int remaining = plan_.domain.levels - 1 - level;
    const double projected = static_cast<double>(children) * std::pow(double(s_.branching), 2.0 * remaining);
    const double pool_projected = projected * double(s_.layout().brick_bytes());
    if (pool_projected > 4.0 * static_cast<double>(d_.info().max_alloc_bytes))
        throw SettingError("leaf_size", fmt::format(
            "leaf_size {} is too small for geometry \"{}\" on {}: level {} already has {} bricks, which "
            "projects to about {:.3g} leaf bricks and a brick pool of {:.3g} bytes; the device allocates at most "
            "{} bytes at once: use a larger leaf_size",
            s_.leaf_size, g_.name, d_.info().name, level, children, projected, pool_projected,
            d_.info().max_alloc_bytes));
    return children;
}

void BrickBuilder::Job::subdivide(int level, std::uint64_t children) {
    auto bricks = std::make_unique<ocl::Buffer<SdfBrick>>(
        allocate<SdfBrick>(d_, children, fmt::format("level {} ({} bricks)", level, children)));
    brick_bytes_ += bricks->bytes();
    if (children > 0) {
        const cl_uint lb = level_log2b(level);
        if (words_.size() < children) words_ = allocate<cl_uint>(d_, children, "the cull word counts");
        ocl::set_args(b_.programs_->subdivide_k.get(), *parents_, static_cast<cl_uint>(parent_count_), lb, offsets_,
                      *bricks, words_);
        const std::size_t global = round_up(parent_count_ << (3 * lb), kGroup1d);
        scheduler_.launch(measure::Stage::subdivide, level, b_.programs_->subdivide_k.get(), global, kGroup1d);
    }
    if (level > 0) level_bricks_.push_back(std::move(parents_));  // the parent level's masks are final now
    parents_ = std::move(bricks);
}

// Each child's edit list from its parent's; without culling every brick keeps the whole list.
void BrickBuilder::Job::cull(int level, std::uint64_t children) {
    if (s_.cull && children > 0) {
        cull_lists(level, children);
        return;
    }
    list_entries_.push_back(children * edits_host_.size());
}

// What the device runs of a kernel at once, as the count and cull stages size their work: compute
// units times the kernel's work-group limit.
std::uint64_t BrickBuilder::Job::resident_items(std::size_t work_group_limit) const {
    return std::uint64_t{d_.info().compute_units} * work_group_limit;
}

// The bits of the cull bit sets per work-item of cull_mark and cull_write (a power of two up to 32):
// the fewest that keep the work-items within resident_items. Changes no bit.
std::uint64_t BrickBuilder::Job::bits_per_item(std::uint64_t words, cl_kernel kernel, std::string_view name) const {
    const std::uint64_t resident = resident_items(ocl::kernel_work_group_limit(d_, kernel, name));
    std::uint64_t span = 1;
    while (span < 32 && words * 32 / span > resident) span *= 2;
    return span;
}

void BrickBuilder::Job::cull_lists(int level, std::uint64_t children) {
    const auto& k = *b_.programs_;
    const ocl::Buffer<SdfBrick>& bricks = *parents_;  // this level's bricks (subdivide moved them there)
    const ocl::Buffer<cl_uint>& parent_lists = *parent_lists_;
    const std::size_t global = round_up(children, kGroup1d);
    const auto n = static_cast<cl_uint>(children);
    const std::uint64_t total_words = b_.scan_.exclusive(words_, words_, children, scheduler_, measure::Stage::cull, level);
    if (total_words > 0xffffffffu / 32)
        throw InputError(fmt::format("level {} inherits {} words of edit-list bits, more than one build handles "
                                     "(2^27): use a larger brick size",
                                     level, total_words));
    if (bits_.size() < total_words) bits_ = allocate<cl_uint>(d_, total_words, "the cull bit sets");
    if (sources_.size() < total_words) sources_ = allocate<cl_uint>(d_, total_words, "the cull word sources");
    if (total_words > 0) {
        const std::uint64_t span = bits_per_item(total_words, k.mark_k.get(), "cull_mark");
        ocl::set_args(k.mark_k.get(), edits_, meshes_, parent_lists, bricks, n, static_cast<cl_uint>(total_words),
                      static_cast<cl_uint>(span), origin_.x, origin_.y, origin_.z, cell(level),
                      plan_.cull_radius(level, s_.layout().apron()), plan_.cull_saturation(level),
                      static_cast<float>(plan_.magnitude), words_, bits_, sources_,
                      ocl::LocalMemory{kGroup1d * sizeof(cl_uint)});
        scheduler_.launch(measure::Stage::cull, level, k.mark_k.get(), round_up(total_words * 32 / span, kGroup1d),
                          kGroup1d);
    }
    const ocl::Buffer<cl_uint>& dep_offsets = deps_ ? deps_->offsets : empty_uints_;
    const ocl::Buffer<cl_uint>& dep_indices = deps_ ? deps_->indices : empty_uints_;
    if (kept_words_.size() < total_words + 1) kept_words_ = allocate<cl_uint>(d_, total_words + 1, "the cull kept counts");
    ocl::set_args(k.cull_count_k.get(), edits_, parent_lists, bricks, n, static_cast<cl_uint>(total_words), words_, bits_,
                  static_cast<cl_uint>(deps_ ? 1 : 0), dep_offsets, dep_indices, kept_words_);
    scheduler_.launch(measure::Stage::cull, level, k.cull_count_k.get(), global, kGroup1d);
    const std::uint64_t entries =
        b_.scan_.exclusive(kept_words_, kept_words_, total_words + 1, scheduler_, measure::Stage::cull, level);
    auto lists = std::make_unique<ocl::Buffer<cl_uint>>(
        allocate<cl_uint>(d_, entries, fmt::format("the edit lists of level {}", level)));
    const std::uint64_t span = bits_per_item(total_words, k.write_k.get(), "cull_write");
    ocl::set_args(k.write_k.get(), parent_lists, bricks, n, static_cast<cl_uint>(total_words), static_cast<cl_uint>(span),
                  words_, bits_, sources_, kept_words_, *lists);
    scheduler_.launch(measure::Stage::cull, level, k.write_k.get(),
                      round_up(std::max<std::uint64_t>(total_words * 32 / span, children), kGroup1d), kGroup1d);
    list_bytes_ += lists->bytes();
    list_entries_.push_back(entries);
    if (!level_leaves_.empty() && level_leaves_.back().level == level - 1) level_leaves_.back().lists = std::move(parent_lists_);
    parent_lists_ = std::move(lists);
}

// Checks this level's bricks (parents_, a level coarser than the finest) against the tolerance; those
// that pass become this level's leaves, the others stay in parents_ for the next level. Returns the
// parents left.
std::uint64_t BrickBuilder::Job::check_and_split(int level) {
    const std::uint64_t n = parent_count_;
    const BrickLayout layout = s_.layout();
    const std::size_t group = std::min<std::size_t>(s_.eval_group, layout.samples_per_brick());
    const ocl::Program program = ocl::build_program(d_, "brick_check.cl", layout.defines());
    const ocl::Kernel kernel = ocl::make_kernel(program, "brick_check");
    LevelLeaves out{level, 0, nullptr, allocate<float>(d_, n, "the check errors"),
                    allocate<cl_uint>(d_, n, "the check results"), nullptr};
    const float band = std::ldexp(plan_.band, plan_.shift(level));
    ocl::set_args(kernel.get(), edits_, meshes_, *parent_lists_, *parents_, origin_.x, origin_.y, origin_.z,
                  static_cast<float>(std::ldexp(plan_.voxel, plan_.shift(level))), plan_.level_clamp[level], band,
                  layout.quantise_scale(band), layout.dequantise_scale(band), plan_.tolerance, plan_.band, out.errors,
                  out.passed,
                  ocl::LocalMemory{layout.samples_per_brick() * sizeof(float)}, ocl::LocalMemory{group * sizeof(float)});
    scheduler_.launch(measure::Stage::check, level, kernel.get(), n * group, group);
    if (offsets_.size() < n) offsets_ = allocate<cl_uint>(d_, n, "the leaf offsets");
    out.count = b_.scan_.exclusive(out.passed, offsets_, n, scheduler_, measure::Stage::check, level);
    out.leaves = std::make_unique<ocl::Buffer<SdfBrick>>(
        allocate<SdfBrick>(d_, out.count, fmt::format("the leaves of level {}", level)));
    auto parents = std::make_unique<ocl::Buffer<SdfBrick>>(
        allocate<SdfBrick>(d_, n - out.count, fmt::format("the parents of level {}", level + 1)));
    const auto& k = *b_.programs_;
    ocl::set_args(k.split_k.get(), *parents_, static_cast<cl_uint>(n), out.passed, offsets_, *out.leaves, *parents);
    scheduler_.launch(measure::Stage::check, level, k.split_k.get(), round_up(n, kGroup1d), kGroup1d);
    brick_bytes_ += out.leaves->bytes() + parents->bytes();
    parents_ = std::move(parents);
    const std::uint64_t left = n - out.count;
    level_leaves_.push_back(std::move(out));
    return left;
}

std::uint64_t BrickBuilder::Job::assemble_leaves() {
    std::vector<cl_uint> first{0}, list_base(static_cast<std::size_t>(plan_.domain.levels), 0);
    std::uint64_t entries = parent_lists_->size();
    for (const LevelLeaves& l : level_leaves_) {
        first.push_back(static_cast<cl_uint>(first.back() + l.count));
        if (l.lists) entries += l.lists->size();
    }
    const std::uint64_t total = first.back();
    ocl::Buffer<SdfBrick> all = allocate<SdfBrick>(d_, total, "the leaves of every level");
    ocl::Buffer<cl_uint> lists = allocate<cl_uint>(d_, entries, "the edit lists of every level");
    std::uint64_t at = 0;
    for (const LevelLeaves& l : level_leaves_) {
        all.copy_from(l.leaves ? *l.leaves : *level_bricks_.back(), first[&l - level_leaves_.data()]);
        list_base[l.level] = static_cast<cl_uint>(l.lists ? at : entries - parent_lists_->size());
        if (l.lists) lists.copy_from(*l.lists, at);
        at += l.lists ? l.lists->size() : 0;
    }
    lists.copy_from(*parent_lists_, at);
    const ocl::Buffer<cl_uint> first_d(d_, std::span<const cl_uint>(first), CL_MEM_READ_ONLY);
    const ocl::Buffer<cl_uint> base_d(d_, std::span<const cl_uint>(list_base), CL_MEM_READ_ONLY);
    ocl::Buffer<cl_uint> positions = allocate<cl_uint>(d_, total, "the leaf positions");
    merged_leaves_ = std::make_unique<ocl::Buffer<SdfBrick>>(allocate<SdfBrick>(d_, total, "the leaves"));
    const auto& k = *b_.programs_;
    const auto count = static_cast<cl_uint>(total);
    ocl::set_args(k.rank_k.get(), all, first_d, static_cast<cl_uint>(level_leaves_.size()), count,
                  static_cast<cl_uint>(plan_.finest()), plan_.log2b, positions);
    scheduler_.launch(measure::Stage::order, -1, k.rank_k.get(), round_up(total, kGroup1d), kGroup1d);
    ocl::set_args(k.place_k.get(), all, positions, count, base_d, *merged_leaves_);
    scheduler_.launch(measure::Stage::order, -1, k.place_k.get(), round_up(total, kGroup1d), kGroup1d);
    list_bytes_ += lists.bytes();
    parent_lists_ = std::make_unique<ocl::Buffer<cl_uint>>(std::move(lists));
    return total;
}

// The check's worst error of every checked leaf (the finest level's are not checked; reads the
// check results back, for the report).
void BrickBuilder::Job::check_errors(std::vector<double>& leaf_errors) const {
    for (const LevelLeaves& l : level_leaves_) {
        const std::vector<float> errors = l.errors.read();
        const std::vector<cl_uint> passed = l.passed.read();
        for (std::size_t i = 0; i < errors.size(); ++i)
            if (passed[i]) leaf_errors.push_back(errors[i]);
    }
}

// Keeps the range of this level's bricks that subtrees_ picks; their lists stay where they are.
std::uint64_t BrickBuilder::Job::keep_subtrees(std::uint64_t children) {
    const std::vector<SdfBrick> records = parents_->read();
    const auto [first, end] = subtrees_->pick(records);
    if (first > end || end > children)
        throw std::logic_error(fmt::format("subtrees: range [{}, {}) of {} bricks", first, end, children));
    parents_ = std::make_unique<ocl::Buffer<SdfBrick>>(
        d_, std::span<const SdfBrick>(records).subspan(first, end - first));
    return end - first;
}

// The pool (every leaf's samples) and the leaves' boxes.
void BrickBuilder::Job::evaluate_leaves(std::uint64_t leaf_count) {
    const BrickLayout layout = s_.layout();
    const std::size_t samples3 = layout.samples_per_brick();
    out_.pool = std::make_unique<ocl::Buffer<std::uint8_t>>(allocate<std::uint8_t>(
        d_, leaf_count * layout.brick_bytes(), fmt::format("the brick pool ({} bricks)", leaf_count)));
    out_.aabbs = std::make_unique<ocl::Buffer<SdfBounds>>(allocate<SdfBounds>(d_, leaf_count, "the brick AABBs"));
    out_.shifts = std::make_unique<ocl::Buffer<cl_uint>>(allocate<cl_uint>(d_, leaf_count, "the brick shifts"));
    if (leaf_count == 0) return;
    const auto lanes = static_cast<std::size_t>(s_.lanes(d_.info()));
    const std::size_t group = std::min<std::size_t>(s_.eval_group, (samples3 + lanes - 1) / lanes);
    const std::size_t per_item = (samples3 + group * lanes - 1) / (group * lanes);
    const double mean_list = s_.cull ? static_cast<double>(parent_lists_->size()) / static_cast<double>(leaf_count)
                                     : static_cast<double>(edits_host_.size());
    // Long lists branch once per edit (EVAL_HOIST), and only those skip far edits; the skip's code
    // costs registers, so only a geometry with sphere or capsule adds or subtracts has it.
    const bool hoist = mean_list >= BuildSettings::kLongList;
    const bool skip_far = hoist && s_.skip_far && std::any_of(edits_host_.begin(), edits_host_.end(), [](const SdfEdit& e) {
        return (e.primitive == SDF_PRIM_SPHERE || e.primitive == SDF_PRIM_CAPSULE) &&
               (e.op == SDF_OP_ADD || e.op == SDF_OP_SUBTRACT);
    });
    const ocl::Program program = ocl::build_program(
        d_, "brick_evaluate.cl",
        fmt::format("{} -DSDF_LANES={} -DPER_ITEM={} -DEVAL_HOIST={} -DAPRON_SHARED={} -DSKIP_FAR={}", layout.defines(),
                    lanes, per_item, hoist ? 1 : 0, s_.apron_share_edits > 0 ? 1 : 0,
                    skip_far ? 1 : 0));
    const ocl::Kernel kernel = ocl::make_kernel(program, "brick_evaluate");
    const int leaf_level = plan_.domain.levels - 1;
    const ocl::Buffer<float> level_clamp(d_, std::span<const float>(plan_.level_clamp), CL_MEM_READ_ONLY);
    const auto finest = static_cast<cl_uint>(plan_.finest());
    const ApronSharing apron = share_aprons(leaf_count, s_.apron_share_edits);
    ocl::set_args(kernel.get(), edits_, meshes_, *parent_lists_, leaves(), owned_ ? *owned_ : empty_uints_, origin_.x,
                  origin_.y, origin_.z,
                  static_cast<float>(plan_.voxel), level_clamp, plan_.band, layout.quantise_scale(plan_.band), finest,
                  plan_.log2b, *out_.pool, ocl::LocalMemory{chunk_bytes()}, static_cast<cl_uint>(s_.chunk));
    scheduler_.launch(measure::Stage::evaluate, leaf_level, kernel.get(), leaf_count * group, group);
    if (apron.copy) {
        ocl::set_args(apron.copy->get(), *owned_, apron.neighbours, *out_.pool);
        scheduler_.launch(measure::Stage::apron, leaf_level, apron.copy->get(), leaf_count * kGroup1d, kGroup1d);
    }
    ocl::set_args(b_.programs_->aabb_k.get(), leaves(), static_cast<cl_uint>(leaf_count), origin_.x, origin_.y,
                  origin_.z, out_.leaf_size, finest, plan_.log2b, *out_.aabbs, *out_.shifts);
    scheduler_.launch(measure::Stage::aabb, leaf_level, b_.programs_->aabb_k.get(), round_up(leaf_count, kGroup1d),
                      kGroup1d);
}

// With sharing on, which regions of its samples each leaf evaluates (owned_): its interior and the
// apron regions whose neighbour of the same level is not a leaf (brick_keys, brick_owned). Returns
// the neighbours and the copy kernel that brick_apron.cl runs after the evaluation. With sharing off
// every leaf evaluates all its samples, and there is nothing to find: owned_ stays empty.
BrickBuilder::Job::ApronSharing BrickBuilder::Job::share_aprons(std::uint64_t leaf_count, int share_edits) {
    ApronSharing a{ocl::Buffer<cl_uint>(d_, 0), std::nullopt, std::nullopt};
    if (share_edits <= 0) return a;
    owned_ = std::make_unique<ocl::Buffer<cl_uint>>(allocate<cl_uint>(d_, leaf_count, "the apron masks"));
    a.neighbours = allocate<cl_uint>(d_, leaf_count * 27, "the apron neighbours");
    ocl::Buffer<cl_ulong> keys = allocate<cl_ulong>(d_, leaf_count, "the leaf keys");
    scratch_bytes_ = std::max<std::uint64_t>(scratch_bytes_, owned_->bytes() + a.neighbours.bytes() + keys.bytes());
    a.program.emplace(ocl::build_program(d_, "brick_apron.cl", s_.layout().defines()));
    const ocl::Kernel keys_k = ocl::make_kernel(*a.program, "brick_keys"), owned = ocl::make_kernel(*a.program, "brick_owned");
    const auto count = static_cast<cl_uint>(leaf_count), finest = static_cast<cl_uint>(plan_.finest());
    const int leaf_level = plan_.domain.levels - 1;
    ocl::set_args(keys_k.get(), leaves(), count, finest, plan_.log2b, keys);
    scheduler_.launch(measure::Stage::apron, leaf_level, keys_k.get(), round_up(leaf_count, kGroup1d), kGroup1d);
    ocl::set_args(owned.get(), leaves(), keys, count, finest, plan_.log2b, static_cast<cl_uint>(share_edits),
                  *owned_, a.neighbours);
    scheduler_.launch(measure::Stage::apron, leaf_level, owned.get(), round_up(leaf_count, kGroup1d), kGroup1d);
    a.copy.emplace(ocl::make_kernel(*a.program, "brick_apron"));
    return a;
}

// The report's counters of the records and lists, reduced on the device (kernels/brick_stats.cl):
// every level's and the leaves' partials land in one buffer that one read brings back.
BrickBuilder::Job::Counters BrickBuilder::Job::count_on_device(std::uint64_t leaf_count) {
    static constexpr std::size_t kGroup = 64, kGroups = 64;  // STATS_GROUP; work-groups per reduction at most
    const auto groups = [](std::uint64_t n) { return std::min<std::size_t>((n + kGroup - 1) / kGroup, kGroups); };
    const std::size_t levels = level_bricks_.size(), leaf_base = 2 * kGroups * levels;
    const Programs::Stats& k = b_.programs_->stats(d_, s_.layout());
    ocl::Buffer<cl_ulong> partial(ocl::pooled, d_, leaf_base + 5 * kGroups);
    Counters c;
    c.records.resize(levels);
    std::vector<std::size_t> launched(levels, 0);
    for (std::size_t l = 0; l < levels; ++l) {
        c.records[l] = level_bricks_[l] ? level_bricks_[l]->size() : 0;
        if (c.records[l] == 0) continue;
        launched[l] = groups(c.records[l]);
        ocl::set_args(k.level.get(), *level_bricks_[l], static_cast<cl_uint>(c.records[l]), partial,
                      static_cast<cl_uint>(2 * kGroups * l));
        ocl::enqueue(d_, k.level.get(), "level_stats", launched[l] * kGroup, kGroup);
    }
    const std::size_t leaf_groups = leaf_count > 0 ? groups(leaf_count) : 0;
    if (leaf_groups > 0) {
        std::vector<cl_uint> flops(edits_host_.size());
        for (std::size_t i = 0; i < flops.size(); ++i) flops[i] = static_cast<cl_uint>(edit_flops(edits_host_[i]));
        const ocl::Buffer<cl_uint> flops_d(d_, std::span<const cl_uint>(flops), CL_MEM_READ_ONLY);
        ocl::set_args(k.leaf.get(), leaves(), static_cast<cl_uint>(leaf_count), *parent_lists_, flops_d,
                      owned_ ? *owned_ : empty_uints_, static_cast<cl_uint>(owned_ ? 1 : 0), partial,
                      static_cast<cl_uint>(leaf_base));
        ocl::enqueue(d_, k.leaf.get(), "leaf_stats", leaf_groups * kGroup, kGroup);
    }
    const std::vector<cl_ulong> p = partial.read();
    c.longest.assign(levels, 0);
    c.tests.assign(levels, 0);
    for (std::size_t l = 0; l < levels; ++l)
        for (std::size_t g = 0; g < launched[l]; ++g) {
            c.longest[l] = std::max(c.longest[l], p[2 * kGroups * l + 2 * g]);
            c.tests[l] += p[2 * kGroups * l + 2 * g + 1];
        }
    for (std::size_t g = 0; g < leaf_groups; ++g) {
        const cl_ulong* v = &p[leaf_base + 5 * g];
        c.entries += v[0];
        c.longest_leaf = std::max<std::uint64_t>(c.longest_leaf, v[1]);
        c.entry_flops += v[2];
        c.flops += v[3];
        c.evaluations += v[4];
    }
    return c;
}

// Bricks, list lengths, work and times per level, from the counters reduced on the device (not part
// of device time).
void BrickBuilder::Job::report(std::uint64_t leaf_count) {
    const Counters c = count_on_device(leaf_count);
    std::uint64_t evaluations = 0;
    std::uint64_t prev_entries = edits_host_.size();  // the pseudo-parent's list
    std::uint64_t prev_records = 1, prev_tests = 0;
    for (std::size_t l = 0; l < level_bricks_.size(); ++l) {
        // Adaptive builds keep only the parents of each level here (the finest level: none).
        const std::uint64_t records = c.records[l];
        LevelReport r;
        r.level = static_cast<int>(l);
        r.cell_size = plan_.domain.cell_size(r.level);
        r.bricks = l < kept_.size() ? kept_[l] : records;
        r.leaves = s_.adaptive() ? 0 : (r.level == plan_.finest() ? r.bricks : 0);
        for (const LevelLeaves& leaves : level_leaves_)
            if (leaves.level == r.level) r.leaves = leaves.count;
        r.edit_entries = l < list_entries_.size() ? list_entries_[l] : 0;
        r.max_edits = static_cast<std::uint32_t>(c.longest[l]);
        const std::uint64_t counted = prev_entries * (l == 0 ? 1 : plan_.per_parent);  // every candidate child of every parent
        add_work(measure::Stage::count, counted, prev_records * (sizeof(SdfBrick) + sizeof(cl_uint)) + prev_entries * kEntryBytes);
        std::uint64_t culled = 0;
        if (s_.cull) {  // cull: each kept child tests its parent's list
            culled = l == 0 ? edits_host_.size() * records : prev_tests;
            add_work(measure::Stage::cull, culled,
                     records * sizeof(SdfBrick) + culled * kEntryBytes + r.edit_entries * sizeof(cl_uint));
        }
        evaluations += counted + culled;
        r.count_ms = scheduler_.stage_ms(measure::Stage::count, r.level, out_.first_launch);
        r.scan_ms = scheduler_.stage_ms(measure::Stage::scan, r.level, out_.first_launch);
        r.subdivide_ms = scheduler_.stage_ms(measure::Stage::subdivide, r.level, out_.first_launch);
        r.cull_ms = scheduler_.stage_ms(measure::Stage::cull, r.level, out_.first_launch);
        out_.level_reports.push_back(r);
        prev_entries = r.edit_entries;
        prev_records = records;
        prev_tests = c.tests[l];
    }
    if (leaf_count > 0 && s_.adaptive()) {
        out_.edits_per_leaf_mean = static_cast<double>(c.entries) / static_cast<double>(leaf_count);
        out_.edits_per_leaf_max = static_cast<std::uint32_t>(c.longest_leaf);
        std::vector<double> errors;
        check_errors(errors);
        std::sort(errors.begin(), errors.end());
        out_.check_error_max = errors.empty() ? 0.0 : errors.back();
        out_.check_error_p99 = errors.empty() ? 0.0 : errors[std::min(errors.size() - 1, errors.size() * 99 / 100)];
    } else if (leaf_count > 0) {
        const LevelReport& leaf = out_.level_reports.back();
        out_.edits_per_leaf_mean = static_cast<double>(leaf.edit_entries) / static_cast<double>(leaf_count);
        out_.edits_per_leaf_max = leaf.max_edits;
    }
    report_flops(leaf_count, c);
    out_.edit_evaluations = evaluations + out_.work[measure::Stage::evaluate].evaluations;
    out_.memory["brick pool"] = out_.pool->bytes();
    out_.memory["brick records"] = brick_bytes_;
    out_.memory["aabbs"] = out_.aabbs->bytes();
    out_.memory["edit lists"] = list_bytes_;
    out_.memory["edits"] = edits_.bytes();
    if (meshes_.size() > 1) out_.memory["mesh grids"] = meshes_.bytes();  // one float: no mesh
    out_.memory["scratch"] = scratch_bytes_;
}

// Evaluate's work from the leaves' lists and owned samples, and the FLOPs of count and cull from the
// mean FLOPs of a leaf list entry.
void BrickBuilder::Job::report_flops(std::uint64_t leaf_count, const Counters& c) {
    const BrickLayout layout = s_.layout();
    add_work(measure::Stage::evaluate, c.evaluations,
             leaf_count * (sizeof(SdfBrick) + sizeof(cl_uint) + layout.brick_bytes()) + c.entries * kEntryBytes);
    const double mean = c.entries > 0 ? static_cast<double>(c.entry_flops) / static_cast<double>(c.entries) : 0.0;
    for (auto& [stage, w] : out_.work) w.flop = static_cast<double>(w.evaluations) * mean;
    out_.work[measure::Stage::evaluate].flop = static_cast<double>(c.flops);
}

void BrickBuilder::Job::add_work(measure::Stage stage, std::uint64_t evaluations, std::uint64_t bytes) {
    StageWork& w = out_.work[stage];
    w.evaluations += evaluations;
    w.bytes += static_cast<double>(bytes);
}

GeometryBuild BrickBuilder::build(const Geometry& g, const BuildSettings& s, measure::Scheduler& scheduler,
                                  const Subtrees* subtrees) {
    const auto wall_start = std::chrono::steady_clock::now();
    s.validate(device_.info());
    if (g.edits.size() > SDF_MAX_EDITS)
        throw InputError(fmt::format("geometry \"{}\" has {} edits; at most {} are supported", g.name, g.edits.size(),
                                     SDF_MAX_EDITS));
    GeometryBuild out;
    out.name = g.name;
    out.first_launch = out.end_launch = scheduler.size();
    out.leaf_size = static_cast<float>(s.leaf_size);
    const Aabb box = bounds(g);
    if (box.empty()) {  // no add edit: nothing can be solid, an empty and valid result
        out.leaves = std::make_unique<ocl::Buffer<SdfBrick>>(device_, 0);
        out.leaf_edit_indices = std::make_unique<ocl::Buffer<cl_uint>>(device_, 0);
        out.pool = std::make_unique<ocl::Buffer<std::uint8_t>>(device_, 0);
        out.aabbs = std::make_unique<ocl::Buffer<SdfBounds>>(device_, 0);
        out.shifts = std::make_unique<ocl::Buffer<cl_uint>>(device_, 0);
        return out;
    }
    const BuildPlan plan = plan_build(g, box, s);
    out.origin = glm::vec3(plan.domain.origin);
    out.levels = plan.domain.levels;
    out.branching = s.branching;
    out.band = plan.band;
    out.clamp_c = plan.clamp_c;
    Job job(*this, g, s, plan, scheduler, out, subtrees);
    job.start();
    const bool complete = job.run_levels();
    out.coarsest_leaf_level = plan.coarsest_leaf;
    out.tolerance = s.tolerance;
    out.leaf_count = s.adaptive() ? job.assemble_leaves() : complete ? job.parent_count() : 0;
    job.evaluate_leaves(out.leaf_count);
    device_.finish();
    scheduler.resolve();
    out.end_launch = scheduler.size();
    out.device_ms = scheduler.total_ms(out.first_launch);
    job.report(out.leaf_count);
    out.leaves = complete || s.adaptive() ? job.take_leaves() : std::make_unique<ocl::Buffer<SdfBrick>>(device_, 0);
    out.leaf_edit_indices = job.take_lists();
    out.host_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - wall_start).count();
    return out;
}

namespace {

// The leaf records' part of the output digest: coordinates, and levels in adaptive builds.
ocl::Records coordinate_records(const GeometryBuild& b, const BuildSettings& s) {
    return {b.leaves->size(), sizeof(SdfBrick), offsetof(SdfBrick, coord), s.adaptive() ? 4 * sizeof(sdf_u32) : 3 * sizeof(sdf_i32)};
}

std::string output_digest_of(const GeometryBuild& b, const BuildSettings& s, std::uint64_t coordinates, std::uint64_t pool) {
    static_assert(offsetof(SdfBrick, level) == 3 * sizeof(sdf_i32), "a leaf's level follows its coordinate");
    Fnv1a64 h;
    const std::array<float, 4> domain{b.origin.x, b.origin.y, b.origin.z, b.leaf_size};
    h.add_values(std::span<const float>(domain));
    const std::array<std::int32_t, 3> layout{s.samples, static_cast<std::int32_t>(s.format), static_cast<std::int32_t>(b.leaf_count)};
    h.add_values(std::span<const std::int32_t>(layout));
    const std::array<std::uint64_t, 2> parts{coordinates, pool};
    return h.add_values(std::span<const std::uint64_t>(parts)).hex();
}

}  // namespace

std::vector<std::pair<std::string, std::string>> build_digests(std::span<const GeometryBuild> builds,
                                                               const BuildSettings& s, ocl::DeviceDigest& digest) {
    for (const GeometryBuild& b : builds) {
        digest.enqueue(b.leaves->get(), coordinate_records(b, s));
        digest.enqueue(b.pool->get(), {b.pool->bytes(), 1, 0, 1});
        digest.enqueue_leaf_lists(*b.leaves, *b.leaf_edit_indices);
    }
    const std::vector<std::uint64_t> v = digest.read_all();
    std::vector<std::pair<std::string, std::string>> out;
    for (std::size_t i = 0; i < builds.size(); ++i)
        out.emplace_back(output_digest_of(builds[i], s, v[3 * i], v[3 * i + 1]), fmt::format("{:016x}", v[3 * i + 2]));
    return out;
}

std::string output_digest(const GeometryBuild& b, const BuildSettings& s) {
    const ocl::Records w = coordinate_records(b, s);
    const std::vector<SdfBrick> leaves = b.leaves->read();
    std::vector<std::byte> coordinates;
    for (const SdfBrick& r : leaves) {
        const auto bytes = std::as_bytes(std::span(&r, 1)).subspan(w.first, w.take);
        coordinates.insert(coordinates.end(), bytes.begin(), bytes.end());
    }
    const std::vector<std::uint8_t> pool = b.pool->read();
    return output_digest_of(b, s, tree_digest(coordinates, ocl::DeviceDigest::block_bytes(w.take)),
                            tree_digest(std::as_bytes(std::span(pool))));
}

std::string list_digest(const GeometryBuild& b) {
    const std::vector<SdfBrick> leaves = b.leaves->read();
    const std::vector<cl_uint> indices = b.leaf_edit_indices->read();
    std::vector<std::uint64_t> per_leaf;
    for (const SdfBrick& r : leaves) {
        Fnv1a64 h;
        h.add_values(std::span<const sdf_i32>(r.coord, 3));
        h.add_values(std::span<const cl_uint>(indices.data() + r.edit_offset, r.edit_count));
        per_leaf.push_back(h.value());
    }
    return fmt::format("{:016x}", tree_digest(std::as_bytes(std::span(per_leaf))));
}

}  // namespace sdfbrick::construct
