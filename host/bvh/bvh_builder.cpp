#include "bvh/bvh_builder.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <numeric>
#include <stdexcept>

#include <fmt/format.h>

#include "cl/launch.h"
#include "cl/program.h"
#include "construct/scan.h"
#include "core/errors.h"
#include "scene/to_device.h"

namespace sdfbrick::bvh {
namespace {

constexpr std::size_t kGroup = 64;
constexpr std::size_t kMarkGroup = 64;  // BVH_MARK_GROUP (kernels/bvh_build.cl)
constexpr cl_uint kFlagUnsorted = 1u, kFlagTooLarge = 2u, kFlagStuck = 4u;  // kernels/bvh_build.cl
constexpr std::size_t kMaxNodes = std::size_t{1} << 29;  // the tracer's stack entries hold node << 2 (sdf_trace.h)

std::size_t round_up(std::size_t n, std::size_t m) { return (n + m - 1) / m * m; }

// Internal nodes of a tree over n leaves (a single leaf still gets a root node).
std::size_t nodes_for(std::size_t n) { return n <= 1 ? n : n - 1; }

float float_down(double x) {
    const auto f = static_cast<float>(x);
    return static_cast<double>(f) <= x ? f : std::nextafter(f, -INFINITY);
}
float float_up(double x) {
    const auto f = static_cast<float>(x);
    return static_cast<double>(f) >= x ? f : std::nextafter(f, INFINITY);
}

// World box of an object: the 8 corners of its geometry's brick box, transformed, rounded outward
// with a margin for the rounding of the instance's float transform.
SdfBounds world_box(const Object& o, const SdfBounds& local) {
    Aabb box;
    for (int c = 0; c < 8; ++c) {
        box.grow(o.transform.apply(glm::dvec3((c & 1) ? local.hi[0] : local.lo[0], (c & 2) ? local.hi[1] : local.lo[1],
                                              (c & 4) ? local.hi[2] : local.lo[2])));
    }
    const double margin = 1e-6 * (glm::length(box.extent()) + glm::length(o.transform.translation) + 1.0);
    SdfBounds out;
    for (int a = 0; a < 3; ++a) {
        out.lo[a] = float_down(box.lo[a] - margin);
        out.hi[a] = float_up(box.hi[a] + margin);
    }
    return out;
}

// Bit i of v -> bit 3i, for the low 16 bits.
std::uint64_t spread16(std::uint64_t v) {
    std::uint64_t x = v & 0xFFFF;
    x = (x | (x << 16)) & 0x0000FF0000FFULL;
    x = (x | (x << 8)) & 0x00F00F00F00FULL;
    x = (x | (x << 4)) & 0x0C30C30C30C3ULL;
    x = (x | (x << 2)) & 0x249249249249ULL;
    return x;
}

}  // namespace

struct BvhBuilder::Programs {
    ocl::Program program;
    ocl::Kernel morton, hit_marks, keep, hierarchy, refit, parity, widen;
    construct::Scan scan;
    explicit Programs(ocl::Device& d)
        : program(ocl::build_program(d, "bvh_build.cl")),
          morton(ocl::make_kernel(program, "bvh_morton_bricks")),
          hit_marks(ocl::make_kernel(program, "bvh_hit_marks")),
          keep(ocl::make_kernel(program, "bvh_keep")),
          hierarchy(ocl::make_kernel(program, "bvh_hierarchy")),
          refit(ocl::make_kernel(program, "bvh_refit")),
          parity(ocl::make_kernel(program, "bvh_parity")),
          widen(ocl::make_kernel(program, "bvh_widen")),
          scan(d) {}
};

// On GPUs 16 work-items read a brick's samples side by side (d28: 64 with a serial reduction took
// 0.26 ms on drops); on CPUs, where a work-group's items run one after another, each has a brick of
// its own (PoCL here: 18 ms on drops against 43 with 16).
BvhBuilder::BvhBuilder(ocl::Device& device, std::size_t mark_parts)
    : device_(device), programs_(std::make_unique<Programs>(device)),
      mark_parts_(mark_parts != 0 ? mark_parts : device.info().type == "cpu" ? 1 : 16) {
    if (mark_parts_ > kMarkGroup || (mark_parts_ & (mark_parts_ - 1)) != 0)
        throw std::invalid_argument("BvhBuilder: mark_parts is a power of two up to 64");
}
BvhBuilder::~BvhBuilder() = default;

// Hierarchy and refit of one tree over n >= 1 sorted leaves into nodes[offset ...]; its root box goes
// to root_boxes[slot]. Scratch buffers hold at least n entries.
struct TreeScratch {
    ocl::Buffer<cl_uint> node_parent, leaf_parent, arrivals;
    TreeScratch(ocl::Device& d, std::size_t n)
        : node_parent(ocl::pooled, d, n), leaf_parent(ocl::pooled, d, n), arrivals(ocl::pooled, d, n) {}
    std::uint64_t bytes() const { return node_parent.bytes() + leaf_parent.bytes() + arrivals.bytes(); }
};

// Per geometry, before its tree: every brick's key, whether it can hold a hit, and the marks' scan.
struct LeafScratch {
    ocl::Buffer<cl_ulong> keys;
    ocl::Buffer<cl_uint> marks, at;
    LeafScratch(ocl::Device& d, std::size_t n)
        : keys(ocl::pooled, d, n), marks(ocl::pooled, d, n), at(ocl::pooled, d, n) {}
    std::uint64_t bytes() const { return keys.bytes() + marks.bytes() + at.bytes(); }
};

// The binary nodes that become wide ones: even[i] = 1 at even depth in its tree (bvh_parity), and
// per tree (slot) how many.
struct WideMarks {
    ocl::Buffer<cl_uint> even, counts;
    WideMarks(ocl::Device& d, std::size_t nodes, std::size_t trees)
        : even(ocl::pooled, d, nodes), counts(ocl::pooled, d, std::vector<cl_uint>(trees, 0u)) {}
};

void BvhBuilder::build_tree(measure::Scheduler& scheduler, measure::Stage stage, const ocl::Buffer<cl_ulong>& keys,
                            const ocl::Buffer<cl_uint>& ids, const ocl::Buffer<SdfBounds>& leaf_boxes, std::size_t n,
                            ocl::Buffer<SdfBvhNode>& nodes,
                            std::size_t offset, TreeScratch& scratch, ocl::Buffer<SdfBounds>& root_boxes,
                            std::size_t slot, ocl::Buffer<cl_uint>& flags, WideMarks& marks) {
    const auto count = static_cast<cl_uint>(n), node_offset = static_cast<cl_uint>(offset);
    const std::vector<cl_uint> zeros(nodes_for(n), 0u);
    scratch.arrivals.write(zeros);
    if (n > 1) {
        ocl::set_args(programs_->hierarchy.get(), keys, ids, count, node_offset, nodes, scratch.node_parent,
                      scratch.leaf_parent);
        const std::size_t global = round_up(n - 1, kGroup);
        scheduler.launch(stage, -1, programs_->hierarchy.get(), global, kGroup);
    }
    ocl::set_args(programs_->refit.get(), leaf_boxes, ids, count, node_offset, nodes, scratch.node_parent,
                  scratch.leaf_parent, scratch.arrivals, root_boxes, static_cast<cl_uint>(slot), flags);
    const std::size_t global = round_up(n, kGroup);
    scheduler.launch(stage, -1, programs_->refit.get(), global, kGroup);
    ocl::set_args(programs_->parity.get(), scratch.node_parent, count, node_offset, marks.even, marks.counts,
                  static_cast<cl_uint>(slot));
    scheduler.launch(stage, -1, programs_->parity.get(), round_up(nodes_for(n), kGroup), kGroup);
}

std::unique_ptr<ocl::Buffer<SdfBvhWideNode>> BvhBuilder::widen(measure::Scheduler& scheduler, measure::Stage stage,
                                                               const ocl::Buffer<SdfBvhNode>& binary,
                                                               const WideMarks& marks, std::size_t count) {
    auto wide = std::make_unique<ocl::Buffer<SdfBvhWideNode>>(ocl::pooled, device_, count);
    if (binary.size() == 0) return wide;
    ocl::Buffer<cl_uint> map(ocl::pooled, device_, binary.size());
    if (programs_->scan.exclusive(marks.even, map, binary.size(), scheduler, stage, -1) != count)
        throw std::logic_error("BVH widen: the marks' scan disagrees with their counts");
    ocl::set_args(programs_->widen.get(), binary, static_cast<cl_uint>(binary.size()), marks.even, map, *wide);
    scheduler.launch(stage, -1, programs_->widen.get(), round_up(binary.size(), kGroup), kGroup);
    return wide;
}

// The top level's leaves: the instances of geometries with bricks, ordered by the Morton key of their
// world box centre (ties by object index); keys are that 48-bit code then the rank: unique, ascending.
// With nothing to trace, one instance of the geometry without bricks (index `empty_geometry`).
struct TopLevel {
    std::vector<SdfInstance> instances;
    std::vector<SdfBounds> boxes;
    std::vector<cl_ulong> keys;
    std::vector<std::size_t> objects;  // the scene object of each instance
};

namespace {

TopLevel empty_top_level(std::size_t empty_geometry) {
    SdfInstance none{};
    none.world_to_geometry[0] = none.world_to_geometry[4] = none.world_to_geometry[8] = 1.0f;
    none.scale = 1.0f;
    none.geometry = static_cast<sdf_u32>(empty_geometry);
    return {{none}, {SdfBounds{{0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, 0.0f}}}, {0}, {}};
}

TopLevel order_instances(const Scene& scene, const SceneBvh& bottom, std::size_t empty_geometry) {
    const std::vector<SdfInstance> all = make_instances(scene);
    std::vector<std::size_t> objects;
    std::vector<SdfBounds> world;
    for (std::size_t i = 0; i < scene.objects.size(); ++i) {
        const std::size_t g = scene.objects[i].geometry;
        if (bottom.roots[g] == SDF_NO_NODE) continue;
        objects.push_back(i);
        world.push_back(world_box(scene.objects[i], bottom.geometry_boxes[g]));
    }
    if (objects.size() > 65536)
        throw InputError(fmt::format("the scene has {} objects with bricks; at most 65536 are supported", objects.size()));
    if (objects.empty()) return empty_top_level(empty_geometry);
    Aabb all_box;
    for (const SdfBounds& b : world) {
        all_box.grow(glm::dvec3(b.lo[0], b.lo[1], b.lo[2]));
        all_box.grow(glm::dvec3(b.hi[0], b.hi[1], b.hi[2]));
    }
    const glm::dvec3 extent = glm::max(all_box.extent(), glm::dvec3(1e-30));
    std::vector<std::uint64_t> morton(objects.size());
    for (std::size_t i = 0; i < objects.size(); ++i) {
        const glm::dvec3 c = (glm::dvec3(world[i].lo[0] + world[i].hi[0], world[i].lo[1] + world[i].hi[1],
                                         world[i].lo[2] + world[i].hi[2]) * 0.5 - all_box.lo) / extent;
        const glm::dvec3 q = glm::clamp(glm::floor(c * 65536.0), glm::dvec3(0.0), glm::dvec3(65535.0));
        morton[i] = spread16(static_cast<std::uint64_t>(q.x)) | (spread16(static_cast<std::uint64_t>(q.y)) << 1) |
                    (spread16(static_cast<std::uint64_t>(q.z)) << 2);
    }
    std::vector<std::size_t> order(objects.size());
    std::iota(order.begin(), order.end(), std::size_t{0});
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
        return morton[a] != morton[b] ? morton[a] < morton[b] : a < b;
    });
    TopLevel top;
    for (std::size_t r = 0; r < order.size(); ++r) {
        const std::size_t i = order[r];
        top.instances.push_back(all[objects[i]]);
        top.boxes.push_back(world[i]);
        top.keys.push_back((morton[i] << 16) | r);
        top.objects.push_back(objects[i]);
    }
    return top;
}

}  // namespace

