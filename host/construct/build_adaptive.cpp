#include "construct/build_parts.h"

#include <algorithm>
#include <cmath>

#include "cl/launch.h"

namespace sdfbrick::construct::detail {

namespace {
// A brick's samples as 32-bit words (S^3 is a multiple of 4 for S = 8 and 10, in every format).
cl_uint brick_words(const BrickLayout& layout) { return static_cast<cl_uint>(layout.brick_bytes() / 4); }
}  // namespace

// brick_check's work-group and staged chunk for a level of n candidates. The work-group changes no
// bit: on GPUs 128 work-items, which fold a class's points with more of them at once. On the H200
// (docs/measurements/roof/d11) engraved_slab's check took 1.19 ms with 128 against 1.43 with the
// evaluation's tuned 64, and no hard case was slower; 256 was slower on five of the six scenes. On
// CPUs, where a core runs a work-group's items one after another, 8: PoCL here
// (docs/measurements/adaptive/c3/cg.txt) ran brick_check 3-20% faster than with the evaluation's tuned
// 32 on every hard case, board and drops. A level with few candidates takes twice the work-items a
// brick (fills_few_waves). The chunk: the evaluation's, or as much as the device's local memory holds
// beside the check's own arrays (about 22 KB for 8^3 samples, 28 KB for 10^3) and the work-group's
// worst errors. The fold is in list order whatever the chunk: no bit depends on it.
AdaptiveLeaves::CheckShape AdaptiveLeaves::check_shape(const ocl::Kernel& kernel, std::uint64_t n) const {
    constexpr std::size_t kCpuGroup = 8;
    const BrickLayout layout = in_.settings.layout();
    const std::size_t limit = ocl::kernel_work_group_limit(in_.device, kernel.get(), "brick_check");
    CheckShape s;
    s.group = in_.device.info().type == "gpu" ? std::min<std::size_t>(128, limit)
                                              : std::min<std::size_t>(kCpuGroup, layout.samples_per_brick());
    const std::uint64_t own_local = ocl::kernel_local_bytes(in_.device, kernel.get(), "brick_check");
    const auto chunk_for = [&](std::size_t g) {
        return staged_chunk(static_cast<std::size_t>(in_.settings.chunk), in_.device.info().local_mem_bytes,
                            own_local + g * sizeof(float), sizeof(SdfPrepared));
    };
    s.chunk = chunk_for(s.group);
    if (s.chunk > 0 && s.group * 2 <= limit && chunk_for(s.group * 2) > 0 &&
        fills_few_waves(in_.device, kernel.get(), s.group * sizeof(float) + s.chunk * sizeof(SdfPrepared), s.group,
                        n)) {
        s.group *= 2;
        s.chunk = chunk_for(s.group);
    }
    if (s.chunk == 0)
        throw SettingError("samples", fmt::format("the adaptive check of {}^3 samples needs more local memory than {} "
                                                  "has ({} bytes): use 8 samples or a uniform build",
                                                  layout.samples, in_.device.info().name,
                                                  in_.device.info().local_mem_bytes));
    return s;
}

// What the check of one level reads. Where culling again pays (long lists on CPUs), the bricks' lists
// are culled for their children first, and the count reads the shorter lists (engraved_slab, PoCL, 2
// cores: count 63.3 -> 35.1 ms against 29.9 uniform); the check and the leaves keep the records and
// lists they had. At the last checked level, the children each brick has among the finest bricks: the
// finest level's count runs before the check, over every brick, on a copy that the parents are taken
// from (so the next count only adds up their masks).
AdaptiveLeaves::Candidates AdaptiveLeaves::candidates(int level, Levels& levels, float window) const {
    const std::uint64_t n = levels.parent_count();
    Candidates c(levels);
    c.last = level + 1 == in_.plan.finest();
    if (c.last && in_.settings.cull && levels.recull_pays(level)) {
        c.own_records.emplace(allocate<SdfBrick>(in_.device, n, "the checked bricks' records"));
        c.own_records->copy_from(levels.parents());
        c.own_lists = levels.recull(level);
    }
    // With hard edits only, clamping commutes with min and max: F_C clamped to +-window is F_{C_l}
    // clamped to it, bit for bit, wherever C >= window. So where the lists were culled again for C,
    // the check's points fold those shorter lists with C (the samples keep the bricks' own lists).
    c.short_folds = c.own_lists && in_.plan.hard && in_.plan.clamp_c >= window &&
                    in_.plan.clamp_c >= 0.5f * in_.plan.tolerance;
    c.fold_clamp = c.short_folds ? in_.plan.clamp_c : in_.plan.level_clamp[level];
    if (c.last) {
        c.counted.emplace(allocate<SdfBrick>(in_.device, n, "the counted bricks"));
        c.children.emplace(allocate<cl_uint>(in_.device, n, "the checked bricks' child counts"));
        c.counted->copy_from(levels.parents());
        levels.count_children(level, *c.counted, *c.children);
    }
    return c;
}

// The check of one level coarser than the finest (brick_check.cl), then the split of its bricks
// into leaves and parents by the scan of the results (brick_split).
std::uint64_t AdaptiveLeaves::check_and_split(int level, Levels& levels) {
    const std::uint64_t n = levels.parent_count();
    const BrickLayout layout = in_.settings.layout();
    const ocl::Program program = ocl::build_program(
        in_.device, "brick_check.cl",
        fmt::format("{} -DSDF_LANES={}", layout.defines(), in_.settings.lanes(in_.device.info())));
    const ocl::Kernel kernel = ocl::make_kernel(program, "brick_check");
    const CheckShape shape = check_shape(kernel, n);
    LevelLeaves out{level,
                    0,
                    nullptr,
                    allocate<float>(in_.device, n, "the check errors"),
                    allocate<cl_uint>(in_.device, n, "the check results"),
                    nullptr,
                    nullptr};
    const float band = std::ldexp(in_.plan.band, in_.plan.shift(level));
    const auto voxel = static_cast<float>(std::ldexp(in_.plan.voxel, in_.plan.shift(level)));
    // Errors count within one voxel of this level of the surface (at least the finest band): every
    // surface point then has check points on both sides within the window.
    const float window = std::max(in_.plan.band, voxel);
    Candidates c = candidates(level, levels, window);
    // A brick with fewer than two children among the finest bricks fails unchecked: as a leaf it would
    // stand for one finest brick or none (its band reaches past its cell), which saves nothing. Those
    // and the bricks that reach a thin edit fail first, and their copies in `masked` have no edits;
    // the others' samples come from the evaluation, which the check compares with the field.
    const cl_uint min_children = c.last ? 2u : 0u;
    ocl::Buffer<SdfBrick> masked = allocate<SdfBrick>(in_.device, n, "the checked bricks");
    const ocl::Kernel thin = ocl::make_kernel(program, "brick_thin");
    // A brick whose field is a plane over its samples passes with half a quantisation step and the
    // rounding as its error, where that cannot fail it (brick_thin).
    const float dequant = layout.dequantise_scale(band);
    ocl::set_args(thin.get(), in_.edits, in_.meshes, c.lists(), c.bricks(), in_.origin.x, in_.origin.y,
                  in_.origin.z, voxel, window, static_cast<float>(in_.plan.domain.cell_size(level)),
                  in_.plan.cull_radius(level), c.children ? *c.children : in_.empty_uints, min_children,
                  dequant, band, in_.plan.tolerance, masked, out.passed, out.errors);
    // A CPU core runs a work-group's items one after another, mostly idle on short lists: 16 of them
    // there (PoCL here: brick_thin 0.40 -> 0.18 ms a build on board, 2.0 -> 1.6 on engraved_slab).
    // The result is an or over the list: no bit depends on the size.
    const std::size_t thin_group = in_.device.info().type == "gpu" ? kGroup1d : 16;
    in_.scheduler.launch(measure::Stage::check, level, thin.get(), n * thin_group, thin_group);
    ocl::Buffer<std::uint8_t> samples = allocate<std::uint8_t>(in_.device, n * layout.brick_bytes(), "the checked samples");
    evaluate_samples(in_, masked, c.lists(), n, nullptr, samples, measure::Stage::check, level);
    ocl::set_args(kernel.get(), in_.prepared_edits, in_.meshes, c.fold_lists(), c.fold_bricks(), samples,
                  in_.origin.x, in_.origin.y, in_.origin.z, voxel, c.fold_clamp, band, dequant, in_.plan.tolerance,
                  window, out.errors, out.passed, ocl::LocalMemory{shape.group * sizeof(float)},
                  ocl::LocalMemory{shape.chunk * sizeof(SdfPrepared)}, static_cast<cl_uint>(shape.chunk));
    in_.scheduler.launch(measure::Stage::check, level, kernel.get(), n * shape.group, shape.group);
    const auto bytes_of = [](const auto& buffer) -> std::uint64_t { return buffer ? buffer->bytes() : 0; };
    const std::uint64_t scratch = samples.bytes() + masked.bytes() + bytes_of(c.counted) + bytes_of(c.children) +
                                  bytes_of(c.own_records);
    split(levels, out, c, samples);
    levels.bytes.scratch = std::max<std::uint64_t>(levels.bytes.scratch, scratch + kept_bytes_);
    if (c.own_lists) out.lists = std::move(c.own_lists);
    checked_.push_back(std::move(out));
    return n - checked_.back().count;
}

// The scan of the check's results, the split of the candidates into this level's leaves and the next
// level's parents, and the leaves' samples kept (the leaf evaluation puts them instead of evaluating
// them).
void AdaptiveLeaves::split(Levels& levels, LevelLeaves& out, const Candidates& c,
                           const ocl::Buffer<std::uint8_t>& samples) {
    const std::uint64_t n = levels.parent_count();
    const int level = out.level;
    ocl::Buffer<cl_uint>& offsets = levels.offsets(n, "the leaf offsets");
    out.count = in_.scan.exclusive(out.passed, offsets, n, in_.scheduler, measure::Stage::check, level);
    out.leaves = std::make_unique<ocl::Buffer<SdfBrick>>(
        allocate<SdfBrick>(in_.device, out.count, fmt::format("the leaves of level {}", level)));
    auto parents = std::make_unique<ocl::Buffer<SdfBrick>>(
        allocate<SdfBrick>(in_.device, n - out.count, fmt::format("the parents of level {}", level + 1)));
    const auto& k = in_.programs;
    ocl::set_args(k.split_k.get(), c.bricks(), c.counted ? *c.counted : c.bricks(), static_cast<cl_uint>(n),
                  out.passed, offsets, *out.leaves, *parents);
    in_.scheduler.launch(measure::Stage::check, level, k.split_k.get(), round_up(n, kGroup1d), kGroup1d);
    if (out.count > 0) {
        const BrickLayout layout = in_.settings.layout();
        out.samples = std::make_unique<ocl::Buffer<std::uint8_t>>(allocate<std::uint8_t>(
            in_.device, out.count * layout.brick_bytes(), fmt::format("the samples of the leaves of level {}", level)));
        ocl::set_args(k.keep_k.get(), samples, out.passed, offsets, static_cast<cl_uint>(n), brick_words(layout),
                      *out.samples);
        in_.scheduler.launch(measure::Stage::check, level, k.keep_k.get(), n * kGroup1d, kGroup1d);
        kept_bytes_ += out.samples->bytes();
    }
    levels.bytes.bricks += out.leaves->bytes() + parents->bytes();
    levels.set_parents(std::move(parents));
    if (c.last) levels.parents_counted();
}

std::uint64_t AdaptiveLeaves::assemble(Levels& levels) {
    std::vector<cl_uint> first{0}, list_base(static_cast<std::size_t>(in_.plan.domain.levels), 0);
    std::uint64_t entries = levels.lists().size();
    for (const LevelLeaves& l : checked_) {
        first.push_back(static_cast<cl_uint>(first.back() + l.count));
        if (l.lists) entries += l.lists->size();
    }
    const std::uint64_t total = first.back();
    ocl::Buffer<SdfBrick> all = allocate<SdfBrick>(in_.device, total, "the leaves of every level");
    ocl::Buffer<cl_uint> lists = allocate<cl_uint>(in_.device, entries, "the edit lists of every level");
    std::uint64_t at = 0;
    for (const LevelLeaves& l : checked_) {
        all.copy_from(l.leaves ? *l.leaves : *levels.level_bricks().back(), first[&l - checked_.data()]);
        list_base[l.level] = static_cast<cl_uint>(l.lists ? at : entries - levels.lists().size());
        if (l.lists) lists.copy_from(*l.lists, at);
        at += l.lists ? l.lists->size() : 0;
    }
    lists.copy_from(levels.lists(), at);
    const ocl::Buffer<cl_uint> first_d(in_.device, std::span<const cl_uint>(first), CL_MEM_READ_ONLY);
    const ocl::Buffer<cl_uint> base_d(in_.device, std::span<const cl_uint>(list_base), CL_MEM_READ_ONLY);
    positions_ = std::make_unique<ocl::Buffer<cl_uint>>(allocate<cl_uint>(in_.device, total, "the leaf positions"));
    ocl::Buffer<cl_uint>& positions = *positions_;
    merged_ = std::make_unique<ocl::Buffer<SdfBrick>>(allocate<SdfBrick>(in_.device, total, "the leaves"));
    evaluated_ = std::make_unique<ocl::Buffer<SdfBrick>>(allocate<SdfBrick>(in_.device, total, "the leaves evaluated"));
    first_ = first;
    const auto& k = in_.programs;
    const auto count = static_cast<cl_uint>(total);
    ocl::Buffer<cl_ulong> keys = allocate<cl_ulong>(in_.device, total, "the leaf keys");
    ocl::set_args(k.keys_k.get(), all, count, static_cast<cl_uint>(in_.plan.finest()), in_.plan.log2b, keys);
    in_.scheduler.launch(measure::Stage::order, -1, k.keys_k.get(), round_up(total, kGroup1d), kGroup1d);
    ocl::set_args(k.rank_k.get(), keys, first_d, static_cast<cl_uint>(checked_.size()), count, positions);
    in_.scheduler.launch(measure::Stage::order, -1, k.rank_k.get(), round_up(total, kGroup1d), kGroup1d);
    ocl::set_args(k.place_k.get(), all, positions, count, base_d, static_cast<cl_uint>(in_.plan.finest()), *merged_,
                  *evaluated_);
    in_.scheduler.launch(measure::Stage::order, -1, k.place_k.get(), round_up(total, kGroup1d), kGroup1d);
    levels.bytes.lists += lists.bytes();
    levels.set_lists(std::make_unique<ocl::Buffer<cl_uint>>(std::move(lists)));
    return total;
}

void AdaptiveLeaves::put_samples(ocl::Buffer<std::uint8_t>& pool) const {
    const BrickLayout layout = in_.settings.layout();
    for (std::size_t i = 0; i < checked_.size(); ++i) {
        const LevelLeaves& l = checked_[i];
        if (!l.samples) continue;
        ocl::set_args(in_.programs.put_k.get(), *l.samples, *positions_, first_[i], static_cast<cl_uint>(l.count),
                      brick_words(layout), pool);
        in_.scheduler.launch(measure::Stage::evaluate, l.level, in_.programs.put_k.get(), l.count * kGroup1d, kGroup1d);
    }
}

void AdaptiveLeaves::keep_lists(int level, std::unique_ptr<ocl::Buffer<cl_uint>> lists) {
    if (!checked_.empty() && checked_.back().level == level && !checked_.back().lists)
        checked_.back().lists = std::move(lists);
}

void AdaptiveLeaves::add_finest(std::uint64_t count) {
    checked_.push_back({in_.plan.finest(), count, nullptr, ocl::Buffer<float>(in_.device, 0),
                        ocl::Buffer<cl_uint>(in_.device, 0), nullptr, nullptr});
}

std::uint64_t AdaptiveLeaves::leaves_of(int level) const {
    for (const LevelLeaves& l : checked_)
        if (l.level == level) return l.count;
    return 0;
}

AdaptiveLeaves::CheckedLeaves AdaptiveLeaves::check_errors() const {
    CheckedLeaves out;
    for (const LevelLeaves& l : checked_) {
        const std::vector<float> errors = l.errors.read();
        const std::vector<cl_uint> passed = l.passed.read();
        for (std::size_t i = 0; i < errors.size(); ++i) {
            if (!passed[i]) continue;
            out.errors.push_back(std::abs(errors[i]));  // negative: passed as a plane (brick_thin)
            if (errors[i] < 0.0f) ++out.planes[l.level];
        }
    }
    return out;
}

}  // namespace sdfbrick::construct::detail
