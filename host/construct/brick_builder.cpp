#include "construct/brick_builder.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <bit>
#include <numeric>

#include <fmt/format.h>

#include "construct/edit_deps.h"
#include "cl/cl_error.h"
#include "cl/launch.h"
#include "core/errors.h"
#include "core/hash.h"
#include "construct/domain.h"
#include "scene/to_device.h"

namespace sdfbrick::construct {

std::string_view to_string(BrickFormat f) {
    switch (f) {
        case BrickFormat::int8: return "int8";
        case BrickFormat::int16: return "int16";
        case BrickFormat::float32: return "float";
    }
    return "?";
}

std::optional<BrickFormat> format_from_string(std::string_view s) {
    if (s == "int8") return BrickFormat::int8;
    if (s == "int16") return BrickFormat::int16;
    if (s == "float" || s == "float32") return BrickFormat::float32;
    return std::nullopt;
}

std::size_t sample_bytes(BrickFormat f) {
    return f == BrickFormat::int8 ? 1 : f == BrickFormat::int16 ? 2 : 4;
}

void BuildSettings::validate(const ocl::DeviceInfo& device) const {
    if (!(leaf_size > 0.0) || !std::isfinite(leaf_size))
        throw SettingError("leaf_size", fmt::format("leaf_size must be a positive number, got {}", leaf_size));
    if (branching != 2 && branching != 4)
        throw SettingError("branching", fmt::format("branching must be 2 or 4, got {}", branching));
    if (samples != 8 && samples != 10) throw SettingError("samples", fmt::format("samples must be 8 or 10, got {}", samples));
    if (levels < 0 || levels > 31)
        throw SettingError("levels", fmt::format("levels must lie in 1..31 (0 = automatic), got {}", levels));
    if (chunk < 16 || chunk > 256) throw SettingError("chunk", fmt::format("chunk must lie in 16..256, got {}", chunk));
    if (eval_group < 1 || eval_group > 1024 || (eval_group & (eval_group - 1)) != 0)
        throw SettingError("eval_group", fmt::format("eval_group must be a power of two in 1..1024, got {}", eval_group));
    if (static_cast<std::size_t>(eval_group) > device.max_work_group_size)
        throw SettingError("eval_group", fmt::format("eval_group {} is larger than the {} work-items per work-group {} "
                                                     "allows", eval_group, device.max_work_group_size, device.name));
    if (!(band_voxels > 0.0) || band_voxels > 64.0)
        throw SettingError("band_voxels", fmt::format("band_voxels must lie in (0, 64], got {}", band_voxels));
    if (!(guard >= 0.0) || guard > 64.0) throw SettingError("guard", fmt::format("guard must lie in [0, 64], got {}", guard));
    const std::uint64_t local = static_cast<std::uint64_t>(chunk) * sizeof(SdfEdit) + 64 * sizeof(cl_uint);
    if (local > device.local_mem_bytes)
        throw SettingError("chunk", fmt::format("chunk {} needs {} bytes of local memory; {} has {}", chunk, local,
                                                device.name, device.local_mem_bytes));
}

struct BrickBuilder::Programs {
    ocl::Program count, subdivide, cull, aabb;
    ocl::Kernel count_k, subdivide_k, words_k, mark_k, cull_count_k, write_k, aabb_k;
    std::unique_ptr<DependencyBuilder> dependencies;  // built on first use

