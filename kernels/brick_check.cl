/* brick_check.cl: stage "check" (adaptive builds). One work-group per brick of a level whose bricks
 * may be leaves. The brick's S^3 samples are brick_evaluate's (launched on these bricks first, into
 * `pool`), compared with the band-limited field at the check points: every point of the half-voxel
 * lattice over the samples that is not a sample itself (cell centres, face and edge midpoints) and
 * lies in the brick's cell (its boundary included: the apron's points lie in the neighbours' cells,
 * where the tracer reads the neighbours), where the trilinear interpolation the tracer uses is the
 * mean of 2, 4 or 8 samples. Both are compared clamped to +-window (one voxel of this level, at least
 * the finest band: every surface point has check points on both sides inside it, while a kink of the
 * field further out, the middle of a thick slab, must not force a refinement). A check point fails
 * when |interpolated - field| > tolerance there, or when the two differ in sign and the field is at
 * least tolerance / 2 deep (a thin feature that the samples step over). Check points half a voxel
 * apart cannot see a feature narrower than that, so a brick whose list holds an edit thinner than its
 * voxel (sdf_feature_size) whose surface comes within `radius` (the cull's: the brick and its apron;
 * cell: the cull's cell size) plus the window of the brick's centre fails too, whatever its points
 * show (brick_thin, which runs first).
 * Every edit the cull drops fails that distance test, so culling on and off agree.
 * The points go in eight classes (seven with one lane), cell centres first (class_odd), and the
 * classes in phases (phase_end: each class of cell centres, then the six others together), in values
 * of SDF_LANES points (one on GPUs): points in a deep cell are skipped, those whose field is known to
 * be beyond the window from a sample (below) are settled at once, and the others are listed with
 * their interpolated values and folded through the brick's list (or, with hard edits only, the one
 * culled again for the children with their saturation clamp_c: the same bits within the window)
 * staged in __local chunks as brick_evaluate does, their coordinates computed in lanes; a
 * work-group stops after the first phase with a failing point.
 * Writes the brick's worst error (INFINITY when it failed) and whether it passed.
 * Compile-time: SAMPLES, APRON, FORMAT and SDF_LANES (points folded per value) as brick_evaluate. */
#include "sdf_build.h"
#include "sdf_format.h"

#define SAMPLE_COUNT (SAMPLES * SAMPLES * SAMPLES)
#define INTERIOR (SAMPLES - 2 * APRON)
#define CELLS (SAMPLES - 1)
/* The brick's cell, where the tracer searches it, is s in [APRON - 0.5, SAMPLES - APRON - 0.5] in
 * sample space: half-voxel lattice coordinates h = 2 s from INSIDE_LO to INSIDE_HI. Points beyond lie
 * in the neighbours' cells, which check their own. */
#define INSIDE_LO (2 * APRON - 1)
#define INSIDE_HI (2 * (SAMPLES - APRON) - 1)
#if INSIDE_HI > 2 * SAMPLES - 3
#error "a point inside the cell must not have the last sample of an axis as its lowest corner"
#endif
/* The first class: on CPU lanes the even cell centres come first (class_odd); with one lane (GPUs),
 * where a class is a few latency-bound phases of a work-group, all cell centres form one class (on
 * the H200 the extra class made the check 4-8% slower: docs/measurements/roof/d10). */
#if SDF_LANES > 1
#define FIRST_CLASS 0u
#else
#define FIRST_CLASS 1u
#endif
#define VALUES ((SAMPLE_COUNT + SDF_LANES - 1) / SDF_LANES) /* values of SDF_LANES point numbers of a class */
/* A phase: the classes checked before the work-group next tests whether the brick failed. The cell
 * centres (one or two classes) each make a phase, since a failing brick usually fails there; the
 * six classes of face centres and edge midpoints make one, so that their points are classified and
 * folded together (fewer barriers, more points a work-item). PHASE_POINTS: the points inside the
 * cell of the largest phase, the six classes with one or two even axes (IN_ODD odd and IN_EVEN even
 * coordinates on each axis). A listed point is (class << 10) | point number. */
