/* trace_counts.cl: the brick tracer's per-pixel counters (aux.y: node visits, in-brick steps, the
 * SDF_TRACE_CAPPED flag; kernels/trace.cl) summed where they are, so that a report needs no image
 * on the host. Pixels [first, first + count); each of the work-groups (COUNTS_GROUP work-items, a
 * grid-stride loop) writes its three sums at out[3 g ...]; the host adds them up. Integer sums: the
 * order changes nothing. */
#include "sdf_types.h"

#define COUNTS_GROUP 64

__attribute__((reqd_work_group_size(COUNTS_GROUP, 1, 1)))
kernel void trace_counts(global const uint2* aux, uint first, uint count, global ulong* out) {
    local ulong v[3][COUNTS_GROUP];
    const uint lid = get_local_id(0);
    ulong visits = 0, steps = 0, capped = 0;
    for (uint i = get_global_id(0); i < count; i += get_global_size(0)) {
        const uint a = aux[first + i].y;
        visits += a & 0xFFFFu;
        steps += (a >> 16) & 0x7FFFu;
        capped += (a & SDF_TRACE_CAPPED) != 0u ? 1 : 0;
    }
    v[0][lid] = visits;
    v[1][lid] = steps;
    v[2][lid] = capped;
    for (uint stride = COUNTS_GROUP / 2; stride > 0; stride /= 2) {
        barrier(CLK_LOCAL_MEM_FENCE);
        if (lid < stride)
            for (int k = 0; k < 3; ++k) v[k][lid] += v[k][lid + stride];
    }
    barrier(CLK_LOCAL_MEM_FENCE);
    if (lid == 0)
        for (int k = 0; k < 3; ++k) out[3 * get_group_id(0) + k] = v[k][0];
}
