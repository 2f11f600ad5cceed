/* edit_prepare.cl: every edit of a build in the form the folds read (SdfPrepared, sdf_prepare in
 * sdf_edit.h), once per build. The evaluation, the check, the count and the cull stage their lists
 * from these: preparing an edit takes two correctly rounded divisions, which they did once per brick
 * and staged chunk while the work-group waited at the barrier (an H100: drops' build at 0.0625 3.71
 * ms with them against 3.58 without; docs/performance.md). Same values, so the same bits. */
#include "sdf_build.h"

/* reaches: each edit's sdf_edit_reach, so that the cull stages need the prepared edit alone. */
__kernel void edit_prepare(__global const SdfEdit* edits, uint count, __global SdfPrepared* prepared,
                           __global float* reaches) {
    const uint i = get_global_id(0);
    if (i >= count) return;
    const SdfEdit e = edits[i];
    prepared[i] = sdf_prepare(e);
    reaches[i] = sdf_edit_reach(&e);
}