#define IN_ODD ((INSIDE_HI - INSIDE_LO) / 2 + 1)
#define IN_EVEN ((INSIDE_HI - INSIDE_LO) / 2)
#define PHASE_POINTS (3 * (IN_ODD) * (IN_ODD) * (IN_EVEN) + 3 * (IN_ODD) * (IN_EVEN) * (IN_EVEN))
inline uint phase_end(uint k) { return k < 2u ? k + 1u : 8u; }
#define STORED (VALUES * SDF_LANES + SAMPLES * SAMPLES + SAMPLES + 1) /* the corners the last value reads */

/* Half a quantisation step of the stored samples (dequant: the distance per stored unit), by which a
 * stored sample may differ from the field clamped to the band; 0 for float samples. */
inline float half_step_of(float dequant) {
#if FORMAT == 2
    return 0.0f;
#else
    return 0.5f * dequant;
#endif
}

/* Lane 0 of a value (sdf_edit.h: every lane is the float result at its point). */
#if SDF_LANES == 1
inline float first_lane(sdf_real v) { return v; }
#else
inline float first_lane(sdf_real v) { return v.s0; }
#endif

inline sdf_real load_lanes(__local const float* a) {
#if SDF_LANES == 1
    return a[0];
#else
    return SDF_REAL_CAT(vload, SDF_LANES)(0, a);
#endif
}
inline void store_lanes(sdf_real v, __local float* a) {
#if SDF_LANES == 1
    a[0] = v;
#else
    SDF_REAL_CAT(vstore, SDF_LANES)(v, 0, a);
#endif
}

/* Whether the brick's list reaches an edit thinner than its voxel (see above). */
inline int reaches_thin_edit(__global const SdfEdit* edits, __global const float* meshes, __global const uint* list,
                             uint n, float3 centre, float voxel, float reach, uint lid, uint wg) {
    for (uint j = lid; j < n; j += wg) {
        const SdfEdit e = edits[list[j]];
        if (!(sdf_feature_size(e, meshes) < voxel)) continue; /* its value is not needed */
        const SdfPrepared pe = sdf_prepare(e);
        const float v = first_lane(sdf_edit_value(&pe, meshes, SDF_SPLAT(centre.x), SDF_SPLAT(centre.y), SDF_SPLAT(centre.z)));
        if (fabs(v) < reach) return 1; /* the result is an or: the first one settles it */
    }
    return 0;
}

/* The check points in eight classes of one parity each, cell centres first (odd on three axes: where
 * the trilinear error of a smooth field peaks, so a failing brick usually fails there), then face
 * centres (odd on two), then edge midpoints (odd on one). The cell centres come in two classes: those
 * of the cells whose coordinates are all even (an eighth of them, spread over the brick), then the
 * rest, so that most failing bricks stop after a few points. Point i of the class with odd
 * axes `odd` is numbered like sample i = x + S (y + S z): it is h = 2 (x, y, z) + odd on the
 * half-voxel lattice, and its lowest corner is sample i. On an odd axis the coordinate S - 1 has no
 * point (no sample above it): h = 2 S - 1 there, past the lattice's 2 CELLS, and such lanes are
 * skipped. So a value's corners are consecutive samples (loads, not gathers), and its coordinates
 * take a division by the constant S. */
#define ODD_X 0x3B /* bit k: whether class k is odd on x (classes 0-1 (1, 1, 1); 2-4 (0, 1, 1), */
#define ODD_Y 0x57 /* (1, 0, 1), (1, 1, 0); 5-7 (1, 0, 0), (0, 1, 0), (0, 0, 1)) */
#define ODD_Z 0x8F
inline int3 class_odd(uint k) { return (int3)((ODD_X >> k) & 1, (ODD_Y >> k) & 1, (ODD_Z >> k) & 1); }

/* class_odd for a class number per lane. */
inline void class_odd_lanes(sdf_index k, sdf_index* ox, sdf_index* oy, sdf_index* oz) {
    *ox = ((sdf_index)(ODD_X) >> k) & 1;
    *oy = ((sdf_index)(ODD_Y) >> k) & 1;
    *oz = ((sdf_index)(ODD_Z) >> k) & 1;
}