    explicit Programs(ocl::Device& d)
        : count(ocl::build_program(d, "brick_count.cl")), subdivide(ocl::build_program(d, "brick_subdivide.cl")),
          cull(ocl::build_program(d, "brick_cull.cl")), aabb(ocl::build_program(d, "brick_aabb.cl")),
          count_k(ocl::make_kernel(count, "brick_count")), subdivide_k(ocl::make_kernel(subdivide, "brick_subdivide")),
          words_k(ocl::make_kernel(cull, "cull_words")), mark_k(ocl::make_kernel(cull, "cull_mark")),
          cull_count_k(ocl::make_kernel(cull, "cull_count")),
          write_k(ocl::make_kernel(cull, "cull_write")), aabb_k(ocl::make_kernel(aabb, "brick_aabb")) {}
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
        return ocl::Buffer<T>(d, count);
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

// Rounds a positive double up to the next float (the margins below must not shrink).
float float_up(double x) {
    const auto f = static_cast<float>(x);
    return static_cast<double>(f) >= x ? f : std::nextafter(f, INFINITY);
}

}  // namespace

GeometryBuild BrickBuilder::build(const Geometry& g, const BuildSettings& s) {
    const auto wall_start = std::chrono::steady_clock::now();
    s.validate(device_.info());
    if (g.edits.size() > SDF_MAX_EDITS)
        throw InputError(fmt::format("geometry \"{}\" has {} edits; at most {} are supported", g.name, g.edits.size(),
                                     SDF_MAX_EDITS));
    GeometryBuild out;
    out.name = g.name;
    measure::Scheduler scheduler(device_);

    const Aabb box = bounds(g);
    if (box.empty()) {  // no add edit: nothing can be solid, an empty and valid result
        out.leaves = std::make_unique<ocl::Buffer<SdfBrick>>(device_, 0);
        out.leaf_edit_indices = std::make_unique<ocl::Buffer<cl_uint>>(device_, 0);
        out.pool = std::make_unique<ocl::Buffer<std::uint8_t>>(device_, 0);
        out.aabbs = std::make_unique<ocl::Buffer<SdfBounds>>(device_, 0);
        out.leaf_size = static_cast<float>(s.leaf_size);
        return out;
    }
    construct::Domain domain = construct::make_domain(box, s.leaf_size, s.branching);
    if (s.levels > 0) {
        if (s.levels < domain.levels)
            throw SettingError("levels", fmt::format("levels {} cannot cover geometry \"{}\" at leaf_size {}: it needs "
                                                     "at least {}", s.levels, g.name, s.leaf_size, domain.levels));
        const int bits_per_level = s.branching == 4 ? 2 : 1;
        if ((s.levels - 1) * bits_per_level > 30)
            throw SettingError("levels", fmt::format("levels {} with branching {} exceeds 2^30 leaf bricks per axis",
                                                     s.levels, s.branching));
        domain.levels = s.levels;
    }
    const int levels = domain.levels;
    const cl_uint log2b = s.branching == 4 ? 2 : 1;
    const std::size_t per_parent = std::size_t{1} << (3 * log2b);
    out.origin = glm::vec3(domain.origin);
    out.leaf_size = static_cast<float>(s.leaf_size);
    out.levels = levels;

    // Thresholds, saturation and margins (docs/construction.md).
    const glm::dvec3 far_corner = domain.origin + domain.side();
    const double magnitude = std::max({glm::abs(domain.origin).x, glm::abs(domain.origin).y, glm::abs(domain.origin).z,
                                       std::abs(far_corner.x), std::abs(far_corner.y), std::abs(far_corner.z)});
    auto threshold = [&](int level) {
        return float_up(domain.half_diagonal(level) * (1.0 + 1.0 / 1024.0) + magnitude * std::ldexp(1.0, -16));
    };
    const double voxel = s.voxel();
    out.band = static_cast<float>(s.band_voxels * voxel);
    out.clamp_c = float_up(std::max<double>(out.band, threshold(levels - 1)) * (1.0 + 1.0 / 256.0) +
                           s.guard * largest_blend(g));
    auto cull_radius = [&](int level) {
        return float_up(std::sqrt(3.0) * (0.5 * domain.cell_size(level) + (s.apron() - 0.5) * voxel) * (1.0 + 1e-6));
    };

    // Edits, the root's list (every edit, ascending) and the dependencies.
    const std::vector<SdfEdit> device_edits = to_device(g);
    const std::size_t n_edits = device_edits.size();
    ocl::Buffer<SdfEdit> edits(device_, device_edits, CL_MEM_READ_ONLY);
    std::vector<cl_uint> all(n_edits);
    std::iota(all.begin(), all.end(), 0u);
    std::optional<EditDependencies> deps;
    if (s.cull && s.dependencies) {
        if (!programs_->dependencies) programs_->dependencies = std::make_unique<DependencyBuilder>(device_, scan_);
        deps = programs_->dependencies->compute(edits, n_edits, scheduler);
        out.dependency_entries = deps->total;
        out.memory["dependency lists"] = deps->bytes();
    }
    ocl::Buffer<cl_uint> empty_uints(device_, 0);
    const ocl::Buffer<cl_uint>& dep_offsets = deps ? deps->offsets : empty_uints;
    const ocl::Buffer<cl_uint>& dep_indices = deps ? deps->indices : empty_uints;

    // Level -1: one pseudo-parent whose single child (branching 1) is the root.
    SdfBrick pseudo{};
    pseudo.level = 0xffffffffu;
    pseudo.edit_offset = 0;
    pseudo.edit_count = static_cast<sdf_u32>(n_edits);
    auto parents = std::make_unique<ocl::Buffer<SdfBrick>>(device_, std::span<const SdfBrick>(&pseudo, 1));
    auto parent_lists = std::make_unique<ocl::Buffer<cl_uint>>(device_, std::span<const cl_uint>(all));
    std::size_t parent_count = 1;
    std::vector<std::unique_ptr<ocl::Buffer<SdfBrick>>> level_bricks;
    std::uint64_t brick_bytes = 0, list_bytes = parent_lists->bytes(), scratch_bytes = 0;
    std::vector<std::uint64_t> list_entries;

    ocl::Buffer<cl_uint> counts(device_, 0), offsets(device_, 0), words(device_, 0), bits(device_, 0);
    const float ox = out.origin.x, oy = out.origin.y, oz = out.origin.z;
    const std::size_t count_local_bytes = static_cast<std::size_t>(s.chunk) * sizeof(SdfEdit);

    for (int level = 0; level < levels; ++level) {
        const cl_uint lb = level == 0 ? 0u : log2b;
        const std::size_t candidates = parent_count << (3 * lb);
        const std::size_t group = std::size_t{1} << (3 * lb);
        const float cell = static_cast<float>(domain.cell_size(level));
        // count
        if (counts.size() < parent_count) counts = allocate<cl_uint>(device_, parent_count, "the child counts");
        if (offsets.size() < parent_count) offsets = allocate<cl_uint>(device_, parent_count, "the child offsets");
        ocl::set_args(programs_->count_k.get(), edits, *parent_lists, *parents, lb, ox, oy, oz, cell, threshold(level),
                      out.clamp_c, counts, ocl::LocalMemory{count_local_bytes}, static_cast<cl_uint>(s.chunk),
                      ocl::LocalMemory{group * sizeof(cl_uint)});
        scheduler.launch("count", level, programs_->count_k.get(), candidates, group);
        // scan
        const std::uint64_t children = scan_.exclusive(counts, offsets, parent_count, scheduler, "scan", level);
        // Refuse early (not after minutes of work) a build whose pool cannot fit: a surface's brick count
        // grows about B^2 per level, so project the leaves from this level's count (generously).
        const int remaining = levels - 1 - level;
        const double projected = static_cast<double>(children) * std::pow(double(s.branching), 2.0 * remaining);
        const double pool_projected = projected * std::pow(double(s.samples), 3.0) * double(sample_bytes(s.format));
        if (pool_projected > 4.0 * static_cast<double>(device_.info().max_alloc_bytes))
            throw SettingError("leaf_size", fmt::format(
                "leaf_size {} is too small for geometry \"{}\" on {}: level {} already has {} bricks, which "
                "projects to about {:.3g} leaf bricks and a brick pool of {:.3g} bytes; the device allocates at most "
                "{} bytes at once: use a larger leaf_size",
                s.leaf_size, g.name, device_.info().name, level, children, projected, pool_projected,
                device_.info().max_alloc_bytes));
        // subdivide
        auto bricks = std::make_unique<ocl::Buffer<SdfBrick>>(
            allocate<SdfBrick>(device_, children, fmt::format("level {} ({} bricks)", level, children)));
        brick_bytes += bricks->bytes();
        if (children > 0) {
            ocl::set_args(programs_->subdivide_k.get(), *parents, static_cast<cl_uint>(parent_count), lb, offsets, *bricks);
            const std::size_t global = round_up(candidates, kGroup1d);
            scheduler.launch("subdivide", level, programs_->subdivide_k.get(), global, kGroup1d);
        }
        if (level > 0) level_bricks.push_back(std::move(parents));  // the parent level's masks are final now
        // cull
        std::unique_ptr<ocl::Buffer<cl_uint>> lists;
        if (s.cull && children > 0) {
            const std::size_t global = round_up(children, kGroup1d);
            if (words.size() < children) words = allocate<cl_uint>(device_, children, "the cull word counts");
            if (counts.size() < children) counts = allocate<cl_uint>(device_, children, "the cull counts");
            ocl::set_args(programs_->words_k.get(), *bricks, static_cast<cl_uint>(children), words);
            scheduler.launch("cull", level, programs_->words_k.get(), global, kGroup1d);
            const std::uint64_t total_words = scan_.exclusive(words, words, children, scheduler, "cull", level);
            if (bits.size() < total_words) bits = allocate<cl_uint>(device_, total_words, "the cull bit sets");
            if (total_words > 0) {
                const std::size_t word_global = round_up(total_words, kGroup1d);
                ocl::set_args(programs_->mark_k.get(), edits, *parent_lists, *bricks, static_cast<cl_uint>(children),
                              static_cast<cl_uint>(total_words), ox, oy, oz, cell, cull_radius(level), out.clamp_c,
                              static_cast<float>(magnitude), words, bits);
                scheduler.launch("cull", level, programs_->mark_k.get(), word_global, kGroup1d);
            }
            ocl::set_args(programs_->cull_count_k.get(), edits, *parent_lists, *bricks, static_cast<cl_uint>(children),
                          words, bits, static_cast<cl_uint>(deps ? 1 : 0), dep_offsets, dep_indices, counts);
            scheduler.launch("cull", level, programs_->cull_count_k.get(), global, kGroup1d);
            if (offsets.size() < children) offsets = allocate<cl_uint>(device_, children, "the list offsets");
            const std::uint64_t entries = scan_.exclusive(counts, offsets, children, scheduler, "cull", level);
            lists = std::make_unique<ocl::Buffer<cl_uint>>(
                allocate<cl_uint>(device_, entries, fmt::format("the edit lists of level {}", level)));
            ocl::set_args(programs_->write_k.get(), *parent_lists, *bricks, static_cast<cl_uint>(children), words, bits,
                          offsets, *lists);
            scheduler.launch("cull", level, programs_->write_k.get(), global, kGroup1d);
            list_bytes += lists->bytes();
            list_entries.push_back(entries);
        } else {
            lists = std::move(parent_lists);  // every brick keeps the whole list
            list_entries.push_back(children * n_edits);
        }
        scratch_bytes = std::max<std::uint64_t>(scratch_bytes, counts.bytes() + offsets.bytes() + words.bytes() + bits.bytes());
        parents = std::move(bricks);
        parent_lists = std::move(lists);
        parent_count = children;
        if (children == 0) break;
    }
    const bool complete = level_bricks.size() + 1 == static_cast<std::size_t>(levels) && parent_count > 0;
    out.leaf_count = complete ? parent_count : 0;
    level_bricks.push_back(std::move(parents));

    // evaluate + aabb
    const std::size_t samples3 = static_cast<std::size_t>(s.samples) * s.samples * s.samples;
    const std::size_t pool_values = out.leaf_count * samples3;
    out.pool = std::make_unique<ocl::Buffer<std::uint8_t>>(allocate<std::uint8_t>(
        device_, pool_values * sample_bytes(s.format), fmt::format("the brick pool ({} bricks)", out.leaf_count)));
    out.aabbs = std::make_unique<ocl::Buffer<SdfBounds>>(
        allocate<SdfBounds>(device_, out.leaf_count, "the brick AABBs"));
    if (out.leaf_count > 0) {
        const std::size_t group = std::min<std::size_t>(s.eval_group, samples3);
        const std::size_t per_item = (samples3 + group - 1) / group;
        const std::string options = fmt::format("-D SAMPLES={} -D APRON={} -D PER_ITEM={} -D FORMAT={}", s.samples,
                                                s.apron(), per_item, static_cast<int>(s.format));
        const ocl::Program program = ocl::build_program(device_, "brick_evaluate.cl", options);
        const ocl::Kernel kernel = ocl::make_kernel(program, "brick_evaluate");
        const float quant = s.format == BrickFormat::int8    ? static_cast<float>(127.0 / out.band)
                            : s.format == BrickFormat::int16 ? static_cast<float>(32767.0 / out.band)
                                                             : 1.0f;
        ocl::set_args(kernel.get(), edits, *parent_lists, *level_bricks.back(), ox, oy, oz, static_cast<float>(voxel),
                      out.clamp_c, out.band, quant, *out.pool, ocl::LocalMemory{count_local_bytes},
                      static_cast<cl_uint>(s.chunk));
        scheduler.launch("evaluate", levels - 1, kernel.get(), out.leaf_count * group, group);
        const std::size_t global = round_up(out.leaf_count, kGroup1d);
        ocl::set_args(programs_->aabb_k.get(), *level_bricks.back(), static_cast<cl_uint>(out.leaf_count), ox, oy, oz,
                      out.leaf_size, *out.aabbs);
        scheduler.launch("aabb", levels - 1, programs_->aabb_k.get(), global, kGroup1d);
    }
    device_.finish();
    out.launches = scheduler.resolve();
    out.device_ms = scheduler.total_ms();

    // Report: bricks, list lengths and work per level (read back the records; not part of device time).
    std::uint64_t evaluations = 0;
    std::uint64_t prev_entries = n_edits;  // the pseudo-parent's list
    std::vector<SdfBrick> prev{pseudo};
    for (std::size_t l = 0; l < level_bricks.size(); ++l) {
        const std::vector<SdfBrick> records = level_bricks[l]->read();
        LevelReport r;
        r.level = static_cast<int>(l);
        r.cell_size = domain.cell_size(static_cast<int>(l));
        r.bricks = records.size();
        r.edit_entries = l < list_entries.size() ? list_entries[l] : 0;
        for (const SdfBrick& b : records) r.max_edits = std::max(r.max_edits, b.edit_count);
        const std::uint64_t per = l == 0 ? 1 : per_parent;
        evaluations += prev_entries * per;  // count: every candidate child of every parent
        if (s.cull) {
            for (const SdfBrick& p : prev)  // cull: each kept child tests its parent's list
                evaluations += static_cast<std::uint64_t>(p.edit_count) *
                               (l == 0 ? records.size()
                                       : static_cast<std::size_t>(std::popcount(p.child_mask[0]) + std::popcount(p.child_mask[1])));
        }
        r.count_ms = scheduler.stage_ms("count", r.level);
        r.scan_ms = scheduler.stage_ms("scan", r.level);
        r.subdivide_ms = scheduler.stage_ms("subdivide", r.level);
        r.cull_ms = scheduler.stage_ms("cull", r.level);
        out.level_reports.push_back(r);
        prev_entries = r.edit_entries;
        prev = records;
    }
    if (out.leaf_count > 0) {
        const LevelReport& leaf = out.level_reports.back();
        out.edits_per_leaf_mean = static_cast<double>(leaf.edit_entries) / static_cast<double>(out.leaf_count);
        out.edits_per_leaf_max = leaf.max_edits;
        evaluations += leaf.edit_entries * samples3;
    }
    out.edit_evaluations = evaluations;
    out.memory["brick pool"] = out.pool->bytes();
    out.memory["brick records"] = brick_bytes;
    out.memory["aabbs"] = out.aabbs->bytes();
    out.memory["edit lists"] = list_bytes;
    out.memory["edits"] = edits.bytes();
    out.memory["scratch"] = scratch_bytes;
    out.leaves = std::move(level_bricks.back());
    if (!complete) out.leaves = std::make_unique<ocl::Buffer<SdfBrick>>(device_, 0);
    out.leaf_edit_indices = std::move(parent_lists);
    out.host_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - wall_start).count();
    return out;
}

