/* sdf_apron.h: which samples of a leaf brick the brick evaluates itself (kernel side only; needs
 * SAMPLES and APRON, as brick_evaluate.cl).
 *
 * A brick's S^3 samples fall into 27 regions, one per direction d in {-1, 0, 1}^3: on each axis d = -1
 * covers samples [0, APRON), 0 the interior [APRON, S - APRON) and +1 [S - APRON, S). Region
 * r = (dx + 1) + 3 (dy + 1) + 9 (dz + 1); region 13 (d = 0) is the brick's interior. Every other
 * region lies inside the interior of the brick at coord + d of the same level, if there is one: that
 * brick's own interior samples are the same points (sample i of the brick is point
 * coord * INTERIOR + i - APRON of the level's lattice). The band-limited field at a point does not
 * depend on which brick's culled list computes it (sdf_build.h), so a brick evaluates only its
 * interior and the regions whose neighbour is absent, and brick_apron.cl copies the others from
 * the neighbours. The set is a 27-bit mask, bit r set when the brick evaluates region r (bit 13
 * always). Samples are numbered i + S (j + S k). */
#ifndef SDFBRICK_SDF_APRON_H
#define SDFBRICK_SDF_APRON_H

#define SAMPLE_COUNT (SAMPLES * SAMPLES * SAMPLES)
#define INTERIOR (SAMPLES - 2 * APRON)
#define APRON_INTERIOR_REGION 13u
#define APRON_ALL_REGIONS 0x7FFFFFFu

inline int3 apron_direction(uint r) { return (int3)((int)(r % 3u) - 1, (int)(r / 3u % 3u) - 1, (int)(r / 9u) - 1); }

/* Samples of region r: per axis APRON, or INTERIOR where its direction is 0 (code 1). */
#define APRON_EXTENT(code) ((code) == 1 ? INTERIOR : APRON)
#define APRON_SIZE(r) (APRON_EXTENT((r) % 3) * APRON_EXTENT((r) / 3 % 3) * APRON_EXTENT((r) / 9))
__constant uint apron_region_size[27] = {
    APRON_SIZE(0),  APRON_SIZE(1),  APRON_SIZE(2),  APRON_SIZE(3),  APRON_SIZE(4),  APRON_SIZE(5),  APRON_SIZE(6),
    APRON_SIZE(7),  APRON_SIZE(8),  APRON_SIZE(9),  APRON_SIZE(10), APRON_SIZE(11), APRON_SIZE(12), APRON_SIZE(13),
    APRON_SIZE(14), APRON_SIZE(15), APRON_SIZE(16), APRON_SIZE(17), APRON_SIZE(18), APRON_SIZE(19), APRON_SIZE(20),
    APRON_SIZE(21), APRON_SIZE(22), APRON_SIZE(23), APRON_SIZE(24), APRON_SIZE(25), APRON_SIZE(26)};

/* Samples in the regions of mask. */
inline uint apron_owned_count(uint mask) {
    uint n = 0;
    for (uint r = 0; r < 27u; ++r)
        if ((mask >> r) & 1u) n += apron_region_size[r];
    return n;
}

/* Per axis: the region code (0, 1, 2 for direction -1, 0, +1) of sample coordinate i, the first
 * sample of that code's range and its length. */
inline int apron_code(int i) { return i < APRON ? 0 : i < SAMPLES - APRON ? 1 : 2; }
inline int apron_first(int code) { return code == 0 ? 0 : code == 1 ? APRON : SAMPLES - APRON; }

inline int3 apron_sample(uint a) {
    return (int3)((int)(a % SAMPLES), (int)(a / SAMPLES % SAMPLES), (int)(a / (SAMPLES * SAMPLES)));
}

/* The region of sample (i, j, k), and the sample's position in its region (x fastest). */
inline uint apron_region_of(int3 q) { return (uint)(apron_code(q.x) + 3 * apron_code(q.y) + 9 * apron_code(q.z)); }
inline uint apron_within(int3 q) {
    const int cx = apron_code(q.x), cy = apron_code(q.y), cz = apron_code(q.z);
    return (uint)((q.x - apron_first(cx)) + APRON_EXTENT(cx) * ((q.y - apron_first(cy)) + APRON_EXTENT(cy) * (q.z - apron_first(cz))));
}

/* The owned samples of a work-group's brick in order: region by region (region order), x fastest
 * inside a region. Fills order[c] = sample index of the c-th owned sample, c < apron_owned_count(mask);
 * offsets (27 entries) is scratch. Every work-item of the group calls it; it ends with a barrier. */
inline void apron_owned_order(uint mask, __local uint* offsets, __local ushort* order) {
    const uint lid = get_local_id(0), wg = get_local_size(0);
    for (uint r = lid; r < 27u; r += wg) {
        uint o = 0;
        for (uint p = 0; p < r; ++p)
            if ((mask >> p) & 1u) o += apron_region_size[p];
        offsets[r] = o;
    }
    barrier(CLK_LOCAL_MEM_FENCE);
    for (uint a = lid; a < SAMPLE_COUNT; a += wg) {
        const int3 q = apron_sample(a);
        const uint r = apron_region_of(q);
        if ((mask >> r) & 1u) order[offsets[r] + apron_within(q)] = (ushort)a;
    }
    barrier(CLK_LOCAL_MEM_FENCE);
}

#endif /* SDFBRICK_SDF_APRON_H */