// One geometry's leaves in its tree: the bricks that can hold a hit, their keys in Morton order and
// their brick numbers.
struct KeptLeaves {
    std::size_t count = 0;
    std::unique_ptr<ocl::Buffer<cl_ulong>> keys;
    std::unique_ptr<ocl::Buffer<cl_uint>> ids;
};

namespace {

// Stored values at or below this may be a hit (sdf_types.h); voxel to stored units as the tracer has it.
float hit_threshold(const construct::BuildSettings& settings, const construct::GeometryBuild& b) {
    const float voxel_to_stored = static_cast<float>(settings.voxel()) / settings.layout().dequantise_scale(b.band);
    return SDF_HIT_MARGIN * SDF_SPHERE_EPS * voxel_to_stored;
}

}  // namespace

KeptLeaves BvhBuilder::keep_hit_bricks(const construct::GeometryBuild& b, const construct::BuildSettings& settings,
                                       measure::Scheduler& scheduler, LeafScratch& scratch, ocl::Buffer<cl_uint>& flags) {
    const std::size_t n = b.leaf_count;
    KeptLeaves out;
    if (n == 0) return out;
    ocl::set_args(programs_->morton.get(), *b.leaves, static_cast<cl_uint>(n), static_cast<cl_uint>(b.levels - 1),
                  static_cast<cl_uint>(b.branching == 4 ? 2 : 1), scratch.keys, flags);
    scheduler.launch(measure::Stage::bvh, -1, programs_->morton.get(), round_up(n, kGroup), kGroup);
    const construct::BrickLayout layout = settings.layout();
    ocl::set_args(programs_->hit_marks.get(), *b.pool, static_cast<cl_uint>(n),
                  static_cast<cl_uint>(layout.samples_per_brick()), static_cast<cl_uint>(layout.format_code()),
                  hit_threshold(settings, b), static_cast<cl_uint>(mark_parts_), scratch.marks);
    scheduler.launch(measure::Stage::bvh, -1, programs_->hit_marks.get(), round_up(n * mark_parts_, kMarkGroup),
                     kMarkGroup);
    out.count = programs_->scan.exclusive(scratch.marks, scratch.at, n, scheduler, measure::Stage::bvh, -1);
    if (out.count == 0) return out;
    out.keys = std::make_unique<ocl::Buffer<cl_ulong>>(ocl::pooled, device_, out.count);
    out.ids = std::make_unique<ocl::Buffer<cl_uint>>(ocl::pooled, device_, out.count);
    ocl::set_args(programs_->keep.get(), scratch.keys, scratch.marks, scratch.at, static_cast<cl_uint>(n), *out.keys,
                  *out.ids);
    scheduler.launch(measure::Stage::bvh, -1, programs_->keep.get(), round_up(n, kGroup), kGroup);
    return out;
}

