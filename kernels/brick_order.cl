/* brick_order.cl: stage "order" (adaptive builds). Leaves come from several levels; each level's are
 * in Morton order already, and the merged list must be too (the LBVH is built on it), with no sort:
 *   brick_split: a checked level's bricks -> its leaves (passed) and the next level's parents, both
 *                in their order (offsets: exclusive scan of passed); the parents from `counted`, the
 *                bricks with the next level's child masks where that count ran before the check;
 *   brick_keys:  each leaf's finest-level Morton key (of every level, concatenated level by level,
 *                level_first[m] the first of level m; the apron stage keys the merged leaves with it);
 *   brick_rank:  for each leaf, its position in the merged list = the leaves of every level whose key
 *                is smaller (keys are distinct because leaves are disjoint cells): in its own level
 *                its index there, in each other level a binary search over the keys;
 *   brick_place: each leaf to its position, its edit_offset moved by its level's list base (the
 *                levels' lists are concatenated too), and to `evaluated` with no edits when the check
 *                evaluated it (a level coarser than the finest): the leaf evaluation runs on those
 *                records, and brick_put puts the samples brick_keep kept in their places.
 * brick_keep and brick_put copy a brick's samples as `words` 32-bit words (any format). */
#include "sdf_morton.h"

__kernel void brick_split(__global const SdfBrick* bricks, __global const SdfBrick* counted, uint count,
                          __global const uint* passed, __global const uint* leaf_offsets, __global SdfBrick* leaves,
                          __global SdfBrick* parents) {
    const uint i = get_global_id(0);
    if (i >= count) return;
    const uint before = leaf_offsets[i];
    if (passed[i]) leaves[before] = bricks[i];
    else parents[i - before] = counted[i];
}

__kernel void brick_keys(__global const SdfBrick* bricks, uint count, uint finest, uint log2b, __global ulong* keys) {
    const uint i = get_global_id(0);
    if (i < count) keys[i] = sdf_brick_key(bricks[i], finest, log2b);
}

__kernel void brick_rank(__global const ulong* keys, __global const uint* level_first, uint level_count, uint total,
                         __global uint* positions) {
    const uint i = get_global_id(0);
    if (i >= total) return;
    const ulong key = keys[i];
    uint position = 0u;
    for (uint m = 0; m < level_count; ++m) {
        uint lo = level_first[m], hi = level_first[m + 1u];
        const uint first = lo;
        if (i >= lo && i < hi) lo = hi = i; /* its own level, sorted: the keys before it are smaller */
        while (lo < hi) {
            const uint mid = lo + ((hi - lo) >> 1);
            if (keys[mid] < key) lo = mid + 1u; else hi = mid;
        }
        position += lo - first;
    }
    positions[i] = position;
}

__kernel void brick_place(__global const SdfBrick* leaves, __global const uint* positions, uint total,
                          __global const uint* list_base, uint finest, __global SdfBrick* out,
                          __global SdfBrick* evaluated) {
    const uint i = get_global_id(0);
    if (i >= total) return;
    SdfBrick b = leaves[i];
    b.edit_offset += list_base[b.level];
    out[positions[i]] = b;
    if (b.level != finest) b.edit_count = 0u;
    evaluated[positions[i]] = b;
}

/* A checked level's passing bricks' samples, which the check evaluated, in leaf order (leaf_offsets:
 * the scan of passed). One work-group per checked brick. */
__kernel void brick_keep(__global const uint* samples, __global const uint* passed, __global const uint* leaf_offsets,
                         uint count, uint words, __global uint* kept) {
    const uint i = get_group_id(0);
    if (i >= count || !passed[i]) return;
    for (uint w = get_local_id(0); w < words; w += get_local_size(0))
        kept[(size_t)leaf_offsets[i] * words + w] = samples[(size_t)i * words + w];
}

/* A level's kept samples into the pool at its leaves' merged positions (brick_rank's, the level's
 * leaves from `first` on). One work-group per leaf. */
__kernel void brick_put(__global const uint* kept, __global const uint* positions, uint first, uint count, uint words,
                        __global uint* pool) {
    const uint j = get_group_id(0);
    if (j >= count) return;
    for (uint w = get_local_id(0); w < words; w += get_local_size(0))
        pool[(size_t)positions[first + j] * words + w] = kept[(size_t)j * words + w];
}