/* The lattice coordinates of points i of a class, one per lane. */
inline void class_lanes(sdf_index i, int3 odd, sdf_index* hx, sdf_index* hy, sdf_index* hz) {
    *hx = 2 * (i % SAMPLES) + odd.x;
    *hy = 2 * ((i / SAMPLES) % SAMPLES) + odd.y;
    *hz = 2 * (i / (SAMPLES * SAMPLES)) + odd.z;
}

/* list[min(k + l, count - 1)] in lane l. */
inline sdf_index list_lanes(__local const ushort* list, uint k, uint count) {
#if SDF_LANES == 1
    return list[min(k, count - 1u)];
#else
    int at[SDF_LANES];
    for (uint l = 0; l < SDF_LANES; ++l) at[l] = list[min(k + l, count - 1u)];
    return SDF_REAL_CAT(vload, SDF_LANES)(0, at);
#endif
}

/* One corner into the sum and the deepest sample so far (strictly deeper replaces it). */
inline void add_corner(sdf_real* sum, sdf_real* deep, sdf_real v) {
    *sum += v;
    *deep = select(*deep, v, fabs(v) > fabs(*deep));
}

/* The trilinear value at the check points of one class (odd axes `odd`) whose lowest corners are
 * samples at + lane: the mean of the 8 corners summed in corner order (corner c takes the upper
 * sample on axis a when bit a of c is set), and in *deepest the stored sample of largest magnitude
 * among them (the first of equal ones). On an even axis the upper and lower samples are the same
 * one, so only the 2, 4 or 8 distinct corners are read; each repeated corner reuses the value read
 * for it, and the sum is the same. */
inline sdf_real interpolate(__local const float* stored, uint at, int3 odd, sdf_real* deepest) {
    const uint dx = 1u, dy = SAMPLES, dz = SAMPLES * SAMPLES;
    const sdf_real v0 = load_lanes(stored + at);
    sdf_real v1 = v0, v2 = v0, v4 = v0;
    if (odd.x) v1 = load_lanes(stored + at + dx);
    if (odd.y) v2 = load_lanes(stored + at + dy);
    if (odd.z) v4 = load_lanes(stored + at + dz);
    sdf_real v3 = odd.x ? v1 : v2, v5 = odd.x ? v1 : v4, v6 = odd.y ? v2 : v4;
    if (odd.x && odd.y) v3 = load_lanes(stored + at + dx + dy);
    if (odd.x && odd.z) v5 = load_lanes(stored + at + dx + dz);
    if (odd.y && odd.z) v6 = load_lanes(stored + at + dy + dz);
    sdf_real v7 = !odd.z ? v3 : !odd.y ? v5 : v6;
    if (odd.x && odd.y && odd.z) v7 = load_lanes(stored + at + dx + dy + dz);
    sdf_real sum = 0.0f, deep = 0.0f;
    add_corner(&sum, &deep, v0);
    add_corner(&sum, &deep, v1);
    add_corner(&sum, &deep, v2);
    add_corner(&sum, &deep, v3);
    add_corner(&sum, &deep, v4);
    add_corner(&sum, &deep, v5);
    add_corner(&sum, &deep, v6);
    add_corner(&sum, &deep, v7);
    *deepest = deep;
    return sum * 0.125f;
}

/* The error at a check point from its interpolated and exact values; negative when the sign test
 * fails there. */
inline sdf_real point_error(sdf_real interpolated, sdf_real exact, float tolerance, float window) {
    const sdf_real error = fabs(fmin(fmax(interpolated, -window), window) - fmin(fmax(exact, -window), window));
    return select(error, SDF_SPLAT(-1.0f), (exact < 0.0f) != (interpolated < 0.0f) && fabs(exact) >= 0.5f * tolerance);
}

/* Lane masks without a trip through memory: bit l of lane_bits is set where lane l of a comparison's
 * result is true; lanes_of turns such bits back into a lane mask. */