std::uint64_t BvhBuilder::build_bottom_levels(std::span<const construct::GeometryBuild> builds,
                                              const construct::BuildSettings& settings, measure::Scheduler& scheduler,
                                              SceneBvh& out, ocl::Buffer<SdfBounds>& root_boxes,
                                              ocl::Buffer<cl_uint>& flags) {
    std::size_t max_leaves = 1;
    for (const construct::GeometryBuild& b : builds) max_leaves = std::max<std::size_t>(max_leaves, b.leaf_count);
    LeafScratch leaf_scratch(device_, max_leaves);
    std::vector<KeptLeaves> kept;
    std::size_t total_nodes = 0, max_kept = 1;
    for (const construct::GeometryBuild& b : builds) {
        kept.push_back(keep_hit_bricks(b, settings, scheduler, leaf_scratch, flags));
        total_nodes += nodes_for(kept.back().count);
        max_kept = std::max(max_kept, kept.back().count);
        out.tree_leaves.push_back(kept.back().count);
    }
    const cl_uint flag = flags.read()[0];
    if (flag & kFlagTooLarge)
        throw SettingError("leaf_size", "a brick coordinate needs more than the 21 bits per axis of the BVH's Morton "
                                        "keys: use a larger leaf_size or fewer levels");
    if (flag & kFlagUnsorted) throw std::logic_error("construction's leaf bricks are not in Morton order");
    if (total_nodes >= kMaxNodes)
        throw InputError(fmt::format("the scene's bricks need {} BVH nodes; the tracer addresses fewer than {}",
                                     total_nodes, kMaxNodes));
    ocl::Buffer<SdfBvhNode> binary(ocl::pooled, device_, total_nodes);
    TreeScratch scratch(device_, max_kept);
    WideMarks marks(device_, total_nodes, builds.size());
    std::size_t offset = 0;
    for (std::size_t g = 0; g < builds.size(); ++g) {
        if (kept[g].count == 0) continue;
        build_tree(scheduler, measure::Stage::bvh, *kept[g].keys, *kept[g].ids, *builds[g].aabbs, kept[g].count,
                   binary, offset, scratch, root_boxes, g, flags, marks);
        offset += nodes_for(kept[g].count);
    }
    const std::vector<SdfBounds> boxes = root_boxes.read();
    out.geometry_boxes.assign(boxes.begin(), boxes.begin() + static_cast<std::ptrdiff_t>(builds.size()));
    // Every tree's root is its first node, at even depth: its wide index is the marks of the trees before.
    const std::vector<cl_uint> counts = marks.counts.read();
    std::size_t wide_count = 0;
    for (std::size_t g = 0; g < builds.size(); ++g) {
        out.roots.push_back(kept[g].count == 0 ? SDF_NO_NODE : static_cast<std::uint32_t>(wide_count));
        wide_count += counts[g];
    }
    out.nodes = widen(scheduler, measure::Stage::bvh, binary, marks, wide_count);
    out.node_count = wide_count;
    std::uint64_t kept_bytes = 0;
    for (const KeptLeaves& k : kept)
        if (k.count) kept_bytes += k.keys->bytes() + k.ids->bytes();
    // the binary trees, and the marks and their numbers (the same size)
    return binary.bytes() + leaf_scratch.bytes() + kept_bytes + scratch.bytes() + 2 * marks.even.bytes();
}

