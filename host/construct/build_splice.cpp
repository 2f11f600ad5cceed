// BrickBuilder::rebuild: the build of a geometry after an edit change, from the build before it.
//
// A brick's subtree (which of its descendants are kept, their edit lists, their samples) depends only
// on the brick's own edit list, and an edit enters a list only where it can change the band-limited
// field (sdf_within_reach), so a changed edit leaves alone every subtree it cannot reach. The levels
// run as in a build, but after each level's cull only the bricks a changed edit (as it was, or as it
// is) may reach go on; a brick out of reach is frozen: its subtree is the earlier build's leaves under
// it, a contiguous run of the Morton-ordered leaves, whose lists only have their edit indices moved
// down past removed edits. A brick out of reach with no earlier leaves under it (its keep decision
// may have changed: the count's rounding allowance sums over its parent's whole list) is built, as
// is everything in reach. The leaves built again and the frozen runs are merged in Morton order on
// the device (kernels/brick_splice.cl).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include "cl/launch.h"
#include "construct/build_parts.h"

namespace sdfbrick::construct {

namespace {

std::uint64_t spread21(std::uint32_t v) {
    std::uint64_t x = v & 0x1FFFFFu;
    x = (x | (x << 32)) & 0x1F00000000FFFFull;
    x = (x | (x << 16)) & 0x1F0000FF0000FFull;
    x = (x | (x << 8)) & 0x100F00F00F00F00Full;
    x = (x | (x << 4)) & 0x10C30C30C30C30C3ull;
    x = (x | (x << 2)) & 0x1249249249249249ull;
    return x;
}

// The Morton key of a brick's low corner on the finest lattice (sdf_morton.h), its cell 2^shift
// finest cells wide.
std::uint64_t lattice_key(const SdfBrick& b, unsigned shift) {
    return spread21(static_cast<std::uint32_t>(b.coord[0]) << shift) |
           (spread21(static_cast<std::uint32_t>(b.coord[1]) << shift) << 1) |
           (spread21(static_cast<std::uint32_t>(b.coord[2]) << shift) << 2);
}

bool confinable(const BuildSettings& s, const EditChange& change) {
    if (s.adaptive() || !s.cull || s.dependencies || s.apron_share_edits > 0) return false;
    for (const std::vector<Edit>* list : {&change.before, &change.after})
        for (const Edit& e : *list)
            if (e.op == Op::Intersect || e.primitive == Primitive::Mesh) return false;
    return true;
}

bool same_frame(const detail::BuildPlan& plan, const GeometryBuild& before, const BuildSettings& s) {
    return glm::vec3(plan.domain.origin) == before.origin && plan.domain.levels == before.levels &&
           plan.band == before.band && plan.clamp_c == before.clamp_c && static_cast<float>(s.leaf_size) == before.leaf_size &&
           s.branching == before.branching;
}

// How far past its blend a changed edit's value may be and still change what a brick of `level`
// holds or what its subtree computes, with margins for float rounding: its own list (the cull of its
// level: saturation and radius around its centre), and below it the count tests (saturation and
// threshold) and culls of every finer level. Its own keep decision is made again in any case.
struct ReachMargins {
    double own = 0.0, below = 0.0;
};
ReachMargins reach_margins(const detail::BuildPlan& plan, int level) {
    const auto cull = [&](int k) { return double(plan.cull_saturation(k)) + double(plan.cull_radius(k)); };
    ReachMargins m{cull(level), 0.0};
    for (int k = level + 1; k <= plan.finest(); ++k)
        m.below = std::max({m.below, double(plan.saturation(k)) + double(plan.threshold(k)), cull(k)});
    const double slack = plan.magnitude * std::ldexp(1.0, -12);
    return {m.own * (1.0 + 1.0 / 1024.0) + slack, m.below * (1.0 + 1.0 / 1024.0) + slack};
}

// Per level above the finest, where a changed edit reaches: boxes (geometry frame) that hold every
// centre of a brick whose own list it may enter, and boxes that every brick whose subtree it may
// change meets.
struct Reach {
    std::vector<std::vector<Aabb>> own, below;
};
Reach reach_of(const detail::BuildPlan& plan, const EditChange& change) {
    Reach out;
    out.own.resize(static_cast<std::size_t>(plan.finest()));
    out.below.resize(out.own.size());
    for (int l = 0; l < plan.finest(); ++l) {
        const ReachMargins m = reach_margins(plan, l);
        for (const std::vector<Edit>* list : {&change.before, &change.after})
            for (const Edit& e : *list) {
                const glm::dvec3& t = e.transform.translation;
                double size = 0.0;
                for (double p : e.params) size = std::max(size, std::abs(p));
                const double rounding =
                    (plan.magnitude + std::max({std::abs(t.x), std::abs(t.y), std::abs(t.z)}) + e.transform.scale * size) *
                    std::ldexp(1.0, -12);
                out.own[static_cast<std::size_t>(l)].push_back(level_bounds(e, e.blend + m.own + rounding));
                out.below[static_cast<std::size_t>(l)].push_back(level_bounds(e, e.blend + m.below + rounding));
            }
    }
    return out;
}

bool overlaps(const Aabb& a, const Aabb& b) {
    return a.lo.x <= b.hi.x && b.lo.x <= a.hi.x && a.lo.y <= b.hi.y && b.lo.y <= a.hi.y && a.lo.z <= b.hi.z &&
           b.lo.z <= a.hi.z;
}

// A run of output leaves: from the earlier build (old) or the leaves built again (fresh).
struct Run {
    std::uint64_t key = 0;  // of its first leaf
    std::uint32_t first = 0, count = 0;
    bool fresh = false;
};

// The levels' confinement: bricks in reach (or without earlier leaves) go on; the others are frozen
// runs of the earlier leaves.
class Confinement {
public:
    Confinement(const detail::BuildPlan& plan, const std::vector<SdfBrick>& old_records, const EditChange& change)
        : plan_(plan), reach_(reach_of(plan, change)) {
        keys_.reserve(old_records.size());
        for (const SdfBrick& b : old_records) keys_.push_back(lattice_key(b, 0));
    }