#if SDF_LANES == 1
inline uint lane_bits(sdf_index c) { return c != 0 ? 1u : 0u; }
inline sdf_index lanes_of(uint bits) { return (int)(bits & 1u); }
#else
inline uint lane_bits(sdf_index c) {
    const sdf_index b = c & ((sdf_index)(1) << SDF_LANE_OFFSETS);
#if SDF_LANES == 16
    const int8 b8 = b.lo | b.hi;
    const int4 b4 = b8.lo | b8.hi;
#elif SDF_LANES == 8
    const int4 b4 = b.lo | b.hi;
#elif SDF_LANES == 4
    const int4 b4 = b;
#endif
#if SDF_LANES >= 4
    const int2 b2 = b4.lo | b4.hi;
#else
    const int2 b2 = b;
#endif
    return (uint)(b2.x | b2.y);
}
inline sdf_index lanes_of(uint bits) { return (((sdf_index)((int)bits) >> SDF_LANE_OFFSETS) & 1) != 0; }
#endif

/* Folds the errors of a value's lanes in `lanes` (a bit mask) into the work-item's worst error, and
 * fails the brick when one is over the tolerance or failed the sign test (an error of -1). */
inline float keep_errors(sdf_real error, uint lanes, float tolerance, float mine, __local int* failed) {
    const sdf_index on = lanes_of(lanes);
    if (lane_bits(on & (error < 0.0f || error > tolerance))) *failed = 1;
    return fmax(mine, sdf_lanes_max(select(SDF_SPLAT(0.0f), error, on)));
}

/* Whether a hard box or rounded box added alone is, clamped to the band, one face's plane clamped to
 * it over the box [lo, hi] (its samples' span). In the edit's frame, with h the half extents less the
 * rounding r, the six faces' planes are P = +-c_a - h_a, and the distance is the box's (at least
 * every P) less r. Where every plane but face f's is at most L = min(0, r - band) (the band in the
 * edit's units), the distance is P_f - r wherever it is above -band: outside the box only P_f can
 * be positive, and inside, where another plane is the box's, the distance is at most L - r <= -band.
 * A plane's maximum over the span is at a corner, so this holds where at most one face's plane
 * exceeds L at the corners (where none does, the field is -band over the span, as any face's plane
 * clamped is). Returns a bound on the rounding of the folds' values and of the interpolation over
 * the span (64 float epsilons of the magnitudes they add), or -1 where it does not hold. */
inline float box_as_plane(const SdfEdit e, float3 lo, float3 hi, float band) {
    if (e.op != SDF_OP_ADD || e.blend > 0.0f || (e.primitive != SDF_PRIM_BOX && e.primitive != SDF_PRIM_ROUND_BOX))
        return -1.0f;
    const SdfPrepared pe = sdf_prepare(e);
    const float r = e.primitive == SDF_PRIM_ROUND_BOX ? e.params[3] : 0.0f;
    const float3 h = (float3)(e.params[0], e.params[1], e.params[2]) - r;
    const float3 far = fmax(fabs(lo), fabs(hi)) + fabs((float3)(pe.t[0], pe.t[1], pe.t[2]));
    const float extent = fmax(fmax(far.x, far.y), far.z) * pe.inv_scale + fmax(fmax(h.x, h.y), h.z) + r;
    const float out = fabs(pe.out_scale);
    const float rounding = 64.0f * FLT_EPSILON * (extent * out + band);
    const float limit = fmin(0.0f, r - band / out) - rounding / out; /* in the edit's frame */
    float3 above = (float3)(-INFINITY), below = (float3)(-INFINITY); /* the + and - faces' planes' maxima */
    for (uint k = 0; k < 8u; ++k) {
        sdf_real x = SDF_SPLAT((k & 1u) ? hi.x : lo.x), y = SDF_SPLAT((k & 2u) ? hi.y : lo.y),
                 z = SDF_SPLAT((k & 4u) ? hi.z : lo.z);
        sdf_edit_frame_of(&pe, 1, &x, &y, &z);
        const float3 c = (float3)(first_lane(x), first_lane(y), first_lane(z));
        above = fmax(above, c - h);
        below = fmax(below, -c - h);
    }
    const int3 up = isgreater(above, (float3)(limit)), down = isgreater(below, (float3)(limit));
    const int faces = (up.x != 0) + (up.y != 0) + (up.z != 0) + (down.x != 0) + (down.y != 0) + (down.z != 0);
    return faces <= 1 ? rounding : -1.0f;
}

