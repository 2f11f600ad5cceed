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
 * A parent whose list has at least untested_from edits keeps every child without a test (the host
 * sets it where the level is wide and cannot hold leaf candidates: 0 for the root, the
 * pseudo-parent's only child, and on GPUs for the root's children; on GPUs a long list's length
 * below them; else never): the root is the domain itself, and on a GPU a long list's serial fold
 * per child is the slowest test of all, while culling the extra children's lists is parallel work.
 * A child kept that holds no surface keeps none of its own children at the next level's test, so
 * the leaves are the same.
 * The parent's edits are staged through __local memory in chunks of chunk_size, with the terms of
 * their excess and their combine as data (sdf_fold_params: the fold has no branch per edit), except
 * with one lane (GPUs) at a level that is not wide and one work-item per child: there a sphere or
 * capsule edit carries its radial offset instead, and one that cannot change the child's running
 * value is skipped (on an H100 sculpt_dense's count 2.33 -> 2.23 ms, rubble's 0.325 -> 0.303). Where
 * a level has few parents (long lists, few work-groups: bound by latency), the work-group has
 * `parts` work-items per child: they compute the edits' values at the child's centre (which do not
 * depend on the fold) in turn into __local values, and the first folds them in list order, so the
 * bits do not depend on parts. Where even that leaves the level short of work-items (a work-group
 * holds at most the kernel's limit), a parent's children are split over `splits` work-groups
 * (group = parent * splits + split, children split * per .. split * per + per - 1, per = B^3 / splits),
 * each staging the whole list. Writes the parent's child mask (bit = Morton index) and its child
 * count; split work-groups write their part to split_words (mask words, count), which
 * brick_count_merge adds up. */
#include "sdf_build.h"

/* One step of the fold: edit (terms, fold) of value v (one per lane). saturation is C where not wide. */
inline void fold_step(sdf_real* field, sdf_real* excess, float4 terms, float4 fold, sdf_real v, int wide,
                      float saturation) {
    if (wide) *excess += sdf_saturation_excess(terms, v);
    *field = fmin(fmax(sdf_fold_select(fold, *field, v), -saturation), saturation);
}

/* Stages edits base .. base + n - 1 of the parent's list (prepared: edit_prepare.cl) with their excess
 * terms and fold parameters. */
inline void stage_edits(__global const SdfPrepared* edits, __global const uint* list, uint n, uint lid, uint wg,
                        __local SdfPrepared* chunk, __local float4* terms, __local float4* folds, float clamp_c,
                        float saturation, float threshold, float magnitude) {
    for (uint j = lid; j < n; j += wg) {
        const SdfPrepared e = edits[list[j]];
        chunk[j] = e;
        folds[j] = sdf_fold_params(&e);
#if SDF_LANES == 1
        if (!(saturation > clamp_c)) { /* not wide: no excess; terms[j].x is the radial offset (below) or -1 */
            const uint prim = e.kind & 0xffu, op = (e.kind >> 8) & 0xffu;
            const int radial = (prim == SDF_PRIM_SPHERE || prim == SDF_PRIM_CAPSULE) && (op == SDF_OP_ADD || op == SDF_OP_SUBTRACT);
            terms[j] = (float4)(radial ? sdf_radial_offset(&e, prim, saturation) : -1.0f, 0.0f, 0.0f, 0.0f);
            continue;
        }
#endif
        terms[j] = sdf_excess_terms(&e, clamp_c, saturation, threshold, magnitude);
    }
}

/* Whether the fold keeps a child (see above). */
inline sdf_index child_kept(sdf_real field, sdf_real excess, int wide, float threshold, float reject_slack) {
    return wide ? (fabs(field) <= threshold + excess) | (excess >= reject_slack) : fabs(field) <= threshold;
}

/* After kept[0 .. per) is written: the work-group's child mask and count, written by its first
 * work-item (the parent's, or the split's part of it in split_words). */
inline void write_mask(__local const uint* kept, uint per, uint split, uint splits, uint parent, uint group,
                       __global SdfBrick* parents, __global uint* child_counts, __global uint* split_words) {
    uint mask[2] = {0u, 0u}, count = 0;
    for (uint i = 0; i < per; ++i) {
        if (kept[i]) {
            const uint c = split * per + i;
            mask[c >> 5] |= 1u << (c & 31u);
            ++count;
        }
    }
    if (splits == 1u) {
        parents[parent].child_mask[0] = mask[0];
        parents[parent].child_mask[1] = mask[1];
        child_counts[parent] = count;
    } else {
        split_words[3u * group] = mask[0];
        split_words[3u * group + 1u] = mask[1];
        split_words[3u * group + 2u] = count;
    }
}

/* The centre of child `child` of parent b. */
inline float3 child_centre(SdfBrick b, uint child, uint log2b, float3 origin, float child_cell) {
    const int3 coord = (int3)(b.coord[0], b.coord[1], b.coord[2]) * (int)(1u << log2b) + sdf_morton_child(child, log2b);
    return sdf_cell_centre(origin, child_cell, coord);
}

/* With SDF_LANES > 1 (CPU devices) each work-item folds SDF_LANES children at once: lane l holds child
 * lid * SDF_LANES + l of the work-group's `per` (lanes past the last repeat it and are not written);
 * the work-group has ceil(per / SDF_LANES) work-items and no parts (`values` is unused). Every lane
 * does the one-lane fold's operations in the same order: the same bits. With one child a work-item,
 * PoCL ran the fold at a sixth of the evaluation's rate per edit (docs/performance.md). */
__kernel void brick_count(__global const SdfPrepared* edits, __global const float* meshes, __global const uint* edit_indices,
                          __global SdfBrick* parents, uint log2b,
                          float origin_x, float origin_y, float origin_z, float child_cell,
                          float threshold, float clamp_c, float saturation, float reject_slack,
                          float magnitude, uint untested_from,
                          __global uint* child_counts, uint splits, __global uint* split_words,
                          __local SdfPrepared* chunk, __local float4* terms, __local float4* folds, uint chunk_size,
                          __local float* values, __local uint* kept) {
    const uint group = get_group_id(0), parent = group / splits, split = group % splits;
    const uint lid = get_local_id(0), wg = get_local_size(0);
    const uint per = (1u << (3u * log2b)) / splits; /* children of this work-group */
    const SdfBrick b = parents[parent];
    const float3 origin = (float3)(origin_x, origin_y, origin_z);
#if SDF_LANES == 1
    const uint mine = lid % per, child = split * per + mine;
    const uint part = lid / per, parts = wg / per;
    const float3 p = child_centre(b, child, log2b, origin, child_cell);
#else
    float x[SDF_LANES], y[SDF_LANES], z[SDF_LANES];
    for (uint l = 0; l < SDF_LANES; ++l) {
        const float3 c = child_centre(b, split * per + min(lid * SDF_LANES + l, per - 1u), log2b, origin, child_cell);
        x[l] = c.x;
        y[l] = c.y;
        z[l] = c.z;
    }
    const sdf_real px = SDF_REAL_CAT(vload, SDF_LANES)(0, x), py = SDF_REAL_CAT(vload, SDF_LANES)(0, y),
                   pz = SDF_REAL_CAT(vload, SDF_LANES)(0, z);
#endif
    const int wide = saturation > clamp_c;
    const int keep_all = b.edit_count >= untested_from;
    const uint edit_count = keep_all ? 0u : b.edit_count;
    sdf_real field = SDF_SPLAT(saturation), excess = SDF_SPLAT(0.0f);
    for (uint base = 0; base < edit_count; base += chunk_size) {
        const uint n = min(chunk_size, edit_count - base);
        barrier(CLK_LOCAL_MEM_FENCE);
        stage_edits(edits, edit_indices + b.edit_offset + base, n, lid, wg, chunk, terms, folds, clamp_c, saturation,
                    threshold, magnitude);
        barrier(CLK_LOCAL_MEM_FENCE);
#if SDF_LANES == 1
        if (parts == 1u && !wide) {
            /* A sphere or capsule edit whose surface lies beyond the running value's reach cannot
             * change it and is not folded (sdf_fold_radial, as in brick_evaluate: the same bits). */
            for (uint j = 0; j < n; ++j) {
                const SdfPrepared e = chunk[j];
                const float offset = terms[j].x;
                if (offset >= 0.0f)
                    field = sdf_fold_radial(&e, e.kind & 0xffu, (e.kind >> 8) & 0xffu, 0, 0, field, p.x, p.y, p.z, saturation, offset);
                else
                    fold_step(&field, &excess, terms[j], folds[j], sdf_prepared_value(&e, meshes, p), 0, saturation);
            }
        } else if (parts == 1u) {
            /* Unrolled, the values overlap. */
#pragma unroll 4
            for (uint j = 0; j < n; ++j) {
                const SdfPrepared e = chunk[j]; /* OpenCL 1.2 has no generic address space */
                fold_step(&field, &excess, terms[j], folds[j], sdf_prepared_value(&e, meshes, p), wide, saturation);
            }
        } else {
            for (uint j = part; j < n; j += parts) {
                const SdfPrepared e = chunk[j];
                values[j * per + mine] = sdf_prepared_value(&e, meshes, p);
            }
            barrier(CLK_LOCAL_MEM_FENCE);
            if (part == 0u) {
#pragma unroll 4
                for (uint j = 0; j < n; ++j) {
                    fold_step(&field, &excess, terms[j], folds[j], values[j * per + mine], wide, saturation);
                }
            }
        }
#else
        for (uint j = 0; j < n; ++j) {
            const SdfPrepared e = chunk[j];
            fold_step(&field, &excess, terms[j], folds[j], sdf_edit_value(&e, meshes, px, py, pz), wide, saturation);
        }
#endif
    }
#if SDF_LANES == 1
    if (part == 0u) kept[mine] = keep_all || child_kept(field, excess, wide, threshold, reject_slack) ? 1u : 0u;
#else
    int k[SDF_LANES];
    SDF_REAL_CAT(vstore, SDF_LANES)(child_kept(field, excess, wide, threshold, reject_slack), 0, k);
    for (uint l = 0; l < SDF_LANES && lid * SDF_LANES + l < per; ++l) kept[lid * SDF_LANES + l] = keep_all || k[l] ? 1u : 0u;
#endif
    barrier(CLK_LOCAL_MEM_FENCE);
    if (lid == 0) write_mask(kept, per, split, splits, parent, group, parents, child_counts, split_words);
}

/* After a split count: each parent's mask and count from its work-groups' parts (bits of different
 * children, so the or and the sum give what one work-group writes). */
__kernel void brick_count_merge(__global SdfBrick* parents, uint parent_count, uint splits,
                                __global const uint* split_words, __global uint* child_counts) {
    const uint parent = get_global_id(0);
    if (parent >= parent_count) return;
    uint mask[2] = {0u, 0u}, count = 0;
    for (uint s = 0; s < splits; ++s) {
        __global const uint* w = split_words + 3u * (parent * splits + s);
        mask[0] |= w[0];
        mask[1] |= w[1];
        count += w[2];
    }
    parents[parent].child_mask[0] = mask[0];
    parents[parent].child_mask[1] = mask[1];
    child_counts[parent] = count;
}

/* The child counts of parents whose masks are final already (the count ran before their level's
 * check, AdaptiveLeaves::check_and_split): the bits of each mask. */
__kernel void brick_mask_counts(__global const SdfBrick* parents, uint parent_count, __global uint* child_counts) {
    const uint parent = get_global_id(0);
    if (parent >= parent_count) return;
    const SdfBrick b = parents[parent];
    child_counts[parent] = popcount(b.child_mask[0]) + popcount(b.child_mask[1]);
}
