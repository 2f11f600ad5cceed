/* brick_apron.cl: stage "apron". The samples of a leaf brick that lie in a neighbour's interior are
 * evaluated once, by the neighbour, and copied (sdf_apron.h gives the regions):
 *   brick_keys:   every leaf's Morton key (leaves are in key order);
 *   brick_owned:  per leaf, the regions it evaluates itself: its interior and every region whose
 *                 neighbour of the same level is not a leaf (a binary search per direction);
 *   brick_evaluate (brick_evaluate.cl) evaluates those samples;
 *   brick_apron:  one work-item per leaf and region copies each region the leaf does not own from
 *                 the neighbour's interior (stored values: the neighbour quantised the same field at the same point
 *                 with the same band and scale, so the copy is the value the brick would store).
 * Compile-time: SAMPLES, APRON, FORMAT as brick_evaluate. */
#include "sdf_apron.h"
#include "sdf_format.h"
#include "sdf_morton.h"

#define NO_BRICK 0xFFFFFFFFu

__kernel void brick_keys(__global const SdfBrick* bricks, uint count, uint finest, uint log2b, __global ulong* keys) {
    const uint i = get_global_id(0);
    if (i < count) keys[i] = sdf_brick_key(bricks[i], finest, log2b);
}

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

__kernel void brick_owned(__global const SdfBrick* bricks, __global const ulong* keys, uint count, uint finest, uint log2b,
                          __global uint* owned) {
    const uint i = get_global_id(0);
    if (i >= count) return;
    const SdfBrick b = bricks[i];
    uint mask = 1u << APRON_INTERIOR_REGION;
    for (uint r = 0; r < 27u; ++r)
        if (r != APRON_INTERIOR_REGION && find_neighbour(bricks, keys, count, b, apron_direction(r), finest, log2b) == NO_BRICK)
            mask |= 1u << r;
    owned[i] = mask;
}

/* One work-item per brick and region (32 per brick, 27 used): a region the brick does not own is
 * copied from the neighbour in its direction. */
__kernel void brick_apron(__global const SdfBrick* bricks, __global const ulong* keys, __global const uint* owned,
                          uint count, uint finest, uint log2b, __global sample_t* pool) {
    const uint brick = get_global_id(0) >> 5, r = get_global_id(0) & 31u;
    if (brick >= count || r >= 27u || (owned[brick] >> r) & 1u) return;
    const int3 d = apron_direction(r);
    const uint n = find_neighbour(bricks, keys, count, bricks[brick], d, finest, log2b);
    __global sample_t* out = pool + (size_t)brick * SAMPLE_COUNT;
    __global const sample_t* in = pool + (size_t)n * SAMPLE_COUNT;
    const int3 first = (int3)(apron_first(d.x + 1), apron_first(d.y + 1), apron_first(d.z + 1));
    const int3 end = first + (int3)(APRON_EXTENT(d.x + 1), APRON_EXTENT(d.y + 1), APRON_EXTENT(d.z + 1));
    const int shift = d.x * INTERIOR + SAMPLES * (d.y * INTERIOR + SAMPLES * d.z * INTERIOR); /* the same point in n */
    for (int k = first.z; k < end.z; ++k)
        for (int j = first.y; j < end.y; ++j)
            for (int i = first.x; i < end.x; ++i) {
                const int a = i + SAMPLES * (j + SAMPLES * k);
                out[a] = in[a - shift];
            }
}
