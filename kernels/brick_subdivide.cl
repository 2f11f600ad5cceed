/* brick_subdivide.cl: stage "subdivide". One work-item per candidate child (parent * B^3 + Morton
 * index). A kept child goes to slot offsets[parent] + (kept siblings before it), so children follow
 * their parents' order and Morton order inside each parent: the array stays Morton-ordered without a
 * sort. A child starts with its parent's edit list; "cull" refines it, from a bit set of `words`
 * words per child, written here. */
#include "sdf_build.h"

__kernel void brick_subdivide(__global const SdfBrick* parents, uint parent_count, uint log2b,
                              __global const uint* offsets, __global SdfBrick* children, __global uint* words) {
    const uint gid = get_global_id(0);
    const uint per_parent = 1u << (3u * log2b);
    const uint parent = gid >> (3u * log2b);
    if (parent >= parent_count) return;
    const uint i = gid & (per_parent - 1u);
    const SdfBrick b = parents[parent];
    const uint word = b.child_mask[i >> 5], bit = 1u << (i & 31u);
    if (!(word & bit)) return;
    const uint before = (i >= 32u ? popcount(b.child_mask[0]) : 0u) + popcount(word & (bit - 1u));
    const int3 coord = (int3)(b.coord[0], b.coord[1], b.coord[2]) * (int)(1u << log2b) + sdf_morton_child(i, log2b);
    SdfBrick c;
    c.coord[0] = coord.x;
    c.coord[1] = coord.y;
    c.coord[2] = coord.z;
    c.level = b.level + 1u;
    c.edit_offset = b.edit_offset;
    c.edit_count = b.edit_count;
    c.child_mask[0] = 0u;
    c.child_mask[1] = 0u;
    children[offsets[parent] + before] = c;
    words[offsets[parent] + before] = (b.edit_count + 31u) >> 5;
}
