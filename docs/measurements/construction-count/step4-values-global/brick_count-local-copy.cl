/* brick_count.cl: stage "count". One work-group per parent brick, one work-item per candidate child
 * (local size B^3). Each child's centre is tested against the parent's edit list, folded with its
 * running value saturated to [-saturation, saturation]:
 *   - saturation == C (the threshold is below C): the band-limited field itself; kept iff
 *     |F_C(centre)| <= threshold (half the child's diagonal plus a rounding margin);
 *   - saturation > C (a coarse level, whose threshold reaches C and where |F_C| <= C says nothing):
 *     the wider fold W, with excess bounding |F_C - clamp(W, -C, C)| over the child (see
 *     sdf_saturation_excess); kept iff |W(centre)| <= threshold + excess, or excess >= reject_slack
 *     (= C - the leaf threshold: then W cannot prove that no leaf below passes).
 * Either way every ancestor of a leaf that passes its test passes its own (docs/construction.md).
 * The root (the pseudo-parent's only child) is kept without a test where its level is wide: it is
 * the domain itself, one brick, and the long full edit list makes its test the slowest of all.
 * The parent's edits are staged through __local memory in chunks of chunk_size, with the terms of
 * their excess. Where a level has few parents (long lists, few work-groups: bound by latency), the
 * values of the edits at the children's centres, which do not depend on the fold, come first from
 * count_values, a work-item per (list entry, child); brick_count then only folds them, in list
 * order as before, so the bits do not change. Writes the parent's
 * child mask (bit = Morton index) and its child count. */
#include "sdf_build.h"

/* The parent whose list holds list entry `entry`: the last parent whose list starts at or before it
 * (parents' lists ascend; an entry in a gap between them is not one of its parent's). */
inline uint parent_of_entry(__global const SdfBrick* parents, uint count, uint entry) {
    uint lo = 0, hi = count;
    while (hi - lo > 1u) {
        const uint mid = lo + ((hi - lo) >> 1);
        if (parents[mid].edit_offset <= entry) lo = mid; else hi = mid;
    }
    return lo;
}

/* One work-item per (entry of the parents' lists, candidate child): the entry's edit value at the
 * child's centre, at values[entry * B^3 + child]. */
__kernel void count_values(__global const SdfEdit* edits, __global const float* meshes, __global const uint* edit_indices,
                           __global const SdfBrick* parents, uint parent_count, uint entries, uint log2b,
                           float origin_x, float origin_y, float origin_z, float child_cell,
                           __global float* values) {
    const uint gid = get_global_id(0), entry = gid >> (3u * log2b), child = gid & ((1u << (3u * log2b)) - 1u);
    if (entry >= entries) return;
    const SdfBrick b = parents[parent_of_entry(parents, parent_count, entry)];
    if (entry < b.edit_offset || entry - b.edit_offset >= b.edit_count) return;
    const int3 coord = (int3)(b.coord[0], b.coord[1], b.coord[2]) * (int)(1u << log2b) + sdf_morton_child(child, log2b);
    const float3 p = sdf_cell_centre((float3)(origin_x, origin_y, origin_z), child_cell, coord);
    const SdfPrepared e = sdf_prepare(edits[edit_indices[entry]]);
    values[gid] = sdf_prepared_value(&e, meshes, p);
}

/* given: whether count_values computed the values (given_values; staged in values with the chunk);
 * else the fold computes them. */
__kernel void brick_count(__global const SdfEdit* edits, __global const float* meshes, __global const uint* edit_indices,
                          __global SdfBrick* parents, uint log2b,
                          float origin_x, float origin_y, float origin_z, float child_cell,
                          float threshold, float clamp_c, float saturation, float reject_slack,
                          float magnitude, uint given, __global const float* given_values,
                          __global uint* child_counts,
                          __local SdfPrepared* chunk, __local float4* terms, uint chunk_size,
                          __local float* values, __local uint* kept) {
    const uint parent = get_group_id(0);
    const uint lid = get_local_id(0), wg = get_local_size(0);
    const SdfBrick b = parents[parent];
    const int3 coord = (int3)(b.coord[0], b.coord[1], b.coord[2]) * (int)(1u << log2b) + sdf_morton_child(lid, log2b);
    const float3 p = sdf_cell_centre((float3)(origin_x, origin_y, origin_z), child_cell, coord);
    const int wide = saturation > clamp_c;
    const int keep_root = wide && b.level == 0xffffffffu;
    const uint edit_count = keep_root ? 0u : b.edit_count;
    float field = saturation, excess = 0.0f;
    for (uint base = 0; base < edit_count; base += chunk_size) {
        const uint n = min(chunk_size, edit_count - base);
        barrier(CLK_LOCAL_MEM_FENCE);
        for (uint j = lid; j < n; j += wg) {
            const SdfPrepared e = sdf_prepare(edits[edit_indices[b.edit_offset + base + j]]);
            chunk[j] = e;
            terms[j] = sdf_excess_terms(&e, clamp_c, saturation, threshold, magnitude);
        }
        if (given) { /* the chunk's values: entries base.. of the parent's list, B^3 each, in a row */
            __global const float* run = given_values + (size_t)(b.edit_offset + base) * wg;
            const uint total = n * wg;
            for (uint k0 = lid; k0 < total; k0 += 8u * wg) { /* eight loads in flight */
                float x[8];
                for (uint u = 0; u < 8u; ++u) x[u] = k0 + u * wg < total ? run[k0 + u * wg] : 0.0f;
                for (uint u = 0; u < 8u; ++u)
                    if (k0 + u * wg < total) values[k0 + u * wg] = x[u];
            }
        }
        barrier(CLK_LOCAL_MEM_FENCE);
        /* saturation is C where not wide. */
        if (given) {
#pragma unroll 4
            for (uint j = 0; j < n; ++j) {
                const SdfPrepared e = chunk[j]; /* OpenCL 1.2 has no generic address space */
                const float v = values[j * wg + lid];
                if (wide) excess += sdf_saturation_excess(terms[j], v);
                field = fmin(fmax(sdf_combine(&e, field, v), -saturation), saturation);
            }
        } else {
            /* Unrolled, the values overlap. */
#pragma unroll 4
            for (uint j = 0; j < n; ++j) {
                const SdfPrepared e = chunk[j];
                const float v = sdf_prepared_value(&e, meshes, p);
                if (wide) excess += sdf_saturation_excess(terms[j], v);
                field = fmin(fmax(sdf_combine(&e, field, v), -saturation), saturation);
            }
        }
    }
    kept[lid] = keep_root || (wide ? fabs(field) <= threshold + excess || excess >= reject_slack
                                   : fabs(field) <= threshold) ? 1u : 0u;
    barrier(CLK_LOCAL_MEM_FENCE);
    if (lid == 0) {
        uint mask[2] = {0u, 0u}, count = 0;
        for (uint i = 0; i < wg; ++i) {
            if (kept[i]) {
                mask[i >> 5] |= 1u << (i & 31u);
                ++count;
            }
        }
        parents[parent].child_mask[0] = mask[0];
        parents[parent].child_mask[1] = mask[1];
        child_counts[parent] = count;
    }
}
