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
inline uint apron_code(int i) { return i < APRON ? 0u : i < SAMPLES - APRON ? 1u : 2u; }
inline uint apron_first(uint code) { return code == 0u ? 0u : code == 1u ? (uint)APRON : (uint)(SAMPLES - APRON); }

inline int3 apron_sample(uint a) {
    return (int3)((int)(a % SAMPLES), (int)(a / SAMPLES % SAMPLES), (int)(a / (SAMPLES * SAMPLES)));
}

/* The region of sample (i, j, k). */
inline uint apron_region_of(int3 q) { return apron_code(q.x) + 3u * apron_code(q.y) + 9u * apron_code(q.z); }

/* Owned samples are numbered interior first (x fastest), then the other owned regions in region
 * order (x fastest inside each). */
#define APRON_INTERIOR_COUNT (INTERIOR * INTERIOR * INTERIOR)

/* The owned samples of mask in that order, as a table: order[c] = the sample index of the c-th owned
 * sample (c < apron_owned_count(mask)); offsets (27 entries) is scratch. Every work-item of the group calls it (it has barriers). */
inline void apron_owned_order(uint mask, __local uint* offsets, __local ushort* order) {
    const uint lid = get_local_id(0), wg = get_local_size(0);
    for (uint r = lid; r < 27u; r += wg) {
        uint o = APRON_INTERIOR_COUNT;
        for (uint p = 0; p < r; ++p)
            if (p != APRON_INTERIOR_REGION && ((mask >> p) & 1u)) o += apron_region_size[p];
        offsets[r] = r == APRON_INTERIOR_REGION ? 0u : o;
    }
    barrier(CLK_LOCAL_MEM_FENCE);
    for (uint a = lid; a < SAMPLE_COUNT; a += wg) {
        const int3 q = apron_sample(a);
        const uint cx = apron_code(q.x), cy = apron_code(q.y), cz = apron_code(q.z);
        const uint r = cx + 3u * cy + 9u * cz;
        if ((mask >> r) & 1u)
            order[offsets[r] + ((uint)q.x - apron_first(cx)) +
                  APRON_EXTENT(cx) * (((uint)q.y - apron_first(cy)) + APRON_EXTENT(cy) * ((uint)q.z - apron_first(cz)))] = (ushort)a;
    }
    barrier(CLK_LOCAL_MEM_FENCE);
}

#endif /* SDFBRICK_SDF_APRON_H */