void BvhBuilder::build_top_level(const TopLevel& top, measure::Scheduler& scheduler, SceneBvh& out,
                                 ocl::Buffer<SdfBounds>& root_boxes, std::size_t slot, ocl::Buffer<cl_uint>& flags) {
    out.instances = std::make_unique<ocl::Buffer<SdfInstance>>(ocl::pooled, device_, std::span<const SdfInstance>(top.instances));
    out.instance_objects = top.objects;
    ocl::Buffer<SdfBvhNode> binary(ocl::pooled, device_, nodes_for(top.instances.size()));
    ocl::Buffer<cl_ulong> keys(ocl::pooled, device_, std::span<const cl_ulong>(top.keys));
    std::vector<cl_uint> identity(top.instances.size());
    std::iota(identity.begin(), identity.end(), cl_uint{0});
    ocl::Buffer<cl_uint> ids(ocl::pooled, device_, std::span<const cl_uint>(identity));
    ocl::Buffer<SdfBounds> boxes(ocl::pooled, device_, std::span<const SdfBounds>(top.boxes));
    TreeScratch scratch(device_, top.instances.size());
    WideMarks marks(device_, binary.size(), slot + 1);  // counted under the tree's slot, as its root box
    build_tree(scheduler, measure::Stage::tlas, keys, ids, boxes, top.instances.size(), binary, 0, scratch, root_boxes,
               slot, flags, marks);
    if (flags.read()[0] & kFlagStuck) throw std::logic_error("BVH refit: a sibling's box never became visible");
    out.tlas_node_count = marks.counts.read()[slot];
    out.tlas = widen(scheduler, measure::Stage::tlas, binary, marks, out.tlas_node_count);
}

