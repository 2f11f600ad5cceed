/* scan.cl: exclusive prefix sum of uint values, any length (host/construct/scan.h drives it).
 * Pass 1 (scan_blocks): each work-group scans a block of ITEMS * get_local_size(0) values, writes
 * the exclusive result and the block's total; scan_popcount_blocks does the same over the bit counts
 * of the words in[0, words), then zeros (the cull's kept entries per word, and their total). The
 * block totals are scanned the same way (recursion on the host) and pass 2 (scan_add) adds each
 * block's offset. Integer sums: the order of additions cannot change a result. A sum that wraps past
 * 2^32 sets *overflow (a constant store: its order does not matter). The local size must be a power
 * of two. */
#define ITEMS 4

/* The block scan of values v[i], i < n: in[i] (popcounts 0) or its bit count (1) for i < inputs, 0
 * beyond. */
inline void scan_block(__global const uint* in, uint inputs, int popcounts, __global uint* out, uint n,
                       __global uint* block_sums, __global uint* overflow, __local uint* partial) {
    const uint lid = get_local_id(0), wg = get_local_size(0);
    const uint base = (get_group_id(0) * wg + lid) * ITEMS;
    uint v[ITEMS];
    uint sum = 0;
    int wrapped = 0;
    for (uint i = 0; i < ITEMS; ++i) {
        v[i] = base + i < inputs ? (popcounts ? popcount(in[base + i]) : in[base + i]) : 0u;
        const uint s = sum + v[i];
        wrapped |= s < sum;
        sum = s;
    }
    partial[lid] = sum;
    barrier(CLK_LOCAL_MEM_FENCE);
    /* Hillis-Steele inclusive scan of the per-item sums. */
    for (uint offset = 1; offset < wg; offset <<= 1) {
        const uint add = lid >= offset ? partial[lid - offset] : 0u;
        barrier(CLK_LOCAL_MEM_FENCE);
        const uint s = partial[lid] + add;
        wrapped |= s < add;
        partial[lid] = s;
        barrier(CLK_LOCAL_MEM_FENCE);
    }
    uint running = lid > 0 ? partial[lid - 1] : 0u;
    for (uint i = 0; i < ITEMS; ++i) {
        if (base + i < n) out[base + i] = running;
        running += v[i];
    }
    if (lid == wg - 1) block_sums[get_group_id(0)] = partial[lid];
    if (wrapped) *overflow = 1u;
}

__kernel void scan_blocks(__global const uint* in, __global uint* out, uint n, __global uint* block_sums,
                          __global uint* overflow, __local uint* partial) {
    scan_block(in, n, 0, out, n, block_sums, overflow, partial);
}

__kernel void scan_popcount_blocks(__global const uint* in, uint words, __global uint* out, uint n,
                                   __global uint* block_sums, __global uint* overflow, __local uint* partial) {
    scan_block(in, words, 1, out, n, block_sums, overflow, partial);
}

__kernel void scan_add(__global uint* out, uint n, __global const uint* block_offsets, __global uint* overflow) {
    const uint block = get_group_id(0);
    const uint base = (block * get_local_size(0) + get_local_id(0)) * ITEMS;
    const uint add = block_offsets[block];
    for (uint i = 0; i < ITEMS; ++i) {
        if (base + i < n) {
            const uint s = out[base + i] + add;
            if (s < add) *overflow = 1u;
            out[base + i] = s;
        }
    }
}