/* Before the samples are evaluated: per brick, whether it reaches a thin edit or has fewer than
 * min_children children at the next level (children: that level's count over every brick checked
 * here). Either fails it: its copy in `masked`, which the evaluation reads, has no edits, so that
 * nothing is folded for it. passed: 0 for those, 1 for the others. errors: 0, except for a brick
 * whose list is one edit whose band-limited field is a plane's over its samples (box_as_plane):
 * trilinear interpolation reproduces a plane, so where a check point's corners lie within the band
 * its error is at most half a quantisation step (half_step_of) and the rounding. Where that bound is
 * under half the tolerance (no sign test can fail) and band - sqrt(3) voxels - the bound is beyond
 * the window (a point next to a corner saturated at the band lies beyond the window with its
 * interpolation, the field 1-Lipschitz and the point sqrt(3)/2 voxel from its corners, so both clamp
 * to the same value), errors holds minus the bound (the host reads its sign as the plane's mark)
 * and brick_check passes the brick unchecked; elsewhere 0. */
__kernel void brick_thin(__global const SdfEdit* edits, __global const float* meshes, __global const uint* edit_indices,
                         __global const SdfBrick* bricks, float origin_x, float origin_y, float origin_z, float voxel,
                         float window, float cell, float radius, __global const uint* children, uint min_children,
                         float dequant, float band, float tolerance, __global SdfBrick* masked,
                         __global uint* passed, __global float* errors) {
    __local int thin;
    const uint brick = get_group_id(0);
    const uint lid = get_local_id(0), wg = get_local_size(0);
    SdfBrick b = bricks[brick];
    const int few = min_children > 0u && children[brick] < min_children; /* failed already: no edit read */
    if (lid == 0) thin = few;
    barrier(CLK_LOCAL_MEM_FENCE);
    const float3 centre = sdf_cell_centre((float3)(origin_x, origin_y, origin_z), cell,
                                          (int3)(b.coord[0], b.coord[1], b.coord[2]));
    if (!few && reaches_thin_edit(edits, meshes, edit_indices + b.edit_offset, b.edit_count, centre, voxel,
                                  radius + window, lid, wg))
        thin = 1;
    barrier(CLK_LOCAL_MEM_FENCE);
    if (lid == 0) {
        const float3 lo = sdf_cell_centre((float3)(origin_x, origin_y, origin_z), voxel,
                                          (int3)(b.coord[0], b.coord[1], b.coord[2]) * INTERIOR - APRON);
        const float rounding = !thin && b.edit_count == 1u
                                   ? box_as_plane(edits[edit_indices[b.edit_offset]], lo,
                                                  lo + (float)(SAMPLES - 1) * voxel, band)
                                   : -1.0f;
        const float bound = half_step_of(dequant) + rounding;
        const int plane = rounding >= 0.0f && bound < 0.5f * tolerance && band - 1.7320508f * voxel - bound >= window;
        if (thin) b.edit_count = 0u;
        masked[brick] = b;
        passed[brick] = thin ? 0u : 1u;
        errors[brick] = plane ? -bound : 0.0f;
    }
}

