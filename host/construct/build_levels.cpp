#include "construct/build_parts.h"

#include <algorithm>
#include <numeric>
#include <span>
#include <stdexcept>

#include "cl/host_memory.h"
#include "cl/launch.h"

namespace sdfbrick::construct::detail {

namespace {
constexpr std::uint64_t kMaxChunkWords = 8;  // words of a list cull_mark_siblings stages at once
}  // namespace

Levels::Levels(BuildInputs& in, const Subtrees* subtrees, AdaptiveLeaves* adaptive, const Region* region)
    : in_(in),
      subtrees_(subtrees),
      adaptive_(adaptive),
      region_(region),
      counts_(ocl::pooled, in.device, 0),
      offsets_(ocl::pooled, in.device, 0),
      words_(ocl::pooled, in.device, 0),
      bits_(ocl::pooled, in.device, 0),
      sources_(ocl::pooled, in.device, 0),
      kept_words_(ocl::pooled, in.device, 0),
      split_words_(ocl::pooled, in.device, 0),
      sibling_groups_(ocl::pooled, in.device, 0) {}

// The root's list (every edit, ascending), the pseudo-parent of level 0, the dependencies.
void Levels::start() {
    std::vector<cl_uint> all(in_.edits_host.size());
    std::iota(all.begin(), all.end(), 0u);
    pseudo_.level = 0xffffffffu;
    pseudo_.edit_offset = 0;
    pseudo_.edit_count = static_cast<sdf_u32>(all.size());
    parents_ = std::make_unique<ocl::Buffer<SdfBrick>>(ocl::pooled, in_.device, std::span<const SdfBrick>(&pseudo_, 1));
    parent_lists_ = std::make_unique<ocl::Buffer<cl_uint>>(ocl::pooled, in_.device, std::span<const cl_uint>(all));
    bytes.lists = parent_lists_->bytes();
    if (in_.settings.cull && in_.settings.dependencies) {
        if (!in_.programs.dependencies)
            in_.programs.dependencies = std::make_unique<DependencyBuilder>(in_.device, in_.scan);
        deps_ = in_.programs.dependencies->compute(in_.edits, in_.edits_host.size(), in_.scheduler);
        in_.out.dependency_entries = deps_->total;
        in_.out.memory["dependency lists"] = deps_->bytes();
    }
}

bool Levels::run() {
    for (int level = 0; level < in_.plan.domain.levels; ++level) {
        std::uint64_t children = count_and_scan(level);
        subdivide(level, children);
        cull(level, children);
        if (subtrees_ && subtrees_->splits_at(level, children, in_.plan.coarsest_leaf)) {
            children = keep_subtrees(children);
            subtrees_ = nullptr;
        }
        if (region_ && level < in_.plan.finest()) children = keep_region(level, children);
        bytes.scratch =
            std::max<std::uint64_t>(bytes.scratch, counts_.bytes() + offsets_.bytes() + words_.bytes() + bits_.bytes() +
                                                       sources_.bytes() + kept_words_.bytes() + split_words_.bytes() +
                                                       sibling_groups_.bytes());
        kept_.push_back(children);
        parent_count_ = children;
        if (adaptive_ && level >= in_.plan.coarsest_leaf && level < in_.plan.finest() && children > 0) {
            parent_count_ = adaptive_->check_and_split(level, *this);
            if (parent_count_ > 0 && in_.settings.cull && !reculled_ && recull_pays(level))
                adaptive_->keep_lists(level, recull(level));
            reculled_ = false;
        }
        if (parent_count_ == 0) break;
    }
    const bool complete =
        level_bricks_.size() + 1 == static_cast<std::size_t>(in_.plan.domain.levels) && parent_count_ > 0;
    level_bricks_.push_back(std::move(parents_));
    if (adaptive_ && complete) adaptive_->add_finest(parent_count_);  // unchecked: nothing is finer
    return complete;
}

// The count stage's work-groups: BuildSettings::count_parts work-items per child. Automatic: on GPUs
// as many as keep the level within resident_items (the top levels: long lists folded by few
// work-groups, bound by latency). A parent's children are split over count_splits work-groups;
// automatic: as few as hold the parts within the kernel's work-group limit, with their values in
// __local memory. Edits are staged in chunks of the parents' mean list, rounded up to 16, up to 256
// (fewer barriers) as local memory allows (a larger chunk than lists need costs occupancy). None of
// these changes a bit: the fold is in list order either way.
Levels::CountShape Levels::count_shape(std::size_t children, std::uint64_t mean_list) const {
    // A staged edit: its prepared form, its excess terms and fold parameters.
    constexpr std::size_t kStaged = sizeof(SdfPrepared) + 2 * sizeof(cl_float4), kMinChunk = 16, kMaxParts = 16;
    const std::size_t limit = ocl::kernel_work_group_limit(in_.device, in_.programs.count_k.get(), "brick_count");
    const std::uint64_t resident = resident_items(limit);
    CountShape shape;
    const auto per = [&] { return children / shape.splits; };
    const auto local = [&] { return in_.device.info().local_mem_bytes - per() * sizeof(cl_uint); };
    const auto values_fit = [&] { return shape.parts == 1 || kMinChunk * (kStaged + per() * sizeof(float)) <= local(); };
    if (in_.settings.count_splits > 0)
        shape.splits = std::min(static_cast<std::size_t>(in_.settings.count_splits), children);  // the root has one
    if (in_.settings.count_parts > 0) {
        shape.parts = static_cast<std::size_t>(in_.settings.count_parts);
    } else if (in_.device.info().type == "gpu") {
        // with the splits given, no more parts than their work-groups hold
        while (shape.parts * 2 <= kMaxParts && parent_count_ * children * shape.parts * 2 <= resident &&
               (in_.settings.count_splits == 0 || per() * shape.parts * 2 <= limit))
            shape.parts *= 2;
    }
    if (in_.settings.count_splits == 0) {
        while (per() * shape.parts > limit && shape.splits < children) shape.splits *= 2;
        // A CPU runs a work-group on one core: where a level has fewer parents than the device has
        // cores (the top levels), their children go to more work-groups, 4 children each at least.
        if (in_.device.info().type != "gpu")
            while (parent_count_ * shape.splits * 2 <= in_.device.info().compute_units && per() >= 8)
                shape.splits *= 2;
    }
    // A CPU folds a SIMD value of children per work-item where each child has one (the setting `lanes`).
    if (shape.parts == 1) shape.lanes = in_.settings.lanes(in_.device.info());
    if (per() * shape.parts > limit || !values_fit())
        throw SettingError(in_.settings.count_parts > 0 ? "count_parts" : "count_splits",
                           fmt::format("count_parts {} with count_splits {} does not fit brick_count's work-group on "
                                       "{} ({} work-items, {} bytes of local memory)",
                                       shape.parts, shape.splits, in_.device.info().name, limit, local()));
    const std::size_t per_edit = kStaged + (shape.parts > 1 ? per() * sizeof(float) : 0);
    const std::size_t wanted =
        round_up(static_cast<std::size_t>(std::clamp<std::uint64_t>(mean_list, 1, 256)), kMinChunk);
    shape.chunk = std::min({wanted, std::size_t{256}, local() / per_edit});
    return shape;
}

// The list length from which the count of `level` keeps a parent's children untested.
std::uint32_t Levels::untested_from(int level) const {
    return detail::untested_from(level, in_.plan.saturation(level) > in_.plan.clamp_c, in_.plan.coarsest_leaf,
                                 in_.device.info().type == "gpu",
                                 static_cast<std::uint32_t>(in_.settings.count_untested));
}

void Levels::count(int level, ocl::Buffer<SdfBrick>& parents, ocl::Buffer<cl_uint>& counts) {
    const cl_uint lb = level_log2b(level);
    const std::size_t per_parent = std::size_t{1} << (3 * lb);
    const std::uint64_t entries = parent_entries_.empty() ? in_.edits_host.size() : parent_entries_.back();
    const CountShape shape =
        count_shape(per_parent, (entries + parent_count_ - 1) / std::max<std::size_t>(parent_count_, 1));
    const std::size_t per = per_parent / shape.splits, values = shape.parts > 1 ? shape.chunk * per : 1;
    const std::size_t split_words = shape.splits > 1 ? 3 * parent_count_ * shape.splits : 1;
    if (split_words_.size() < split_words) split_words_ = allocate<cl_uint>(in_.device, split_words, "the split counts");
    const auto& k = in_.programs;
    const ocl::Kernel& kernel = in_.programs.count_kernel(in_.device, shape.lanes);
    ocl::set_args(kernel.get(), in_.prepared_edits, in_.meshes, *parent_lists_, parents, lb, in_.origin.x, in_.origin.y,
                  in_.origin.z, cell(level), in_.plan.threshold(level), in_.plan.clamp_c, in_.plan.saturation(level),
                  in_.plan.reject_slack(), static_cast<float>(in_.plan.magnitude),
                  static_cast<cl_uint>(untested_from(level)), counts,
                  static_cast<cl_uint>(shape.splits), split_words_, ocl::LocalMemory{shape.chunk * sizeof(SdfPrepared)},
                  ocl::LocalMemory{shape.chunk * sizeof(cl_float4)}, ocl::LocalMemory{shape.chunk * sizeof(cl_float4)},
                  static_cast<cl_uint>(shape.chunk), ocl::LocalMemory{values * sizeof(float)},
                  ocl::LocalMemory{per * sizeof(cl_uint)});
    const std::size_t group = shape.lanes > 1 ? (per + shape.lanes - 1) / shape.lanes : per * shape.parts;
    in_.scheduler.launch(measure::Stage::count, level, kernel.get(), parent_count_ * shape.splits * group, group);
    if (shape.splits > 1) {
        ocl::set_args(k.count_merge_k.get(), parents, static_cast<cl_uint>(parent_count_),
                      static_cast<cl_uint>(shape.splits), split_words_, counts);
        in_.scheduler.launch(measure::Stage::count, level, k.count_merge_k.get(), round_up(parent_count_, kGroup1d),
                             kGroup1d);
    }
}

void Levels::count_children(int level, ocl::Buffer<SdfBrick>& bricks, ocl::Buffer<cl_uint>& counts) {
    count(level + 1, bricks, counts);
}

std::uint64_t Levels::count_and_scan(int level) {
    if (counts_.size() < parent_count_) counts_ = allocate<cl_uint>(in_.device, parent_count_, "the child counts");
    if (offsets_.size() < parent_count_) offsets_ = allocate<cl_uint>(in_.device, parent_count_, "the child offsets");
    if (parents_counted_) {
        ocl::set_args(in_.programs.mask_counts_k.get(), *parents_, static_cast<cl_uint>(parent_count_), counts_);
        in_.scheduler.launch(measure::Stage::count, level, in_.programs.mask_counts_k.get(),
                             round_up(parent_count_, kGroup1d), kGroup1d);
        parents_counted_ = false;
    } else {
        count(level, *parents_, counts_);
    }
    const std::uint64_t children =
        in_.scan.exclusive(counts_, offsets_, parent_count_, in_.scheduler, measure::Stage::scan, level);
    // Refuse early (not after minutes of work) a build whose pool cannot fit: a surface's brick count
    // grows about B^2 per level, so project the leaves from this level's count (generously).
    const int remaining = in_.plan.domain.levels - 1 - level;
    const double projected = static_cast<double>(children) * std::pow(double(in_.settings.branching), 2.0 * remaining);
    const double pool_projected = projected * double(in_.settings.layout().brick_bytes());
    if (pool_projected > 4.0 * static_cast<double>(in_.device.info().max_alloc_bytes))
        throw SettingError(
            "leaf_size",
            fmt::format(
                "leaf_size {} is too small for geometry \"{}\" on {}: level {} already has {} bricks, which "
                "projects to about {:.3g} leaf bricks and a brick pool of {:.3g} bytes; the device allocates at most "
                "{} bytes at once: use a larger leaf_size",
                in_.settings.leaf_size, in_.geometry.name, in_.device.info().name, level, children, projected,
                pool_projected, in_.device.info().max_alloc_bytes));
    check_host_projection(level, children, projected);
    return children;
}

void Levels::check_host_projection(int level, std::uint64_t children, double projected) const {
    if (in_.settings.host_bytes_per_leaf <= 0.0) return;
    const double host_projected = projected * in_.settings.host_bytes_per_leaf;
    const std::optional<std::uint64_t> available = ocl::host_memory_available();
    if (!available || host_projected <= static_cast<double>(*available)) return;
    throw SettingError(
        "leaf_size",
        fmt::format("leaf_size {} is too small for geometry \"{}\" on this host: level {} already has {} bricks, which "
                    "projects to about {:.3g} leaf bricks holding about {:.3g} bytes of host memory ({:.0f} per leaf); "
                    "{} bytes are available: use a larger leaf_size",
                    in_.settings.leaf_size, in_.geometry.name, level, children, projected, host_projected,
                    in_.settings.host_bytes_per_leaf, *available));
}

void Levels::subdivide(int level, std::uint64_t children) {
    auto bricks = std::make_unique<ocl::Buffer<SdfBrick>>(
        allocate<SdfBrick>(in_.device, children, fmt::format("level {} ({} bricks)", level, children)));
    bytes.bricks += bricks->bytes();
    if (children > 0) {
        const cl_uint lb = level_log2b(level);
        if (words_.size() < children) words_ = allocate<cl_uint>(in_.device, children, "the cull word counts");
        ocl::set_args(in_.programs.subdivide_k.get(), *parents_, static_cast<cl_uint>(parent_count_), lb, offsets_,
                      *bricks, words_);
        const std::size_t global = round_up(parent_count_ << (3 * lb), kGroup1d);
        in_.scheduler.launch(measure::Stage::subdivide, level, in_.programs.subdivide_k.get(), global, kGroup1d);
    }
    if (level > 0) level_bricks_.push_back(std::move(parents_));  // the parent level's masks are final now
    parents_ = std::move(bricks);
}

// Each child's edit list from its parent's; without culling every brick keeps the whole list.
void Levels::cull(int level, std::uint64_t children) {
    std::uint64_t entries = children * in_.edits_host.size();
    if (in_.settings.cull && children > 0) {
        std::unique_ptr<ocl::Buffer<cl_uint>> replaced =
            cull_lists(level, children, in_.plan.cull_saturation(level), true);
        if (adaptive_) adaptive_->keep_lists(level - 1, std::move(replaced));
        entries = parent_lists_->size();
    }
    list_entries_.push_back(entries);
    parent_entries_.push_back(entries);
}

// Culling a checked level's parents again pays where their lists are long and shrink by half or
// more, on CPU devices. The edits kept lie within saturation + radius of a brick's centre, so about
// the cube of the two saturations' ratio of them stays (a hard edit's saturation at a level is that
// level's band, 4x the next one's); the next level's count folds each parent's list for its 64
// children, one after the other on a CPU core. Short lists cost less to count than the re-cull's
// launches and its scans' host waits: grooved_board on PoCL (16 cores, lists of 3 edits) took 25-26
// ms against 23.6 with a re-cull at every checked level, and on the H200 every hard case was slower
// with it; engraved_slab's candidates of cell 0.25 (about 60 edits) gain from it (docs/construction.md).
bool Levels::recull_pays(int level) const {
    constexpr std::uint64_t kLongList = 32;
    if (in_.device.info().type == "gpu" || parent_entries_.back() < kLongList * parent_count_) return false;
    const double radius = in_.plan.cull_radius(level);
    const double ratio = (in_.plan.parent_saturation(level) + radius) / (in_.plan.cull_saturation(level) + radius);
    return ratio * ratio * ratio <= 0.5;
}

// The bricks of a checked level (all of them before the check, its parents after it): their lists
// were culled to hold for their own evaluation as leaves (a wider saturation); their children need
// less. Culled again, the next level's count and cull read shorter lists. The level's leaves keep
// the lists they were checked with (the ones returned).
std::unique_ptr<ocl::Buffer<cl_uint>> Levels::recull(int level) {
    ocl::set_args(in_.programs.words_k.get(), *parents_, static_cast<cl_uint>(parent_count_), words_);
    in_.scheduler.launch(measure::Stage::cull, level, in_.programs.words_k.get(), round_up(parent_count_, kGroup1d),
                         kGroup1d);
    std::unique_ptr<ocl::Buffer<cl_uint>> replaced =
        cull_lists(level, parent_count_, in_.plan.parent_saturation(level), false);
    parent_entries_.back() = parent_lists_->size();
    reculled_ = true;
    return replaced;
}

// What the device runs of a kernel at once, as the count and cull stages size their work: compute
// units times the kernel's work-group limit.
std::uint64_t Levels::resident_items(std::size_t work_group_limit) const {
    return std::uint64_t{in_.device.info().compute_units} * work_group_limit;
}

// The bits of the cull bit sets per work-item of cull_mark and cull_write (a power of two up to 32):
// the fewest that keep the work-items within resident_items. Changes no bit.
std::uint64_t Levels::bits_per_item(std::uint64_t words, cl_kernel kernel, std::string_view name) const {
    const std::uint64_t resident = resident_items(ocl::kernel_work_group_limit(in_.device, kernel, name));
    std::uint64_t span = 1;
    while (span < 32 && words * 32 / span > resident) span *= 2;
    return span;
}

std::unique_ptr<ocl::Buffer<cl_uint>> Levels::cull_lists(int level, std::uint64_t children, float saturation,
                                                         bool siblings) {
    const auto& k = in_.programs;
    const ocl::Buffer<SdfBrick>& bricks = *parents_;  // this level's bricks (subdivide moved them there)
    const ocl::Buffer<cl_uint>& parent_lists = *parent_lists_;
    const std::size_t global = round_up(children, kGroup1d);
    const auto n = static_cast<cl_uint>(children);
    const std::uint64_t total_words =
        in_.scan.exclusive(words_, words_, children, in_.scheduler, measure::Stage::cull, level);
    if (total_words > 0xffffffffu / 32)
        throw InputError(
            fmt::format("level {} inherits {} words of edit-list bits, more than one build handles "
                        "(2^27): use a larger brick size",
                        level, total_words));
    if (bits_.size() < total_words) bits_ = allocate<cl_uint>(in_.device, total_words, "the cull bit sets");
    if (sources_.size() < total_words) sources_ = allocate<cl_uint>(in_.device, total_words, "the cull word sources");
    if (total_words > 0) cull_mark(level, children, saturation, total_words, siblings);
    if (deps_) {
        ocl::set_args(k.dependencies_k.get(), in_.edits, parent_lists, bricks, n, words_, bits_, deps_->offsets,
                      deps_->indices);
        in_.scheduler.launch(measure::Stage::cull, level, k.dependencies_k.get(), global, kGroup1d);
    }
    if (kept_words_.size() < total_words + 1)
        kept_words_ = allocate<cl_uint>(in_.device, total_words + 1, "the cull kept counts");
    // Each word's output slot: the prefix sum of the kept entries per word (its bits), and their total.
    const std::uint64_t entries =
        in_.scan.exclusive_popcounts(bits_, kept_words_, total_words + 1, in_.scheduler, measure::Stage::cull, level);
    auto lists = std::make_unique<ocl::Buffer<cl_uint>>(
        allocate<cl_uint>(in_.device, entries, fmt::format("the edit lists of level {}", level)));
    // On GPUs at most 4 bits a work-item: 8 work-items write a word's entries side by side, where a
    // word a work-item left a warp's stores 32 lists apart (an H100: drops' cull 0.44 -> 0.34 ms,
    // sculpt_dense's 4.06 -> 3.63; a bit a work-item 0.46 and 4.66, 8 bits 0.37 and 3.68).
    constexpr std::uint64_t kGpuWriteSpan = 4;
    const std::uint64_t fill = bits_per_item(total_words, k.write_k.get(), "cull_write");
    const std::uint64_t span = in_.device.info().type == "gpu" ? std::min(fill, kGpuWriteSpan) : fill;
    ocl::set_args(k.write_k.get(), parent_lists, bricks, n, static_cast<cl_uint>(total_words),
                  static_cast<cl_uint>(span), words_, bits_, sources_, kept_words_, *lists);
    in_.scheduler.launch(measure::Stage::cull, level, k.write_k.get(),
                         round_up(std::max<std::uint64_t>(total_words * 32 / span, children), kGroup1d), kGroup1d);
    bytes.lists += lists->bytes();
    std::swap(parent_lists_, lists);
    return lists;
}

// Where a level has many parents (settings.cull_siblings per compute unit) with several new bricks
// each, and on GPUs lists of 256 edits or more on average, the parents' work-groups test them all
// against their lists, staged once (mark_siblings); elsewhere cull_mark spreads the words over the
// device: the top levels (few parents, whose long lists a work-group each would walk serially on a
// device left mostly idle), re-culls, and on GPUs short lists (as quick either way there). Both
// give the same bits.
void Levels::cull_mark(int level, std::uint64_t n, float saturation, std::uint64_t total_words, bool siblings) {
    constexpr std::uint64_t kMinSiblings = 8, kGpuMinWords = 8;
    const auto& k = in_.programs;
    const float radius = in_.plan.cull_radius(level);
    const std::size_t per_parent = std::size_t{1} << (3 * level_log2b(level));
    const std::uint64_t parents_from =
        static_cast<std::uint64_t>(in_.settings.cull_siblings) * in_.device.info().compute_units;
    const bool long_lists = in_.device.info().type != "gpu" || total_words >= kGpuMinWords * n;
    if (siblings && parents_from > 0 && parent_count_ >= parents_from && n >= kMinSiblings * parent_count_ &&
        long_lists && siblings_limit() >= per_parent) {
        // On CPUs a work-item tests a SIMD value of children (the setting `lanes`) for a word of the list.
        const auto lanes = static_cast<std::size_t>(in_.settings.lanes(in_.device.info()));
        mark_siblings(level, n, saturation, total_words, lanes,
                      lanes > 1 ? (per_parent + lanes - 1) / lanes * kMaxChunkWords : std::max(kGroup1d, per_parent));
        return;
    }
    const std::uint64_t span = bits_per_item(total_words, k.mark_k.get(), "cull_mark");
    ocl::set_args(k.mark_k.get(), in_.prepared_edits, in_.edit_reaches, in_.meshes, *parent_lists_, *parents_, static_cast<cl_uint>(n),
                  static_cast<cl_uint>(total_words), static_cast<cl_uint>(span), in_.origin.x, in_.origin.y, in_.origin.z,
                  cell(level), radius, saturation, static_cast<float>(in_.plan.magnitude), words_, bits_, sources_,
                  ocl::LocalMemory{kGroup1d * sizeof(cl_uint)});
    in_.scheduler.launch(measure::Stage::cull, level, k.mark_k.get(), round_up(total_words * 32 / span, kGroup1d),
                         kGroup1d);
}

std::size_t Levels::siblings_limit() const {
    return ocl::kernel_work_group_limit(in_.device, in_.programs.mark_siblings_k.get(), "cull_mark_siblings");
}

// cull_mark_siblings over this level's n new bricks: as many words a chunk as a parent's children and
// its list use on average (the local memory beyond them costs occupancy), and a share of words a
// work-group: the mean list split over as many work-groups as fill the device, a chunk at least. Each
// parent gets as many work-groups as its list holds shares (sibling_groups, then their scan), so that
// one parent's long list does not hold the level back.
void Levels::mark_siblings(int level, std::uint64_t n, float saturation, std::uint64_t total_words, std::size_t lanes,
                           std::size_t group) {
    constexpr std::uint64_t kMaxSplits = 64;
    const auto& k = in_.programs;
    const ocl::Kernel& kernel = in_.programs.siblings_kernel(in_.device, static_cast<int>(lanes));
    const std::uint64_t mean_words = (total_words + n - 1) / n, groups = parent_count_ * group;
    const std::uint64_t chunk_words =
        std::clamp<std::uint64_t>(std::min(group * lanes * parent_count_ / n, mean_words), 1, kMaxChunkWords);
    const std::uint64_t fill = (resident_items(siblings_limit()) + groups - 1) / groups;
    const std::uint64_t splits = std::clamp<std::uint64_t>(std::min(fill, mean_words / chunk_words), 1, kMaxSplits);
    const auto share = static_cast<cl_uint>(std::max(chunk_words, (mean_words + splits - 1) / splits));
    const auto parents = static_cast<cl_uint>(parent_count_);
    if (sibling_groups_.size() < parent_count_)
        sibling_groups_ = allocate<cl_uint>(in_.device, parent_count_, "the sibling cull's work-groups");
    ocl::set_args(k.sibling_groups_k.get(), *parents_, offsets_, counts_, parents, share, sibling_groups_);
    in_.scheduler.launch(measure::Stage::cull, level, k.sibling_groups_k.get(), round_up(parent_count_, kGroup1d),
                         kGroup1d);
    const std::uint64_t work_groups =
        in_.scan.exclusive(sibling_groups_, sibling_groups_, parent_count_, in_.scheduler, measure::Stage::cull, level);
    ocl::set_args(kernel.get(), in_.prepared_edits, in_.edit_reaches, in_.meshes, *parent_lists_, *parents_, offsets_, counts_,
                  in_.origin.x, in_.origin.y, in_.origin.z, cell(level),
                  in_.plan.cull_radius(level), saturation,
                  static_cast<float>(in_.plan.magnitude), words_, bits_, sources_,
                  ocl::LocalMemory{chunk_words * 32 * sizeof(SdfPrepared)},
                  ocl::LocalMemory{chunk_words * 32 * sizeof(cl_float)}, static_cast<cl_uint>(chunk_words),
                  sibling_groups_, parents, share);
    in_.scheduler.launch(measure::Stage::cull, level, kernel.get(), work_groups * group, group);
}

// Keeps the range of this level's bricks that subtrees_ picks; their lists stay where they are.
std::uint64_t Levels::keep_subtrees(std::uint64_t children) {
    const std::vector<SdfBrick> records = parents_->read();
    const auto [first, end] = subtrees_->pick(records);
    if (first > end || end > children)
        throw std::logic_error(fmt::format("subtrees: range [{}, {}) of {} bricks", first, end, children));
    parents_ = std::make_unique<ocl::Buffer<SdfBrick>>(ocl::pooled, in_.device,
                                                       std::span<const SdfBrick>(records).subspan(first, end - first));
    return end - first;
}

// Keeps the bricks of this level that the region goes on with; their lists stay where they are.
std::uint64_t Levels::keep_region(int level, std::uint64_t children) {
    if (children == 0) return 0;
    const std::vector<SdfBrick> records = parents_->read();
    std::vector<SdfBrick> kept;
    for (std::uint32_t i : region_->keep(level, records)) kept.push_back(records.at(i));
    parents_ = std::make_unique<ocl::Buffer<SdfBrick>>(ocl::pooled, in_.device, std::span<const SdfBrick>(kept));
    return kept.size();
}

ocl::Buffer<cl_uint>& Levels::offsets(std::size_t n, std::string_view what) {
    if (offsets_.size() < n) offsets_ = allocate<cl_uint>(in_.device, n, what);
    return offsets_;
}

}  // namespace sdfbrick::construct::detail
