// A BVH over the boxes of one geometry's edits, for the device reference tracer
// (kernels/reference_trace.cl), which asks it "which edit boxes contain this point?".
//
// This tree is built on the HOST (it is small: one leaf per edit, at most SDF_MAX_EDITS = 65,536
// edits, built in milliseconds) and uploaded. The brick BVH of the brick tracer is a different tree,
// built on the device (LBVH over the Morton-ordered leaf bricks).
//
// Layout: SdfBvhNode (kernels/sdf_types.h), nodes[0] is the root; child[i] >= 0 is a node index,
// child[i] < 0 is the leaf of box ~child[i] (one box per leaf). With a single box the root holds it
// as child 0 and child 1 is missing (an empty box, lo > hi, index 0: never entered). No boxes: no nodes.
//
// Build: recursive median split on the longest axis of the box centres, at half the boxes (rounded
// down), the boxes ordered by (centre on that axis, box index). That order is total, so the tree is
// the same on every platform and standard library (std::nth_element picks the same set of boxes for
// each half whatever its internal order). Depth <= ceil(log2 n) + 1.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "scene/scene.h"
#include "sdf_types.h"

namespace sdfbrick::reference {

struct EditBvh {
    std::vector<SdfBvhNode> nodes;
    int depth = 0;  // nodes on the longest root-to-leaf path (0 without boxes)
};

// The smallest float box that contains b (each bound rounded outward). Empty b -> an empty box.
SdfBounds to_float_box(const Aabb& b);

// Whether the closed box holds p (lo <= p <= hi on every axis); the kernel uses the same test.
bool contains(const SdfBounds& b, const glm::vec3& p);

// Throws std::invalid_argument for more than SDF_MAX_EDITS boxes or a box with a NaN bound.
EditBvh build_edit_bvh(std::span<const SdfBounds> boxes);

// Indices of the boxes that contain p, ascending, found through the tree (what the kernel does on
// the device). For tests and host tools.
std::vector<std::uint32_t> boxes_containing(const EditBvh& bvh, std::span<const SdfBounds> boxes, const glm::vec3& p);

}  // namespace sdfbrick::reference
