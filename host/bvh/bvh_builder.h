// Stage "bvh" (docs/tracing.md): a linear BVH (Karras 2012) per geometry over its leaf bricks that can hold a hit,
// built and refit on the device directly from construction's Morton order (kernels/bvh_build.cl), and
// a top level over the object instances, so instances of one geometry share its bricks and tree.
// The top level's few keys are computed and sorted on the host; its tree is built by the same kernels.
// The tracer walks the 4-wide trees made from these binary ones, which the build then lets go.
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "construct/brick_builder.h"
#include "measure/scheduler.h"
#include "cl/buffer.h"
#include "cl/device.h"
#include "scene/scene.h"
#include "sdf_types.h"

namespace sdfbrick::bvh {

struct SceneBvh {
    // The 4-wide trees the tracer walks (kernels/bvh_build.cl): made from binary LBVHs, which are
    // scratch of the build; one wide node per binary node at even depth.
    std::unique_ptr<ocl::Buffer<SdfBvhWideNode>> nodes;   // the bottom levels of all geometries, one array
    std::unique_ptr<ocl::Buffer<SdfBvhWideNode>> tlas;    // the top level (root 0); leaf i = instances[i]
    std::unique_ptr<ocl::Buffer<SdfInstance>> instances;  // in the top level's leaf order
    std::vector<std::uint32_t> roots;        // per geometry: its root in nodes, SDF_NO_NODE without leaves
    std::vector<std::uint64_t> tree_leaves;  // per geometry: the bricks in its tree (those that can hold a hit)
    std::vector<SdfBounds> geometry_boxes;   // per geometry: the box of its tree's bricks (geometry frame)
    std::vector<std::size_t> instance_objects;  // instances[i] is scene object instance_objects[i]
    std::uint64_t node_count = 0, tlas_node_count = 0;  // wide nodes
    double device_ms = 0.0;  // the BVH's launches
    double host_ms = 0.0;
    std::map<std::string, std::uint64_t> memory;
};

struct TreeScratch;
struct LeafScratch;
struct KeptLeaves;
struct TopLevel;
struct WideMarks;

class BvhBuilder {
public:
    // mark_parts: work-items that share a brick's test for a hit (bvh_hit_marks), a power of two up
    // to 64; 0 picks by the device (changes no bit).
    explicit BvhBuilder(ocl::Device& device, std::size_t mark_parts = 0);
    ~BvhBuilder();

    // builds[g] is scene.geometries[g] as BrickBuilder built it with settings. A geometry's tree holds
    // the bricks that can hold a hit: those with a sample at or below the tracer's hit threshold
    // (SDF_SPHERE_EPS voxels, times SDF_HIT_MARGIN); a brick outside the surface everywhere changes no
    // ray's result. A scene with nothing to trace gets a top level with one instance of a geometry
    // without bricks (SdfBrickGeometry root SDF_NO_NODE), which every ray misses.
    // Throws InputError when a brick coordinate exceeds the 21 bits per axis
    // of the Morton keys (too many levels).
    // Every launch is recorded in scheduler (the run's launch recorder).
    SceneBvh build(const Scene& scene, std::span<const construct::GeometryBuild> builds,
                   const construct::BuildSettings& settings, measure::Scheduler& scheduler);

private:
    struct Programs;
    // Every geometry's tree into out.nodes (roots, geometry_boxes); returns the scratch bytes used.
    std::uint64_t build_bottom_levels(std::span<const construct::GeometryBuild> builds,
                                      const construct::BuildSettings& settings, measure::Scheduler& scheduler,
                                      SceneBvh& out, ocl::Buffer<SdfBounds>& root_boxes, ocl::Buffer<cl_uint>& flags);
    // Build b's bricks that can hold a hit, in Morton order (keys checked into flags).
    KeptLeaves keep_hit_bricks(const construct::GeometryBuild& b, const construct::BuildSettings& settings,
                               measure::Scheduler& scheduler, LeafScratch& scratch, ocl::Buffer<cl_uint>& flags);
    void build_top_level(const TopLevel& top, measure::Scheduler& scheduler, SceneBvh& out,
                         ocl::Buffer<SdfBounds>& root_boxes, std::size_t slot, ocl::Buffer<cl_uint>& flags);
    // The wide trees of the binary trees in `binary`: count wide nodes, from the nodes marked even.
    std::unique_ptr<ocl::Buffer<SdfBvhWideNode>> widen(measure::Scheduler& scheduler, measure::Stage stage,
                                                       const ocl::Buffer<SdfBvhNode>& binary, const WideMarks& marks,
                                                       std::size_t count);
    // A tree over n leaves with sorted keys; leaf j is ids[j], its box leaf_boxes[ids[j]].
    void build_tree(measure::Scheduler& scheduler, measure::Stage stage, const ocl::Buffer<cl_ulong>& keys,
                    const ocl::Buffer<cl_uint>& ids, const ocl::Buffer<SdfBounds>& leaf_boxes, std::size_t n,
                    ocl::Buffer<SdfBvhNode>& nodes,
                    std::size_t offset, TreeScratch& scratch, ocl::Buffer<SdfBounds>& root_boxes, std::size_t slot,
                    ocl::Buffer<cl_uint>& flags, WideMarks& marks);
    ocl::Device& device_;
    std::unique_ptr<Programs> programs_;
    std::size_t mark_parts_;
};

// Per brick of build b's pool (read back to the host), 1 when it can hold a hit (a sample at or below
// the tracer's hit threshold, as BvhBuilder::build keeps them), else 0.
std::vector<std::uint8_t> hit_bricks(std::span<const std::uint8_t> pool, const construct::BuildSettings& settings,
                                     const construct::GeometryBuild& b);

// Checks a wide tree read back to the host: every leaf l with in_tree[l] is reached exactly once from
// root and no other leaf is, a leaf's box in its node equals leaf_boxes[leaf], and every internal
// slot's box contains the boxes of the node's slots it names (unused slots are SDF_WIDE_EMPTY).
// Returns "" when it holds, else the first violation.
std::string check_tree(std::span<const SdfBvhWideNode> nodes, std::uint32_t root, std::span<const SdfBounds> leaf_boxes,
                       std::span<const std::uint8_t> in_tree);

}  // namespace sdfbrick::bvh