    detail::Region region() {
        return {[this](int level, const std::vector<SdfBrick>& records) { return keep(level, records); }};
    }
    std::vector<Run>& frozen() { return frozen_; }

private:
    std::vector<std::uint32_t> keep(int level, const std::vector<SdfBrick>& records) {
        const double cell = plan_.domain.cell_size(level);
        const unsigned shift = static_cast<unsigned>(plan_.shift(level));
        std::vector<std::uint32_t> out;
        for (std::size_t i = 0; i < records.size(); ++i) {
            const SdfBrick& b = records[i];
            Aabb box;
            box.lo = plan_.domain.origin + glm::dvec3(b.coord[0], b.coord[1], b.coord[2]) * cell;
            box.hi = box.lo + glm::dvec3(cell);
            const Aabb centre{box.lo + 0.5 * cell, box.lo + 0.5 * cell};
            const auto& own = reach_.own[static_cast<std::size_t>(level)];
            const auto& below = reach_.below[static_cast<std::size_t>(level)];
            const bool reached = std::any_of(own.begin(), own.end(), [&](const Aabb& r) { return overlaps(r, centre); }) ||
                                 std::any_of(below.begin(), below.end(), [&](const Aabb& r) { return overlaps(r, box); });
            const std::uint64_t first = lattice_key(b, shift), end = first + (std::uint64_t{1} << (3 * shift));
            const auto lo = std::lower_bound(keys_.begin(), keys_.end(), first);
            const auto hi = std::lower_bound(lo, keys_.end(), end);
            if (reached || lo == hi) {
                out.push_back(static_cast<std::uint32_t>(i));
            } else {
                frozen_.push_back({first, static_cast<std::uint32_t>(lo - keys_.begin()), static_cast<std::uint32_t>(hi - lo), false});
            }
        }
        return out;
    }

