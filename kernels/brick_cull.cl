/* brick_cull.cl: stage "cull". Refines each new brick's edit list (inherited from its parent) to the
 * edits that may change the band-limited field anywhere the brick's descendants will test or sample:
 * within radius of the brick's centre (half its diagonal plus the sample apron). With dependencies
 * on, every edit that a kept smooth edit depends on (and that the parent's list holds) is kept too.
 * Lists stay unique and ascending: a bit per parent-list entry, then compaction.
 *   cull_words: words of the bit set per brick  -> scan -> word offsets
 *   cull_mark:  the bit set and the kept count  -> scan -> list offsets
 *   cull_write: the compacted list; the brick's edit_offset / edit_count now name it */
#include "sdf_build.h"

__kernel void cull_words(__global const SdfBrick* bricks, uint count, __global uint* words) {
    const uint i = get_global_id(0);
    if (i < count) words[i] = (bricks[i].edit_count + 31u) >> 5;
}

/* Position of value in the ascending list[0, n), or n when absent. */
inline uint find_sorted(__global const uint* list, uint n, uint value) {
    uint lo = 0, hi = n;
    while (lo < hi) {
        const uint mid = lo + ((hi - lo) >> 1);
        if (list[mid] < value) lo = mid + 1u; else hi = mid;
    }
    return lo < n && list[lo] == value ? lo : n;
}

__kernel void cull_mark(__global const SdfEdit* edits, __global const uint* parent_indices,
                        __global const SdfBrick* bricks, uint count,
                        float origin_x, float origin_y, float origin_z, float cell,
                        float radius, float clamp_c, float magnitude,
                        __global const uint* word_offsets, __global uint* bits,
                        uint use_dependencies, __global const uint* dep_offsets, __global const uint* dep_indices,
                        __global uint* kept_counts) {
    const uint i = get_global_id(0);
    if (i >= count) return;
    const SdfBrick b = bricks[i];
    const float3 c = sdf_cell_centre((float3)(origin_x, origin_y, origin_z), cell,
                                     (int3)(b.coord[0], b.coord[1], b.coord[2]));
    __global const uint* list = parent_indices + b.edit_offset;
    __global uint* mask = bits + word_offsets[i];
    const uint words = (b.edit_count + 31u) >> 5;
    for (uint w = 0; w < words; ++w) {
        uint word = 0;
        const uint end = min(b.edit_count, (w + 1u) << 5);
        for (uint j = w << 5; j < end; ++j) {
            const SdfEdit e = edits[list[j]];
            if (sdf_edit_reaches(&e, sdf_edit_value(&e, c), clamp_c, radius, magnitude)) word |= 1u << (j & 31u);
        }
        mask[w] = word;
    }
    if (use_dependencies) {
        /* Only edits kept by the test above pull in their dependencies (no closure). */
        for (uint w = 0; w < words; ++w) {
            uint word = mask[w];
            while (word != 0u) {
                const uint j = (w << 5) + (31u - clz(word & (0u - word)));
                word &= word - 1u;
                const uint edit = list[j];
                if (!(edits[edit].blend > 0.0f)) continue;
                for (uint d = dep_offsets[edit]; d < dep_offsets[edit + 1u]; ++d) {
                    const uint q = find_sorted(list, b.edit_count, dep_indices[d]);
                    if (q < b.edit_count) mask[q >> 5] |= 1u << (q & 31u);
                }
            }
        }
    }
    uint kept = 0;
    for (uint w = 0; w < words; ++w) kept += popcount(mask[w]);
    kept_counts[i] = kept;
}

__kernel void cull_write(__global const uint* parent_indices, __global SdfBrick* bricks, uint count,
                         __global const uint* word_offsets, __global const uint* bits,
                         __global const uint* list_offsets, __global uint* indices) {
    const uint i = get_global_id(0);
    if (i >= count) return;
    const SdfBrick b = bricks[i];
    __global const uint* list = parent_indices + b.edit_offset;
    __global const uint* mask = bits + word_offsets[i];
    uint out = list_offsets[i];
    const uint words = (b.edit_count + 31u) >> 5;
    for (uint w = 0; w < words; ++w) {
        uint word = mask[w];
        while (word != 0u) {
            const uint j = (w << 5) + (31u - clz(word & (0u - word)));
            word &= word - 1u;
            indices[out++] = list[j];
        }
    }
    bricks[i].edit_count = out - list_offsets[i];
    bricks[i].edit_offset = list_offsets[i];
}
