/* brick_stats.cl: the build report's work counters, reduced where the records are (nothing but the
 * partial sums crosses to the host). One fixed-size work-group shape (STATS_GROUP work-items, a
 * grid-stride loop); each work-group writes its partials, the host adds them up. Integer sums and
 * maxima only: the order of the reduction changes no value.
 *   level_stats: per level, the longest edit list and the sum of edit_count x kept children (the
 *                next level's cull tests);
 *   leaf_stats:  over the leaves, list entries, the longest list, the list entries' FLOPs, the
 *                evaluation's FLOPs and edit evaluations (FLOPs and evaluations x the samples each
 *                leaf evaluates: all of them, or its owned regions where leaves share aprons).
 * Compile-time: SAMPLES, APRON (sdf_apron.h). */
#include "sdf_types.h"
#include "sdf_apron.h"

#define STATS_GROUP 64

/* Reduces STATS_GROUP values of v in place: sum (max_op 0) or maximum (1); the result is in v[0]. */
void group_reduce(local ulong* v, int max_op) {
    const uint lid = get_local_id(0);
    for (uint stride = STATS_GROUP / 2; stride > 0; stride /= 2) {
        barrier(CLK_LOCAL_MEM_FENCE);
        if (lid < stride) v[lid] = max_op ? max(v[lid], v[lid + stride]) : v[lid] + v[lid + stride];
    }
    barrier(CLK_LOCAL_MEM_FENCE);
}

__attribute__((reqd_work_group_size(STATS_GROUP, 1, 1)))
kernel void level_stats(global const SdfBrick* bricks, uint count, global ulong* out, uint base) {
    local ulong longest[STATS_GROUP], tests[STATS_GROUP];
    const uint lid = get_local_id(0);
    ulong m = 0, t = 0;
    for (uint i = get_global_id(0); i < count; i += get_global_size(0)) {
        const SdfBrick b = bricks[i];
        m = max(m, (ulong)b.edit_count);
        t += (ulong)b.edit_count * (ulong)(popcount(b.child_mask[0]) + popcount(b.child_mask[1]));
    }
    longest[lid] = m;
    tests[lid] = t;
    group_reduce(longest, 1);
    group_reduce(tests, 0);
    if (lid == 0) {
        out[base + 2 * get_group_id(0)] = longest[0];
        out[base + 2 * get_group_id(0) + 1] = tests[0];
    }
}

__attribute__((reqd_work_group_size(STATS_GROUP, 1, 1)))
kernel void leaf_stats(global const SdfBrick* leaves, uint count, global const uint* lists,
                       global const uint* edit_flops, global const uint* owned, uint use_owned, global ulong* out,
                       uint base) {
    local ulong v[5][STATS_GROUP];
    const uint lid = get_local_id(0);
    ulong entries = 0, longest = 0, entry_flops = 0, flops = 0, evaluations = 0;
    for (uint i = get_global_id(0); i < count; i += get_global_size(0)) {
        const SdfBrick b = leaves[i];
        ulong f = 0;
        for (uint j = 0; j < b.edit_count; ++j) f += edit_flops[lists[b.edit_offset + j]];
        const ulong samples = use_owned ? apron_owned_count(owned[i]) : (ulong)(SAMPLES * SAMPLES * SAMPLES);
        entries += b.edit_count;
        longest = max(longest, (ulong)b.edit_count);
        entry_flops += f;
        flops += f * samples;
        evaluations += (ulong)b.edit_count * samples;
    }
    v[0][lid] = entries;
    v[1][lid] = longest;
    v[2][lid] = entry_flops;
    v[3][lid] = flops;
    v[4][lid] = evaluations;
    for (int k = 0; k < 5; ++k) group_reduce(v[k], k == 1);
    if (lid == 0)
        for (int k = 0; k < 5; ++k) out[base + 5 * get_group_id(0) + k] = v[k][0];
}
