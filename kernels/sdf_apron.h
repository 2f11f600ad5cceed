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

/* Regions by kind, as sets of region bits: faces (off the interior on one axis: INTERIOR^2 APRON
 * samples), edges (on two: INTERIOR APRON^2) and corners (on three: APRON^3). */
#define APRON_FACES ((1u << 4) | (1u << 10) | (1u << 12) | (1u << 14) | (1u << 16) | (1u << 22))
#define APRON_CORNERS ((1u << 0) | (1u << 2) | (1u << 6) | (1u << 8) | (1u << 18) | (1u << 20) | (1u << 24) | (1u << 26))
#define APRON_EDGES (APRON_ALL_REGIONS & ~APRON_FACES & ~APRON_CORNERS & ~(1u << APRON_INTERIOR_REGION))
#define APRON_FACE_SIZE (INTERIOR * INTERIOR * APRON)
#define APRON_EDGE_SIZE (INTERIOR * APRON * APRON)
#define APRON_CORNER_SIZE (APRON * APRON * APRON)
#define APRON_INTERIOR_COUNT (INTERIOR * INTERIOR * INTERIOR)
#define APRON_SHELL (SAMPLE_COUNT - APRON_INTERIOR_COUNT) /* samples outside the interior */

/* Samples in the regions of mask (bit 13 always set). */
inline uint apron_owned_count(uint mask) {
    return APRON_INTERIOR_COUNT + APRON_FACE_SIZE * popcount(mask & APRON_FACES) +
           APRON_EDGE_SIZE * popcount(mask & APRON_EDGES) + APRON_CORNER_SIZE * popcount(mask & APRON_CORNERS);
}

/* Per axis: the region code (0, 1, 2 for direction -1, 0, +1) of sample coordinate i, and the first
 * sample of that code's range. */
inline uint apron_code(int i) { return i < APRON ? 0u : i < SAMPLES - APRON ? 1u : 2u; }
inline uint apron_first(uint code) { return code == 0u ? 0u : code == 1u ? (uint)APRON : (uint)(SAMPLES - APRON); }

inline int3 apron_sample(uint a) {
    return (int3)((int)(a % SAMPLES), (int)(a / SAMPLES % SAMPLES), (int)(a / (SAMPLES * SAMPLES)));
}

/* The region of sample (i, j, k). */
inline uint apron_region_of(int3 q) { return apron_code(q.x) + 3u * apron_code(q.y) + 9u * apron_code(q.z); }

/* The 26 regions of the shell by kind (faces, edges, corners), each kind in region order: owned
 * samples are numbered interior first (x fastest), then the owned regions in this order (x fastest
 * inside each), so that a region's first number takes three popcounts of the mask. */
__constant uchar apron_shell_regions[26] = {4, 10, 12, 14, 16, 22, 1, 3, 5, 7, 9, 11, 15, 17, 19, 21, 23, 25,
                                            0, 2, 6, 8, 18, 20, 24, 26};

/* Of the j-th shell sample (faces, edges, corners; region after region in the order above): its
 * region, its number inside the region, and the region's kind set and size. */
inline uint apron_shell_region(uint j, uint* i, uint* kind, uint* size) {
    const uint edges = 6u * APRON_FACE_SIZE, corners = edges + 12u * APRON_EDGE_SIZE;
    if (j < edges) {
        *kind = APRON_FACES;
        *size = APRON_FACE_SIZE;
        *i = j % APRON_FACE_SIZE;
        return apron_shell_regions[j / APRON_FACE_SIZE];
    }
    if (j < corners) {
        *kind = APRON_EDGES;
        *size = APRON_EDGE_SIZE;
        *i = (j - edges) % APRON_EDGE_SIZE;
        return apron_shell_regions[6u + (j - edges) / APRON_EDGE_SIZE];
    }
    *kind = APRON_CORNERS;
    *size = APRON_CORNER_SIZE;
    *i = (j - corners) % APRON_CORNER_SIZE;
    return apron_shell_regions[18u + (j - corners) / APRON_CORNER_SIZE];
}

/* The sample index of number i (x fastest) of region r (the interior's c-th sample with r =
 * APRON_INTERIOR_REGION, a constant that folds the branches away). */
inline uint apron_region_sample(uint r, uint i) {
    const uint cx = r % 3u, cy = r / 3u % 3u, cz = r / 9u;
    const uint x = cx == 1u ? i % INTERIOR : i % APRON, t = cx == 1u ? i / INTERIOR : i / APRON;
    const uint y = cy == 1u ? t % INTERIOR : t % APRON, z = cy == 1u ? t / INTERIOR : t / APRON;
    return (apron_first(cx) + x) + SAMPLES * ((apron_first(cy) + y) + SAMPLES * (apron_first(cz) + z));
}

/* The owned shell samples of mask in that order, as a table: shell[c] = the sample index of owned
 * sample APRON_INTERIOR_COUNT + c. Every work-item of the group calls it; the caller puts a barrier
 * before reading it. */
inline void apron_owned_shell(uint mask, __local ushort* shell) {
    const uint lid = get_local_id(0), wg = get_local_size(0);
    const uint faces = APRON_FACE_SIZE * popcount(mask & APRON_FACES);
    const uint edges = faces + APRON_EDGE_SIZE * popcount(mask & APRON_EDGES);
    for (uint j = lid; j < APRON_SHELL; j += wg) {
        uint i, kind, size;
        const uint r = apron_shell_region(j, &i, &kind, &size);
        if (!((mask >> r) & 1u)) continue;
        const uint before = kind == APRON_FACES ? 0u : kind == APRON_EDGES ? faces : edges;
        shell[before + size * popcount(mask & kind & ((1u << r) - 1u)) + i] = (ushort)apron_region_sample(r, i);
    }
}

#endif /* SDFBRICK_SDF_APRON_H */