SceneBvh BvhBuilder::build(const Scene& scene, std::span<const construct::GeometryBuild> builds,
                           const construct::BuildSettings& settings, measure::Scheduler& scheduler) {
    const auto wall_start = std::chrono::steady_clock::now();
    if (builds.size() != scene.geometries.size())
        throw std::invalid_argument("BvhBuilder::build: one build per geometry is needed");
    SceneBvh out;
    const std::size_t first_launch = scheduler.size();
    const cl_uint zero = 0;
    ocl::Buffer<cl_uint> flags(ocl::pooled, device_, std::span<const cl_uint>(&zero, 1));
    ocl::Buffer<SdfBounds> root_boxes(ocl::pooled, device_, builds.size() + 1);
    const std::uint64_t scratch_bytes = build_bottom_levels(builds, settings, scheduler, out, root_boxes, flags);
    build_top_level(order_instances(scene, out, builds.size()), scheduler, out, root_boxes, builds.size(), flags);
    scheduler.resolve();
    out.device_ms = scheduler.total_ms(first_launch);
    out.memory["bvh nodes"] = out.nodes->bytes();
    out.memory["tlas nodes"] = out.tlas->bytes() + out.instances->bytes();
    out.memory["bvh scratch"] = scratch_bytes;
    out.host_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - wall_start).count();
    return out;
}

