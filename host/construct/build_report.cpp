#include "construct/build_parts.h"

#include <algorithm>

#include "cl/launch.h"
#include "construct/work.h"

namespace sdfbrick::construct::detail {

// The report's counters of the records and lists, reduced on the device (kernels/brick_stats.cl):
// every level's and the leaves' partials land in one buffer that one read brings back.
BuildReport::Counters BuildReport::count_on_device(const ocl::Buffer<SdfBrick>& leaves,
                                                   const ocl::Buffer<cl_uint>& lists, std::uint64_t leaf_count) {
    static constexpr std::size_t kGroup = 64, kGroups = 64;  // STATS_GROUP; work-groups per reduction at most
    const auto groups = [](std::uint64_t n) { return std::min<std::size_t>((n + kGroup - 1) / kGroup, kGroups); };
    const std::size_t levels = levels_.level_bricks().size(), leaf_base = 2 * kGroups * levels;
    const BuildPrograms::Stats& k = in_.programs.stats(in_.device, in_.settings.layout());
    // Adaptive builds: the evaluation's work is counted over the records it read (leaves whose
    // samples the check evaluated have no edits there), the lists' over the leaves.
    const ocl::Buffer<SdfBrick>* evaluated = adaptive_ ? &adaptive_->evaluated() : nullptr;
    const std::size_t evaluated_base = leaf_base + 5 * kGroups;
    ocl::Buffer<cl_ulong> partial(ocl::pooled, in_.device, evaluated_base + 5 * kGroups);
    Counters c;
    c.records.resize(levels);
    std::vector<std::size_t> launched(levels, 0);
    for (std::size_t l = 0; l < levels; ++l) {
        c.records[l] = levels_.level_bricks()[l] ? levels_.level_bricks()[l]->size() : 0;
        if (c.records[l] == 0) continue;
        launched[l] = groups(c.records[l]);
        ocl::set_args(k.level.get(), *levels_.level_bricks()[l], static_cast<cl_uint>(c.records[l]), partial,
                      static_cast<cl_uint>(2 * kGroups * l));
        ocl::enqueue(in_.device, k.level.get(), "level_stats", launched[l] * kGroup, kGroup);
    }
    const std::size_t leaf_groups = leaf_count > 0 ? groups(leaf_count) : 0;
    if (leaf_groups > 0) {
        std::vector<cl_uint> flops(in_.edits_host.size());
        for (std::size_t i = 0; i < flops.size(); ++i) flops[i] = static_cast<cl_uint>(edit_flops(in_.edits_host[i]));
        const ocl::Buffer<cl_uint> flops_d(ocl::pooled, in_.device, std::span<const cl_uint>(flops));
        for (const ocl::Buffer<SdfBrick>* records : {&leaves, evaluated}) {
            if (!records) continue;
            ocl::set_args(k.leaf.get(), *records, static_cast<cl_uint>(leaf_count), lists, flops_d,
                          evaluation_.owned() ? *evaluation_.owned() : in_.empty_uints,
                          static_cast<cl_uint>(evaluation_.owned() ? 1 : 0), partial,
                          static_cast<cl_uint>(records == &leaves ? leaf_base : evaluated_base));
            ocl::enqueue(in_.device, k.leaf.get(), "leaf_stats", leaf_groups * kGroup, kGroup);
        }
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
        const cl_ulong* e = &p[(evaluated ? evaluated_base : leaf_base) + 5 * g];
        c.entries += v[0];
        c.longest_leaf = std::max<std::uint64_t>(c.longest_leaf, v[1]);
        c.entry_flops += v[2];
        c.flops += e[3];
        c.evaluations += e[4];
    }
    return c;
}

// Bricks, list lengths, work and times per level, from the counters reduced on the device (not part
// of device time).
void BuildReport::fill(const ocl::Buffer<SdfBrick>& leaves, const ocl::Buffer<cl_uint>& lists,
                       std::uint64_t leaf_count) {
    const Counters c = count_on_device(leaves, lists, leaf_count);
    std::uint64_t evaluations = 0;
    std::uint64_t prev_entries = in_.edits_host.size();  // the pseudo-parent's list
    std::uint64_t prev_records = 1, prev_tests = 0;
    for (std::size_t l = 0; l < levels_.level_bricks().size(); ++l) {
        // Adaptive builds keep only the parents of each level here (the finest level: none).
        const std::uint64_t records = c.records[l];
        LevelReport r;
        r.level = static_cast<int>(l);
        r.cell_size = in_.plan.domain.cell_size(r.level);
        r.bricks = l < levels_.kept().size() ? levels_.kept()[l] : records;
        r.leaves = in_.settings.adaptive() ? 0 : (r.level == in_.plan.finest() ? r.bricks : 0);
        if (adaptive_) r.leaves = adaptive_->leaves_of(r.level);
        r.edit_entries = l < levels_.list_entries().size() ? levels_.list_entries()[l] : 0;
        r.max_edits = static_cast<std::uint32_t>(c.longest[l]);
        const std::uint64_t counted =
            prev_entries * (l == 0 ? 1 : in_.plan.per_parent);  // every candidate child of every parent
        add_work(measure::Stage::count, counted,
                 prev_records * (sizeof(SdfBrick) + sizeof(cl_uint)) + prev_entries * kEntryBytes);
        std::uint64_t culled = 0;
        if (in_.settings.cull) {  // cull: each kept child tests its parent's list
            culled = l == 0 ? in_.edits_host.size() * records : prev_tests;
            add_work(measure::Stage::cull, culled,
                     records * sizeof(SdfBrick) + culled * kEntryBytes + r.edit_entries * sizeof(cl_uint));
        }
        evaluations += counted + culled;
        r.count_ms = in_.scheduler.stage_ms(measure::Stage::count, r.level, in_.out.first_launch);
        r.scan_ms = in_.scheduler.stage_ms(measure::Stage::scan, r.level, in_.out.first_launch);
        r.subdivide_ms = in_.scheduler.stage_ms(measure::Stage::subdivide, r.level, in_.out.first_launch);
        r.cull_ms = in_.scheduler.stage_ms(measure::Stage::cull, r.level, in_.out.first_launch);
        in_.out.level_reports.push_back(r);
        prev_entries = l < levels_.parent_entries().size() ? levels_.parent_entries()[l] : 0;
        prev_records = records;
        prev_tests = c.tests[l];
    }
    if (leaf_count > 0 && in_.settings.adaptive()) {
        in_.out.edits_per_leaf_mean = static_cast<double>(c.entries) / static_cast<double>(leaf_count);
        in_.out.edits_per_leaf_max = static_cast<std::uint32_t>(c.longest_leaf);
        // The maximum and the 99th percentile by selection, not a sort, in the capture's wall time:
        // drops at 0.03125 (E = 0.001) has 52,204 checked leaves, and on this project's 2-core
        // machine sorting 60,000 errors took 4.6 ms, selecting the 99th percentile 0.15.
        AdaptiveLeaves::CheckedLeaves checked = adaptive_->check_errors();
        for (LevelReport& r : in_.out.level_reports)
            if (const auto it = checked.planes.find(r.level); it != checked.planes.end()) r.plane_leaves = it->second;
        std::vector<double>& errors = checked.errors;
        if (!errors.empty()) {
            const std::size_t at = std::min(errors.size() - 1, errors.size() * 99 / 100);
            const auto p99 = errors.begin() + static_cast<std::ptrdiff_t>(at);
            std::nth_element(errors.begin(), p99, errors.end());
            in_.out.check_error_p99 = *p99;
            in_.out.check_error_max = *std::max_element(p99, errors.end());
        } else {
            in_.out.check_error_max = in_.out.check_error_p99 = 0.0;
        }
    } else if (leaf_count > 0) {
        const LevelReport& leaf = in_.out.level_reports.back();
        in_.out.edits_per_leaf_mean = static_cast<double>(leaf.edit_entries) / static_cast<double>(leaf_count);
        in_.out.edits_per_leaf_max = leaf.max_edits;
    }
    report_flops(leaf_count, c);
    in_.out.edit_evaluations = evaluations + in_.out.work[measure::Stage::evaluate].evaluations;
    in_.out.memory["brick pool"] = in_.out.pool->bytes();
    in_.out.memory["brick records"] = levels_.bytes.bricks;
    in_.out.memory["aabbs"] = in_.out.aabbs->bytes();
    in_.out.memory["edit lists"] = levels_.bytes.lists;
    in_.out.memory["edits"] = in_.edits.bytes();
    in_.out.memory["prepared edits"] = in_.prepared_edits.bytes() + in_.edit_reaches.bytes();
    if (in_.meshes.size() > 1) in_.out.memory["mesh grids"] = in_.meshes.bytes();  // one float: no mesh
    in_.out.memory["scratch"] = levels_.bytes.scratch;
}

// Evaluate's work from the leaves' lists and owned samples, and the FLOPs of count and cull from the
// mean FLOPs of a leaf list entry.
void BuildReport::report_flops(std::uint64_t leaf_count, const Counters& c) {
    const BrickLayout layout = in_.settings.layout();
    add_work(measure::Stage::evaluate, c.evaluations,
             leaf_count * (sizeof(SdfBrick) + sizeof(cl_uint) + layout.brick_bytes()) + c.entries * kEntryBytes);
    const double mean = c.entries > 0 ? static_cast<double>(c.entry_flops) / static_cast<double>(c.entries) : 0.0;
    for (auto& [stage, w] : in_.out.work) w.flop = static_cast<double>(w.evaluations) * mean;
    in_.out.work[measure::Stage::evaluate].flop = static_cast<double>(c.flops);
}

void BuildReport::add_work(measure::Stage stage, std::uint64_t evaluations, std::uint64_t bytes) {
    StageWork& w = in_.out.work[stage];
    w.evaluations += evaluations;
    w.bytes += static_cast<double>(bytes);
}

}  // namespace sdfbrick::construct::detail
