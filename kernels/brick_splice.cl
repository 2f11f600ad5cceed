/* brick_splice.cl: stage "splice" (a rebuild after an edit change, construct/build_splice.cpp). The
 * new build's leaves are runs of the earlier build's leaves (the subtrees the change cannot reach)
 * and the leaves built again, merged in Morton order. A run is a segment: its first output leaf, its
 * first source leaf, and whether that source is the earlier build (0) or the new part (1); segments
 * are ordered by first output leaf and the last is a sentinel holding the total.
 *   splice_counts: each output leaf's list length  -> scan -> its list offset;
 *   splice_leaves: one work-group per output leaf: its record (with its new list offset), box, shift,
 *                  samples and list; entries of the earlier build's lists above a removed edit move
 *                  down by the removed edits below them (removed: ascending old indices). */
#include "sdf_types.h"

/* The segment holding output leaf i: the last whose first output leaf is <= i. */
inline uint splice_segment(__global const uint4* segments, uint count, uint i) {
    uint lo = 0, hi = count;
    while (hi - lo > 1u) {
        const uint mid = lo + ((hi - lo) >> 1);
        if (segments[mid].x <= i) lo = mid; else hi = mid;
    }
    return lo;
}

__kernel void splice_counts(__global const SdfBrick* old_leaves, __global const SdfBrick* new_leaves,
                            __global const uint4* segments, uint segment_count, uint total, __global uint* counts) {
    const uint i = get_global_id(0);
    if (i >= total) return;
    const uint4 s = segments[splice_segment(segments, segment_count, i)];
    const uint source = s.y + (i - s.x);
    counts[i] = s.z ? new_leaves[source].edit_count : old_leaves[source].edit_count;
}

__kernel void splice_leaves(__global const SdfBrick* old_leaves, __global const SdfBrick* new_leaves,
                            __global const uint* old_lists, __global const uint* new_lists,
                            __global const uchar* old_pool, __global const uchar* new_pool,
                            __global const SdfBounds* old_boxes, __global const SdfBounds* new_boxes,
                            __global const uint* old_shifts, __global const uint* new_shifts,
                            __global const uint4* segments, uint segment_count,
                            __global const uint* offsets, __global const uint* removed, uint removed_count,
                            uint brick_bytes, __global SdfBrick* leaves, __global uint* lists, __global uchar* pool,
                            __global SdfBounds* boxes, __global uint* shifts) {
    const uint i = get_group_id(0), t = get_local_id(0), n = get_local_size(0);
    const uint4 s = segments[splice_segment(segments, segment_count, i)];
    const uint source = s.y + (i - s.x);
    const int fresh = s.z != 0u;
    SdfBrick b = fresh ? new_leaves[source] : old_leaves[source];
    __global const uint* list = (fresh ? new_lists : old_lists) + b.edit_offset;
    const uint offset = offsets[i];
    for (uint j = t; j < b.edit_count; j += n) {
        uint e = list[j];
        if (!fresh && removed_count > 0u) {
            uint lo = 0, hi = removed_count; /* removed edits below e */
            while (lo < hi) {
                const uint mid = lo + ((hi - lo) >> 1);
                if (removed[mid] < e) lo = mid + 1u; else hi = mid;
            }
            e -= lo;
        }
        lists[offset + j] = e;
    }
    __global const uchar* samples = (fresh ? new_pool : old_pool) + (ulong)source * brick_bytes;
    __global uchar* target = pool + (ulong)i * brick_bytes;
    for (uint j = t; j < brick_bytes; j += n) target[j] = samples[j];
    if (t == 0u) {
        b.edit_offset = offset;
        leaves[i] = b;
        boxes[i] = fresh ? new_boxes[source] : old_boxes[source];
        shifts[i] = fresh ? new_shifts[source] : old_shifts[source];
    }
}