namespace {

// One child slot of a node: its box and child (>= 0 a node, < 0 leaf ~child).
struct Slot {
    SdfBounds box;
    std::int32_t child;
};

std::vector<Slot> slots_of(const SdfBvhWideNode& n) {
    std::vector<Slot> out;
    for (int k = 0; k < 4; ++k)
        if (n.child[k] != SDF_WIDE_EMPTY)
            out.push_back({{{n.lo_x[k], n.lo_y[k], n.lo_z[k]}, {n.hi_x[k], n.hi_y[k], n.hi_z[k]}}, n.child[k]});
    return out;
}

bool contains(const SdfBounds& outer, const SdfBounds& inner) {
    for (int a = 0; a < 3; ++a)
        if (inner.lo[a] < outer.lo[a] || inner.hi[a] > outer.hi[a]) return false;
    return true;
}

}  // namespace

std::vector<std::uint8_t> hit_bricks(std::span<const std::uint8_t> pool, const construct::BuildSettings& settings,
                                     const construct::GeometryBuild& b) {
    const construct::BrickLayout layout = settings.layout();
    const std::size_t per_brick = layout.samples_per_brick(), bytes = layout.sample_bytes();
    const double threshold = hit_threshold(settings, b);
    std::vector<std::uint8_t> out(pool.size() / (per_brick * bytes), 0);
    for (std::size_t i = 0; i < out.size() * per_brick; ++i) {
        const std::uint8_t* p = pool.data() + i * bytes;
        double v = 0.0;
        if (layout.format == construct::BrickFormat::int8) {
            v = static_cast<std::int8_t>(*p);
        } else if (layout.format == construct::BrickFormat::int16) {
            std::int16_t x;
            std::memcpy(&x, p, sizeof x);
            v = x;
        } else {
            float x;
            std::memcpy(&x, p, sizeof x);
            v = x;
        }
        if (v <= threshold) out[i / per_brick] = 1;
    }
    return out;
}

std::string check_tree(std::span<const SdfBvhWideNode> nodes, std::uint32_t root, std::span<const SdfBounds> leaf_boxes,
                       std::span<const std::uint8_t> in_tree) {
    const std::size_t n = leaf_boxes.size();
    if (in_tree.size() != n) return "the leaves' marks are not one per leaf";
    if (std::count(in_tree.begin(), in_tree.end(), 1) == 0)
        return root == SDF_NO_NODE ? "" : "a tree without leaves has a root";
    if (root >= nodes.size()) return fmt::format("root {} is outside the {} nodes", root, nodes.size());
    std::vector<int> seen(n, 0);
    std::vector<std::uint32_t> stack{root};
    std::size_t visited = 0;
    while (!stack.empty()) {
        const std::uint32_t i = stack.back();
        stack.pop_back();
        if (i >= nodes.size()) return fmt::format("node index {} is outside the {} nodes", i, nodes.size());
        if (++visited > nodes.size()) return "a node is reached twice (the tree has a cycle or shared subtree)";
        for (const Slot& slot : slots_of(nodes[i])) {
            if (slot.child < 0) {
                const auto leaf = static_cast<std::size_t>(~slot.child);
                if (leaf >= n) return fmt::format("node {} names leaf {} of {}", i, leaf, n);
                if (!in_tree[leaf]) return fmt::format("node {} names leaf {}, which cannot hold a hit", i, leaf);
                if (seen[leaf]++) return fmt::format("leaf {} is reached twice", leaf);
                const SdfBounds& b = leaf_boxes[leaf];
                if (!std::equal(b.lo, b.lo + 3, slot.box.lo) || !std::equal(b.hi, b.hi + 3, slot.box.hi))
                    return fmt::format("node {} holds a box for leaf {} that is not the leaf's box", i, leaf);
                continue;
            }
            const auto ci = static_cast<std::uint32_t>(slot.child);
            if (ci >= nodes.size()) return fmt::format("node {} names node {} of {}", i, ci, nodes.size());
            for (const Slot& inner : slots_of(nodes[ci]))
                if (!contains(slot.box, inner.box))
                    return fmt::format("the box of node {} in node {} does not contain its children's boxes", ci, i);
            stack.push_back(ci);
        }
    }
    for (std::size_t l = 0; l < n; ++l)
        if (in_tree[l] && !seen[l]) return fmt::format("leaf {} is not reachable", l);
    return "";
}

}  // namespace sdfbrick::bvh
