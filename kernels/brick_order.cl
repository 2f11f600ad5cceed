/* brick_order.cl: stage "order" (adaptive builds). Leaves come from several levels; each level's are
 * in Morton order already, and the merged list must be too (the LBVH is built on it), with no sort:
 *   brick_split: a checked level's bricks -> its leaves (passed) and the next level's parents, both
 *                in their order (offsets: exclusive scan of passed);
 *   brick_rank:  for each leaf of every level (concatenated level by level, level_first[m] the first
 *                of level m), its position in the merged list = the leaves of every level whose
 *                finest-level Morton key is smaller (a binary search per level; keys are distinct
 *                because leaves are disjoint cells);
 *   brick_place: each leaf to its position, its edit_offset moved by its level's list base (the
 *                levels' lists are concatenated too). */
#include "sdf_morton.h"

__kernel void brick_split(__global const SdfBrick* bricks, uint count, __global const uint* passed,
                          __global const uint* leaf_offsets, __global SdfBrick* leaves, __global SdfBrick* parents) {
    const uint i = get_global_id(0);
    if (i >= count) return;
    const uint before = leaf_offsets[i];
    if (passed[i]) leaves[before] = bricks[i];
    else parents[i - before] = bricks[i];
}

__kernel void brick_rank(__global const SdfBrick* leaves, __global const uint* level_first, uint level_count,
                         uint total, uint finest, uint log2b, __global uint* positions) {
    const uint i = get_global_id(0);
    if (i >= total) return;
    const ulong key = sdf_brick_key(leaves[i], finest, log2b);
    uint position = 0u;
    for (uint m = 0; m < level_count; ++m) {
        uint lo = level_first[m], hi = level_first[m + 1u];
        const uint first = lo;
        while (lo < hi) {
            const uint mid = lo + ((hi - lo) >> 1);
            if (sdf_brick_key(leaves[mid], finest, log2b) < key) lo = mid + 1u; else hi = mid;
        }
        position += lo - first;
    }
    positions[i] = position;
}

__kernel void brick_place(__global const SdfBrick* leaves, __global const uint* positions, uint total,
                          __global const uint* list_base, __global SdfBrick* out) {
    const uint i = get_global_id(0);
    if (i >= total) return;
    SdfBrick b = leaves[i];
    b.edit_offset += list_base[b.level];
    out[positions[i]] = b;
}
