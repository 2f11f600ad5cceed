/* Tree digests of device buffers (host twin: tree_digest in host/core/hash.h, docs/design.md).
 * A stream is, for each record r < records, bytes [first, first + take) of the record at
 * data + r * stride. Block i is records [i * per_block, (i + 1) * per_block); work-item i writes
 * the FNV-1a 64 of its block's bytes. The host launches the same kernel over those digests (records
 * of 8 bytes) until one is left. Integer arithmetic only: every device gives the same bits. */
#include "sdf_types.h"

#define FNV_BASIS 0xCBF29CE484222325UL
#define FNV_PRIME 0x100000001B3UL

ulong fnv_word(ulong h, uint w) {
    h = (h ^ (ulong)(w & 0xffu)) * FNV_PRIME;
    h = (h ^ (ulong)((w >> 8) & 0xffu)) * FNV_PRIME;
    h = (h ^ (ulong)((w >> 16) & 0xffu)) * FNV_PRIME;
    return (h ^ (ulong)(w >> 24)) * FNV_PRIME;
}

kernel void digest_blocks(global const uchar* data, ulong records, uint stride, uint first, uint take,
                          uint per_block, global ulong* out) {
    const ulong i = get_global_id(0);
    const ulong r0 = i * per_block;
    if (r0 >= records) return;
    const ulong r1 = min(r0 + (ulong)per_block, records);
    ulong h = FNV_BASIS;
    if (stride == take) {  /* contiguous: bytes [r0 * take, r1 * take) */
        ulong at = r0 * take, end = r1 * take;
        for (; at < end && (at & 3UL) != 0; ++at) h = (h ^ (ulong)data[at]) * FNV_PRIME;
        global const uint* words = (global const uint*)(data + at);
        const ulong n = (end - at) / 4;
        for (ulong k = 0; k < n; ++k) h = fnv_word(h, words[k]);
        for (at += 4 * n; at < end; ++at) h = (h ^ (ulong)data[at]) * FNV_PRIME;
    } else if (((stride | first | take) & 3u) == 0) {  /* whole words of each record */
        for (ulong r = r0; r < r1; ++r) {
            global const uint* words = (global const uint*)(data + r * stride + first);
            for (uint k = 0; k < take / 4; ++k) h = fnv_word(h, words[k]);
        }
    } else {
        for (ulong r = r0; r < r1; ++r)
            for (uint k = 0; k < take; ++k) h = (h ^ (ulong)data[r * stride + first + k]) * FNV_PRIME;
    }
    out[i] = h;
}

/* Per leaf, the FNV-1a 64 of its coordinate (12 bytes) and its edit list (4 bytes an entry). */
kernel void digest_lists(global const SdfBrick* leaves, uint count, global const uint* lists, global ulong* out) {
    const uint i = get_global_id(0);
    if (i >= count) return;
    const SdfBrick b = leaves[i];
    ulong h = FNV_BASIS;
    for (int a = 0; a < 3; ++a) h = fnv_word(h, (uint)b.coord[a]);
    for (uint k = 0; k < b.edit_count; ++k) h = fnv_word(h, lists[b.edit_offset + k]);
    out[i] = h;
}