    const detail::BuildPlan& plan_;
    Reach reach_;
    std::vector<std::uint64_t> keys_;  // the earlier leaves', ascending
    std::vector<Run> frozen_;
};

// The output's runs in Morton order: the frozen runs and the fresh leaves (in Morton order already)
// merged, neighbouring fresh leaves joined into one run.
std::vector<Run> merge_runs(std::vector<Run> frozen, const std::vector<SdfBrick>& fresh) {
    std::sort(frozen.begin(), frozen.end(), [](const Run& a, const Run& b) { return a.key < b.key; });
    std::vector<Run> out;
    std::size_t f = 0;
    for (std::size_t j = 0; j <= fresh.size(); ++j) {
        const std::uint64_t key = j < fresh.size() ? lattice_key(fresh[j], 0) : ~std::uint64_t{0};
        for (; f < frozen.size() && frozen[f].key < key; ++f) out.push_back(frozen[f]);
        if (j == fresh.size()) break;
        if (!out.empty() && out.back().fresh && out.back().first + out.back().count == j)
            ++out.back().count;
        else
            out.push_back({key, static_cast<std::uint32_t>(j), 1, true});
    }
    return out;
}

// The earlier leaves and the fresh ones (part's arrays, fresh's records and lists) into out, run by
// run (segments: each run's first output leaf, first source leaf and whether it is fresh, then a
// sentinel); the earlier lists' indices moved down past the removed edits.
void splice(detail::BuildInputs& in, const GeometryBuild& before, const ocl::Buffer<SdfBrick>& fresh,
            const ocl::Buffer<cl_uint>& fresh_lists, const std::vector<cl_uint4>& segments,
            const std::vector<std::uint32_t>& removed, GeometryBuild& out, std::uint64_t entries) {
    ocl::Device& device_ = in.device;
    measure::Scheduler& scheduler = in.scheduler;
    if (!in.programs.splice) {
        ocl::Program p = ocl::build_program(device_, "brick_splice.cl");
        ocl::Kernel counts = ocl::make_kernel(p, "splice_counts"), leaves = ocl::make_kernel(p, "splice_leaves");
        in.programs.splice = std::make_unique<detail::BuildPrograms::Splice>(
            detail::BuildPrograms::Splice{std::move(p), std::move(counts), std::move(leaves)});
    }
    const auto& k = *in.programs.splice;
    const GeometryBuild& part = in.out;
    const std::uint64_t n = out.leaf_count;
    const std::size_t brick_bytes = in.settings.layout().brick_bytes();
    const ocl::Buffer<cl_uint4> runs(ocl::pooled, device_, std::span<const cl_uint4>(segments));
    const std::vector<cl_uint> removed_list(removed.begin(), removed.end());
    const ocl::Buffer<cl_uint> removed_d(ocl::pooled, device_, std::span<const cl_uint>(removed_list));
    ocl::Buffer<cl_uint> counts(ocl::pooled, device_, n + 1), offsets(ocl::pooled, device_, n + 1);
    const auto segment_count = static_cast<cl_uint>(segments.size() - 1);
    ocl::set_args(k.counts.get(), *before.leaves, fresh, runs, segment_count, static_cast<cl_uint>(n), counts);
    scheduler.launch(measure::Stage::splice, -1, k.counts.get(), detail::round_up(n, detail::kGroup1d), detail::kGroup1d);
    if (in.scan.exclusive(counts, offsets, n, scheduler, measure::Stage::splice, -1) != entries)
        throw std::logic_error("splice: the device's list entries differ from the host's records");
    out.leaves = std::make_unique<ocl::Buffer<SdfBrick>>(detail::allocate<SdfBrick>(device_, n, "the leaves"));
    out.leaf_edit_indices =
        std::make_unique<ocl::Buffer<cl_uint>>(detail::allocate<cl_uint>(device_, entries, "the leaves' edit lists"));
    out.pool = std::make_unique<ocl::Buffer<std::uint8_t>>(
        detail::allocate<std::uint8_t>(device_, n * brick_bytes, fmt::format("the brick pool ({} bricks)", n)));
    out.aabbs = std::make_unique<ocl::Buffer<SdfBounds>>(detail::allocate<SdfBounds>(device_, n, "the brick AABBs"));
    out.shifts = std::make_unique<ocl::Buffer<cl_uint>>(detail::allocate<cl_uint>(device_, n, "the brick shifts"));
    if (n == 0) return;
    ocl::set_args(k.leaves.get(), *before.leaves, fresh, *before.leaf_edit_indices, fresh_lists,
                  *before.pool, *part.pool, *before.aabbs, *part.aabbs, *before.shifts, *part.shifts, runs, segment_count,
                  offsets, removed_d, static_cast<cl_uint>(removed_list.size()), static_cast<cl_uint>(brick_bytes),
                  *out.leaves, *out.leaf_edit_indices, *out.pool, *out.aabbs, *out.shifts);
    scheduler.launch(measure::Stage::splice, -1, k.leaves.get(), n * detail::kGroup1d, detail::kGroup1d);
}

}  // namespace

std::optional<GeometryBuild> BrickBuilder::rebuild(const Geometry& g, const BuildSettings& s, const GeometryBuild& before,
                                                   std::vector<SdfBrick>& records, const EditChange& change,
                                                   measure::Scheduler& scheduler, const std::vector<SdfEdit>* prepared) {
    const auto wall_start = std::chrono::steady_clock::now();
    s.validate(device_.info());
    const Aabb box = bounds(g);
    if (!confinable(s, change) || box.empty() || g.edits.size() > SDF_MAX_EDITS || records.size() != before.leaf_count)
        return std::nullopt;
    const detail::BuildPlan plan = detail::plan_build(g, box, s);
    if (!same_frame(plan, before, s)) return std::nullopt;

    GeometryBuild part;  // the leaves built again
    part.name = g.name;
    part.first_launch = scheduler.size();
    part.leaf_size = before.leaf_size;
    detail::BuildInputs in(device_, *programs_, scan_, g, s, plan, scheduler, part, prepared);
    Confinement confinement(plan, records, change);
    const detail::Region region = confinement.region();
    detail::Levels levels(in, nullptr, nullptr, &region);
    levels.start();
    const std::uint64_t fresh_count = levels.run() ? levels.parent_count() : 0;
    const ocl::Buffer<SdfBrick>& fresh = *levels.level_bricks().back();
    detail::LeafEvaluation(in).evaluate(fresh, levels.lists(), fresh_count, levels.bytes);
    const std::vector<SdfBrick> fresh_records = fresh_count ? fresh.read() : std::vector<SdfBrick>{};
    const std::vector<Run> runs = merge_runs(std::move(confinement.frozen()), fresh_records);

    GeometryBuild out;
    static_cast<GeometryBuildInfo&>(out) = before.info();
    out.name = g.name;
    out.first_launch = part.first_launch;
    // The new records on the host, and the runs as the kernels read them (+ a sentinel).
    std::vector<SdfBrick> merged;
    std::vector<cl_uint4> segments;
    for (const Run& r : runs) {
        segments.push_back({{static_cast<cl_uint>(merged.size()), r.first, r.fresh ? 1u : 0u, 0u}});
        const SdfBrick* from = (r.fresh ? fresh_records.data() : records.data()) + r.first;
        merged.insert(merged.end(), from, from + r.count);
    }
    out.leaf_count = merged.size();
    segments.push_back({{static_cast<cl_uint>(merged.size()), 0u, 0u, 0u}});
    std::uint64_t entries = 0;
    for (SdfBrick& b : merged) {
        b.edit_offset = static_cast<sdf_u32>(entries);
        entries += b.edit_count;
    }
    splice(in, before, fresh, levels.lists(), segments, change.removed, out, entries);
    device_.finish();
    scheduler.resolve();
    out.end_launch = scheduler.size();
    out.device_ms = scheduler.total_ms(out.first_launch);
    out.leaves_built = fresh_count;
    out.host_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - wall_start).count();
    records = std::move(merged);
    return out;
}

}  // namespace sdfbrick::construct