std::string output_digest(const GeometryBuild& b, const BuildSettings& s) {
    Fnv1a64 h;
    const std::array<float, 4> domain{b.origin.x, b.origin.y, b.origin.z, b.leaf_size};
    h.add_values(std::span<const float>(domain));
    const std::array<std::int32_t, 3> layout{s.samples, static_cast<std::int32_t>(s.format), static_cast<std::int32_t>(b.leaf_count)};
    h.add_values(std::span<const std::int32_t>(layout));
    for (const SdfBrick& r : b.leaves->read()) h.add_values(std::span<const sdf_i32>(r.coord, 3));
    const std::vector<std::uint8_t> pool = b.pool->read();
    h.add_values(std::span<const std::uint8_t>(pool));
    return h.hex();
}

std::string list_digest(const GeometryBuild& b) {
    Fnv1a64 h;
    const std::vector<SdfBrick> leaves = b.leaves->read();
    const std::vector<cl_uint> indices = b.leaf_edit_indices->read();
    for (const SdfBrick& r : leaves) {
        h.add_values(std::span<const sdf_i32>(r.coord, 3));
        h.add_values(std::span<const cl_uint>(indices.data() + r.edit_offset, r.edit_count));
    }
    return h.hex();
}

}  // namespace sdfbrick::construct