__kernel void brick_check(__global const SdfPrepared* edits, __global const float* meshes, __global const uint* edit_indices,
                          __global const SdfBrick* bricks, __global const sample_t* pool, float origin_x,
                          float origin_y, float origin_z, float voxel, float clamp_c, float band, float dequant,
                          float tolerance, float window, __global float* errors, __global uint* passed,
                          __local float* worst,
                          __local SdfPrepared* chunk, uint chunk_size) {
    __local int failed;
    __local uint fold_count;
    __local float stored[STORED];                   /* the samples, then zeros that lanes past them read */
    __local ushort to_fold[PHASE_POINTS];           /* the phase's points that need the fold */
    __local float interp[PHASE_POINTS + SDF_LANES]; /* per point of to_fold: its interpolated value */
    __local float value[PHASE_POINTS + SDF_LANES];  /* per point of to_fold: its folded field */
    __local float deep_cells[VALUES * SDF_LANES];   /* per cell, numbered like its lowest corner: 1 when deep */
    const uint brick = get_group_id(0);
    const uint lid = get_local_id(0), wg = get_local_size(0);
    if (passed[brick] == 0u) { /* brick_thin failed it (every work-item returns here) */
        if (lid == 0) errors[brick] = INFINITY;
        return;
    }
    if (errors[brick] < 0.0f) return; /* brick_thin passed it as a plane, with minus its error */
    const SdfBrick b = bricks[brick];
    __global const uint* list = edit_indices + b.edit_offset;
    const int3 first = (int3)(b.coord[0], b.coord[1], b.coord[2]) * INTERIOR - APRON;
    for (uint idx = lid; idx < SAMPLE_COUNT; idx += wg) {
#if FORMAT == 2
        stored[idx] = pool[(size_t)brick * SAMPLE_COUNT + idx];
#else
        stored[idx] = (float)pool[(size_t)brick * SAMPLE_COUNT + idx] * dequant;
#endif
    }
    for (uint idx = SAMPLE_COUNT + lid; idx < STORED; idx += wg) stored[idx] = 0.0f;
    if (lid == 0) failed = 0;
    /* Depth beyond which a check point needs no fold: the window and the sign test's depth, with a
     * margin of 1/64 voxel for the rounding of the folds. A stored sample is within half a
     * quantisation step of F clamped to the band, and F is 1-Lipschitz: a point sqrt(odd axes) / 2
     * voxels from a sample stored at s has |F| >= |s| - step / 2 - that distance, so where that is at
     * least `far`, F clamped to the window is +-window with the sample's sign, and deep enough for
     * the sign test: the list need not be folded there (its error is the one the fold would give). */
    const float far = fmax(window, 0.5f * tolerance) + voxel * 0.015625f;
    const float half_step = half_step_of(dequant);
    /* A cell all of whose corners are stored deeper than far + its half diagonal (+ half a step)
     * lies beyond the window on one side: at every check point in it or on its boundary, F and the
     * interpolation clamp to the same +-window, an error of 0, so those points are skipped. */
    barrier(CLK_LOCAL_MEM_FENCE); /* every sample stored */
    for (uint v = lid; v < VALUES; v += wg) { /* SDF_LANES cells at a time (those past CELLS are never read) */
        const uint at = v * SDF_LANES;
        sdf_real shallowest = fabs(load_lanes(stored + at));
        for (uint c8 = 1; c8 < 8u; ++c8)
            shallowest = fmin(shallowest, fabs(load_lanes(stored + at + (c8 & 1u) + SAMPLES * ((c8 >> 1) & 1u) +
                                                          SAMPLES * SAMPLES * (c8 >> 2))));
        store_lanes(select(SDF_SPLAT(0.0f), SDF_SPLAT(1.0f), shallowest - half_step >= far + 0.8660254f * voxel),
                    deep_cells + at);
    }
    /* A point's cell is the one of its lowest corner, sample i for point i of every class: a point
     * inside the brick's cell has h <= INSIDE_HI <= 2 S - 3 on each axis, so its lowest corner is
     * never the last sample of an axis, and deep_cells[i] is its cell's. */
    float mine = 0.0f;
    for (uint k0 = FIRST_CLASS; k0 < 8u; k0 = phase_end(k0)) {
        barrier(CLK_LOCAL_MEM_FENCE);
        if (failed) break; /* read by every work-item between the same barriers */
        if (lid == 0) fold_count = 0u;
        barrier(CLK_LOCAL_MEM_FENCE);
        for (uint k = k0; k < phase_end(k0); ++k) {
            const int3 odd = class_odd(k);
            const float reach = (k < 2u ? 0.8660254f : k < 5u ? 0.70710678f : 0.5f) * voxel;
            /* SDF_LANES points at a time: those in deep cells are skipped, those known to lie beyond the
             * window settled at once, and the others listed for the fold with their interpolated values */
            for (uint v = lid; v < VALUES; v += wg) {
                sdf_index hx, hy, hz;
                class_lanes((int)(v * SDF_LANES) + SDF_LANE_OFFSETS, odd, &hx, &hy, &hz);
                const sdf_index even = ((hx | hy | hz) & 2) == 0; /* a cell centre of a cell with even coordinates */
                const sdf_index outside = hx < INSIDE_LO || hy < INSIDE_LO || hz < INSIDE_LO || hx > INSIDE_HI ||
                                          hy > INSIDE_HI || hz > INSIDE_HI || /* no point, or outside the cell */
                                          (k == 0u && !even) || (k == 1u && FIRST_CLASS == 0u && even);
                /* no point, or in a deep cell: skipped (a value with nothing else is not interpolated) */
                const uint skipped = lane_bits(outside || load_lanes(deep_cells + v * SDF_LANES) != 0.0f);
                if (skipped == (1u << SDF_LANES) - 1u) continue;
                sdf_real deepest;
                const sdf_real interpolated = interpolate(stored, v * SDF_LANES, odd, &deepest);
                const sdf_index settled = fabs(deepest) - half_step - reach >= far;
                const uint settle = lane_bits(settled) & ~skipped;
                /* the list's order follows the atomics, but nothing computed depends on it: each point
                 * folds its own value, and the error's maximum and `failed` are order-free */
                uint fold = ~(skipped | settle) & ((1u << SDF_LANES) - 1u);
                if (fold) {
                    float lane_values[SDF_LANES];
                    sdf_spill_lanes(interpolated, lane_values);
                    uint at = atomic_add(&fold_count, popcount(fold));
                    for (; fold; fold &= fold - 1u, ++at) {
                        const uint lane = 31u - clz(fold & (0u - fold));
                        to_fold[at] = (ushort)((k << 10) | (v * SDF_LANES + lane));
                        interp[at] = lane_values[lane];
                    }
                }
                if (settle)
                    mine = keep_errors(point_error(interpolated, copysign(SDF_SPLAT(far), deepest), tolerance, window),
                                       settle, tolerance, mine, &failed);
            }
        }
        barrier(CLK_LOCAL_MEM_FENCE);
        const uint listed = fold_count;
        for (uint base = 0; base < b.edit_count; base += chunk_size) {
            const uint m = min(chunk_size, b.edit_count - base);
            barrier(CLK_LOCAL_MEM_FENCE);
            for (uint j = lid; j < m; j += wg) chunk[j] = edits[list[base + j]];
            barrier(CLK_LOCAL_MEM_FENCE);
            for (uint t = lid * SDF_LANES; t < listed; t += wg * SDF_LANES) {
                const sdf_index entry = list_lanes(to_fold, t, listed);
                sdf_index ox, oy, oz, hx, hy, hz;
                class_odd_lanes(entry >> 10, &ox, &oy, &oz);
                class_lanes(entry & 1023, (int3)(0), &hx, &hy, &hz);
                hx += ox;
                hy += oy;
                hz += oz;
                const sdf_real px = origin_x + ((float)first.x + SDF_CONVERT_REAL(hx) * 0.5f + 0.5f) * voxel;
                const sdf_real py = origin_y + ((float)first.y + SDF_CONVERT_REAL(hy) * 0.5f + 0.5f) * voxel;
                const sdf_real pz = origin_z + ((float)first.z + SDF_CONVERT_REAL(hz) * 0.5f + 0.5f) * voxel;
                sdf_real f = base == 0u ? SDF_SPLAT(clamp_c) : load_lanes(value + t);
                for (uint j = 0; j < m; ++j) {
                    const SdfPrepared e = chunk[j];
                    f = sdf_fold_of(&e, e.kind & 0xffu, (e.kind >> 8) & 0xffu, meshes, f, px, py, pz, clamp_c);
                }
                store_lanes(f, value + t);
            }
        }
        for (uint t = lid * SDF_LANES; t < listed; t += wg * SDF_LANES) {
            const sdf_real exact = b.edit_count ? load_lanes(value + t) : SDF_SPLAT(clamp_c);
            const uint lanes = min((uint)SDF_LANES, listed - t);
            mine = keep_errors(point_error(load_lanes(interp + t), fmin(fmax(exact, -band), band), tolerance, window),
                               (1u << lanes) - 1u, tolerance, mine, &failed);
        }
    }
    barrier(CLK_LOCAL_MEM_FENCE);
    worst[lid] = mine;
    barrier(CLK_LOCAL_MEM_FENCE);
    if (lid == 0) {
        float w = 0.0f;
        for (uint i = 0; i < wg; ++i) w = fmax(w, worst[i]);
        errors[brick] = failed ? INFINITY : w;
        passed[brick] = failed ? 0u : 1u;
    }
}
