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

/* Per axis: the region code (0, 1, 2 for direction -1, 0, +1) of sample coordinate i. */
inline uint apron_code(int i) { return i < APRON ? 0u : i < SAMPLES - APRON ? 1u : 2u; }

inline int3 apron_sample(uint a) {
    return (int3)((int)(a % SAMPLES), (int)(a / SAMPLES % SAMPLES), (int)(a / (SAMPLES * SAMPLES)));
}

/* The region of sample (i, j, k). */
inline uint apron_region_of(int3 q) { return apron_code(q.x) + 3u * apron_code(q.y) + 9u * apron_code(q.z); }

/* Owned samples are numbered octant by octant (brick_evaluate.cl culls edits per octant, so a run of
 * consecutive owned samples should lie in as few octants as it can). The octant of sample (i, j, k) is
 * (i >= HALF) + 2 (j >= HALF) + 4 (k >= HALF), HALF = S / 2. A brick that owns every sample numbers
 * them with OCTANT_MAJOR_SAMPLE: octant by octant, x fastest inside each. */
#define HALF (SAMPLES / 2)
#define HALF3 (HALF * HALF * HALF)
#define OCTANT_MAJOR_SAMPLE(c)                                                                            \
    (((c) % HALF + ((c) / HALF3 & 1) * HALF) +                                                            \
     SAMPLES * (((c) / HALF % HALF + ((c) / HALF3 >> 1 & 1) * HALF) +                                     \
                SAMPLES * ((c) / (HALF * HALF) % HALF + ((c) / HALF3 >> 2) * HALF)))
/* The octant of sample index a (an int or int vector: 0 or 1 per axis, as the type's comparisons
 * give -1 for true on vectors). */
#define SAMPLE_OCTANT(a)                                                                                  \
    ((((a) % SAMPLES >= HALF) & 1) | ((((a) / SAMPLES % SAMPLES >= HALF) & 1) << 1) |                     \
     ((((a) / (SAMPLES * SAMPLES) >= HALF) & 1) << 2))

/* A brick that shares samples splits each axis at APRON, HALF and S - APRON into four segments; the
 * 64 boxes they make each lie in one octant and one region. Boxes are numbered octant * 8 + the box's
 * place in its octant, and owned samples are numbered box by box in that order, x fastest inside
 * each box. */
inline uint apron_segment(int i) { return (uint)(i >= APRON) + (uint)(i >= HALF) + (uint)(i >= SAMPLES - APRON); }
inline int apron_segment_first(uint s) { return s == 0u ? 0 : s == 1u ? APRON : s == 2u ? HALF : SAMPLES - APRON; }
inline uint apron_segment_length(uint s) {
    return s == 0u || s == 3u ? (uint)APRON : s == 1u ? (uint)(HALF - APRON) : (uint)(SAMPLES - APRON - HALF);
}
inline uint apron_segment_code(uint s) { return s == 0u ? 0u : s == 3u ? 2u : 1u; }
/* The box number of segments (sx, sy, sz). */
inline uint apron_box(uint sx, uint sy, uint sz) {
    return ((sx >> 1) | (sy >> 1) << 1 | (sz >> 1) << 2) * 8u + ((sx & 1u) | (sy & 1u) << 1 | (sz & 1u) << 2);
}
/* Owned samples of box number b under mask (0 when its region is not owned). */
inline uint apron_box_owned(uint b, uint mask) {
    const uint o = b >> 3, p = b & 7u;
    const uint sx = (o & 1u) << 1 | (p & 1u), sy = (o & 2u) | (p >> 1 & 1u), sz = (o >> 2) << 1 | (p >> 2);
    const uint r = apron_segment_code(sx) + 3u * apron_segment_code(sy) + 9u * apron_segment_code(sz);
    return (mask >> r) & 1u ? apron_segment_length(sx) * apron_segment_length(sy) * apron_segment_length(sz) : 0u;
}

/* The owned samples of mask in that order, as a table: order[c] = the sample index of the c-th owned
 * sample (c < apron_owned_count(mask)); offsets (64 entries) is scratch. Every work-item of the group
 * calls it (it has barriers). */
inline void apron_owned_order(uint mask, __local uint* offsets, __local ushort* order) {
    const uint lid = get_local_id(0), wg = get_local_size(0);
    for (uint b = lid; b < 64u; b += wg) {
        uint o = 0;
        for (uint p = 0; p < b; ++p) o += apron_box_owned(p, mask);
        offsets[b] = o;
    }
    barrier(CLK_LOCAL_MEM_FENCE);
    for (uint a = lid; a < SAMPLE_COUNT; a += wg) {
        const int3 q = apron_sample(a);
        const uint sx = apron_segment(q.x), sy = apron_segment(q.y), sz = apron_segment(q.z);
        const uint r = apron_segment_code(sx) + 3u * apron_segment_code(sy) + 9u * apron_segment_code(sz);
        if ((mask >> r) & 1u)
            order[offsets[apron_box(sx, sy, sz)] + (uint)(q.x - apron_segment_first(sx)) +
                  apron_segment_length(sx) * ((uint)(q.y - apron_segment_first(sy)) +
                                              apron_segment_length(sy) * (uint)(q.z - apron_segment_first(sz)))] = (ushort)a;
    }
    barrier(CLK_LOCAL_MEM_FENCE);
}

#endif /* SDFBRICK_SDF_APRON_H */
