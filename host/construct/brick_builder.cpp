#include "construct/brick_builder.h"

#include "construct/build_parts.h"

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
    if (count_splits < 0 || count_splits > 64 || (count_splits & (count_splits - 1)) != 0)
        throw SettingError("count_splits", fmt::format("count_splits must be a power of two in 1..64 (0 = automatic), got {}",
                                                       count_splits));
    if (count_untested < 0)
        throw SettingError("count_untested", fmt::format("count_untested must be 0 or more, got {}", count_untested));
    if (cull_siblings < 0)
        throw SettingError("cull_siblings", fmt::format("cull_siblings must be 0 or more, got {}", cull_siblings));
    if (apron_share_edits < 0)
        throw SettingError("apron_share_edits", fmt::format("apron_share_edits must be 0 or more, got {}", apron_share_edits));
    if (eval_group < 1 || eval_group > 1024 || (eval_group & (eval_group - 1)) != 0)
        throw SettingError("eval_group", fmt::format("eval_group must be a power of two in 1..1024, got {}", eval_group));
    if (static_cast<std::size_t>(eval_group) > device.max_work_group_size)
        throw SettingError("eval_group", fmt::format("eval_group {} is larger than the {} work-items per work-group {} "
                                                     "allows", eval_group, device.max_work_group_size, device.name));
    if (eval_registers < 0 || eval_registers > 255)
        throw SettingError("eval_registers", fmt::format("eval_registers must lie in 0..255, got {}", eval_registers));
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
    const std::uint64_t local = evaluation_local_bytes(chunk);
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

BrickBuilder::BrickBuilder(ocl::Device& device)
    : device_(device), scan_(device), programs_(std::make_unique<detail::BuildPrograms>(device)) {}

BrickBuilder::~BrickBuilder() = default;

GeometryBuild BrickBuilder::build(const Geometry& g, const BuildSettings& s, measure::Scheduler& scheduler,
                                  const Subtrees* subtrees, const std::vector<SdfEdit>* prepared) {
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
    const detail::BuildPlan plan = detail::plan_build(g, box, s);
    out.origin = glm::vec3(plan.domain.origin);
    out.levels = plan.domain.levels;
    out.branching = s.branching;
    out.band = plan.band;
    out.clamp_c = plan.clamp_c;
    out.coarsest_leaf_level = plan.coarsest_leaf;
    out.tolerance = s.tolerance;
    detail::BuildInputs in(device_, *programs_, scan_, g, s, plan, scheduler, out, prepared);
    std::optional<detail::AdaptiveLeaves> adaptive;
    if (s.adaptive()) adaptive.emplace(in);
    detail::Levels levels(in, subtrees, adaptive ? &*adaptive : nullptr);
    levels.start();
    const bool complete = levels.run();
    out.leaf_count = adaptive ? adaptive->assemble(levels) : complete ? levels.parent_count() : 0;
    out.leaves_built = out.leaf_count;
    const ocl::Buffer<SdfBrick>& leaves = adaptive ? adaptive->merged() : *levels.level_bricks().back();
    detail::LeafEvaluation evaluation(in);
    evaluation.evaluate(leaves, levels.lists(), out.leaf_count, levels.bytes, adaptive ? &*adaptive : nullptr);
    device_.finish();
    scheduler.resolve();
    out.end_launch = scheduler.size();
    out.device_ms = scheduler.total_ms(out.first_launch);
    detail::BuildReport(in, levels, adaptive ? &*adaptive : nullptr, evaluation).fill(leaves, levels.lists(), out.leaf_count);
    out.leaves = adaptive ? adaptive->take_merged()
                 : complete ? levels.take_last_level()
                            : std::make_unique<ocl::Buffer<SdfBrick>>(device_, 0);
    out.leaf_edit_indices = levels.take_lists();
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
