/* brick_apron.cl: stage "apron". The samples of a leaf brick that lie in a neighbour's interior are
 * evaluated once, by the neighbour, and copied (sdf_apron.h gives the regions):
 *   brick_keys (brick_order.cl): every leaf's Morton key (leaves are in key order);
 *   brick_owned:  per leaf, the regions it evaluates itself: its interior and every region whose
 *                 neighbour of the same level is not a leaf (a binary search per direction), and
 *                 the neighbours of the others;
 *   brick_evaluate (brick_evaluate.cl) evaluates those samples;
 *   brick_apron:  one work-group per leaf copies each region the leaf does not own from the
 *                 neighbour's interior (stored values: the neighbour quantised the same field at the same point
 *                 with the same band and scale, so the copy is the value the brick would store).
 * Compile-time: SAMPLES, APRON, FORMAT as brick_evaluate. */
#include "sdf_apron.h"
#include "sdf_format.h"
#include "sdf_morton.h"

#define NO_BRICK 0xFFFFFFFFu

/* The leaf of b's level at b's coord + d, or NO_BRICK. */
inline uint find_neighbour(__global const SdfBrick* bricks, __global const ulong* keys, uint count, SdfBrick b,
                           int3 d, uint finest, uint log2b) {
    const uint shift = (finest - b.level) * log2b;
    const int3 c = (int3)(b.coord[0], b.coord[1], b.coord[2]) + d;
    const uint limit = 1u << (21u - shift);
    if (c.x < 0 || c.y < 0 || c.z < 0 || (uint)c.x >= limit || (uint)c.y >= limit || (uint)c.z >= limit) return NO_BRICK;
    const ulong key = sdf_lattice_key(c, shift);
    uint lo = 0, hi = count;
    while (lo < hi) {
        const uint mid = lo + ((hi - lo) >> 1);
        if (keys[mid] < key) lo = mid + 1u; else hi = mid;
    }
    return lo < count && keys[lo] == key && bricks[lo].level == b.level ? lo : NO_BRICK;
}

/* Per leaf: the regions it owns, and the neighbour of every other region (neighbours[27 i + r]). A
 * leaf with fewer than share_edits edits owns everything: its samples cost less to evaluate than to
 * find. */
__kernel void brick_owned(__global const SdfBrick* bricks, __global const ulong* keys, uint count, uint finest, uint log2b,
                          uint share_edits, __global uint* owned, __global uint* neighbours) {
    const uint i = get_global_id(0);
    if (i >= count) return;
    const SdfBrick b = bricks[i];
    if (b.edit_count < share_edits) {
        owned[i] = APRON_ALL_REGIONS;
        return;
    }
    uint mask = 1u << APRON_INTERIOR_REGION;
    for (uint r = 0; r < 27u; ++r) {
        if (r == APRON_INTERIOR_REGION) continue;
        const uint n = find_neighbour(bricks, keys, count, b, apron_direction(r), finest, log2b);
        neighbours[(size_t)i * 27u + r] = n; /* the interior's entry stays unwritten and unread */
        if (n == NO_BRICK) mask |= 1u << r;
    }
    owned[i] = mask;
}

/* One work-group per leaf: each sample of a region the leaf does not own is copied from the same point
 * in the neighbour. */
__kernel void brick_apron(__global const uint* owned, __global const uint* neighbours, __global sample_t* pool) {
    const uint brick = get_group_id(0);
    const uint mask = owned[brick];
    if (mask == APRON_ALL_REGIONS) return; /* the same in every work-item */
    __local uint nb[27];
    for (uint r = get_local_id(0); r < 27u; r += get_local_size(0)) nb[r] = neighbours[(size_t)brick * 27u + r];
    barrier(CLK_LOCAL_MEM_FENCE);
    __global sample_t* out = pool + (size_t)brick * SAMPLE_COUNT;
    for (uint a = get_local_id(0); a < SAMPLE_COUNT; a += get_local_size(0)) {
        const int3 q = apron_sample(a);
        const uint r = apron_region_of(q);
        if ((mask >> r) & 1u) continue;
        const int3 d = apron_direction(r);
        const int shift = INTERIOR * (d.x + SAMPLES * (d.y + SAMPLES * d.z)); /* the same point in the neighbour */
        out[a] = pool[(size_t)nb[r] * SAMPLE_COUNT + (size_t)((int)a - shift)];
    }
}
