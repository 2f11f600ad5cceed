/* brick_check.cl: stage "check" (adaptive builds). One work-group per brick of a level whose bricks
 * may be leaves. The brick's S^3 samples are brick_evaluate's (launched on these bricks first, into
 * `pool`), compared with the band-limited field at the check points: every point of the half-voxel
 * lattice over the samples that is not a sample itself (cell centres, face and edge midpoints), where
 * the trilinear interpolation the tracer uses is the mean of 2, 4 or 8 samples. Both are compared
 * clamped to +-window (one voxel of this level, at least the finest band: every surface point has
 * check points on both sides inside it, while a kink of the field further out, the middle of a thick
 * slab, must not force a refinement). A check point fails when |interpolated - field| > tolerance
 * there, or when the two differ in sign and the field is at least tolerance / 2 deep (a thin feature
 * that the samples step over). Check points half a voxel apart cannot see a feature narrower than
 * that, so a brick whose list holds an edit thinner than its voxel (sdf_feature_size) whose surface
 * comes within `radius` (the cull's: the brick and its apron; cell: the cull's cell size) plus the
 * window of the brick's centre fails too, whatever its points show (brick_thin, which runs first).
 * Every edit the cull drops fails that distance test, so culling on and off agree.
 * The points go in batches of BATCH, cell centres first (check_coord): those in a deep cell are
 * skipped, those whose field is known to be beyond the window from a sample (below) are settled at
 * once, the others are folded through the brick's list staged in __local chunks as brick_evaluate
 * does; a work-group stops after the first batch with a failing point. Writes the brick's worst error (INFINITY when it failed) and whether it passed.
 * Compile-time: SAMPLES, APRON, FORMAT and SDF_LANES (points folded per value) as brick_evaluate. */
#include "sdf_build.h"
#include "sdf_format.h"

#define SAMPLE_COUNT (SAMPLES * SAMPLES * SAMPLES)
#define INTERIOR (SAMPLES - 2 * APRON)
#define CHECK_AXIS (2 * SAMPLES - 1)
#define CELLS (SAMPLES - 1)
#define CHECK_COUNT (CHECK_AXIS * CHECK_AXIS * CHECK_AXIS - SAMPLE_COUNT) /* the lattice less the samples */
#define BATCH 1024

/* Lane 0 of a value (sdf_edit.h: every lane is the float result at its point). */
#if SDF_LANES == 1
inline float first_lane(sdf_real v) { return v; }
#else
inline float first_lane(sdf_real v) { return v.s0; }
#endif

inline sdf_real load_lanes(const float* a) {
#if SDF_LANES == 1
    return a[0];
#else
    return SDF_REAL_CAT(vload, SDF_LANES)(0, a);
#endif
}
inline void store_lanes(sdf_real v, float* a) {
#if SDF_LANES == 1
    a[0] = v;
#else
    SDF_REAL_CAT(vstore, SDF_LANES)(v, 0, a);
#endif
}

/* Whether the brick's list reaches an edit thinner than its voxel (see above). */
inline int reaches_thin_edit(__global const SdfEdit* edits, __global const float* meshes, __global const uint* list,
                             uint n, float3 centre, float voxel, float reach, uint lid, uint wg) {
    int thin = 0;
    for (uint j = lid; j < n; j += wg) {
        const SdfEdit e = edits[list[j]];
        const SdfPrepared pe = sdf_prepare(e);
        const float v = first_lane(sdf_edit_value(&pe, meshes, SDF_SPLAT(centre.x), SDF_SPLAT(centre.y), SDF_SPLAT(centre.z)));
        thin |= sdf_feature_size(e, meshes) < voxel && fabs(v) < reach;
    }
    return thin;
}

/* Check point t on the half-voxel lattice (odd coordinates lie between samples), cell centres first
 * (odd on three axes: where the trilinear error of a smooth field peaks, so a failing brick usually
 * fails in the first batch), then face centres (two), then edge midpoints (one). */
inline int3 check_coord(uint t) {
    const uint centres = CELLS * CELLS * CELLS, faces = SAMPLES * CELLS * CELLS, edges = CELLS * SAMPLES * SAMPLES;
    if (t < centres) return 2 * (int3)(t % CELLS, (t / CELLS) % CELLS, t / (CELLS * CELLS)) + 1;
    t -= centres;
    if (t < 3u * faces) { /* even on axis t / faces */
        const uint axis = t / faces, r = t % faces;
        const int3 c = (int3)(r % SAMPLES, (r / SAMPLES) % CELLS, r / (SAMPLES * CELLS)); /* even, odd, odd */
        const int3 h = (int3)(2 * c.x, 2 * c.y + 1, 2 * c.z + 1);
        return axis == 0u ? h : axis == 1u ? h.yxz : h.yzx;
    }
    t -= 3u * faces;
    const uint axis = t / edges, r = t % edges; /* odd on axis */
    const int3 c = (int3)(r % CELLS, (r / CELLS) % SAMPLES, r / (CELLS * SAMPLES)); /* odd, even, even */
    const int3 h = (int3)(2 * c.x + 1, 2 * c.y, 2 * c.z);
    return axis == 0u ? h : axis == 1u ? h.yxz : h.yzx;
}

/* The trilinear value at check point h (the mean of its 2, 4 or 8 samples), and in *deepest the
 * stored sample of largest magnitude among them. */
inline float interpolate(__local const float* stored, int3 h, float* deepest) {
    const int3 lo = h >> 1, hi = (h + 1) >> 1;
    float sum = 0.0f, deep = 0.0f;
    for (int c8 = 0; c8 < 8; ++c8) {
        const int3 c = (int3)((c8 & 1) ? hi.x : lo.x, (c8 & 2) ? hi.y : lo.y, (c8 & 4) ? hi.z : lo.z);
        const float v = stored[c.x + SAMPLES * (c.y + SAMPLES * c.z)];
        sum += v;
        deep = fabs(v) > fabs(deep) ? v : deep;
    }
    *deepest = deep;
    return sum * 0.125f;
}

/* The error at a check point from its interpolated and exact values; negative when the sign test
 * fails there. */
inline float point_error(float interpolated, float exact, float tolerance, float window) {
    const float error = fabs(fmin(fmax(interpolated, -window), window) - fmin(fmax(exact, -window), window));
    const int lost = (exact < 0.0f) != (interpolated < 0.0f) && fabs(exact) >= 0.5f * tolerance;
    return lost ? -1.0f : error;
}

/* Before the samples are evaluated: per brick, whether it reaches a thin edit (then it fails, and
 * its copy in `masked`, which the evaluation reads, has no edits, so that nothing is folded for it).
 * passed: 0 for those, 1 for the others (brick_check decides them). */
__kernel void brick_thin(__global const SdfEdit* edits, __global const float* meshes, __global const uint* edit_indices,
                         __global const SdfBrick* bricks, float origin_x, float origin_y, float origin_z, float voxel,
                         float window, float cell, float radius, __global SdfBrick* masked, __global uint* passed) {
    __local int thin;
    const uint brick = get_group_id(0);
    const uint lid = get_local_id(0), wg = get_local_size(0);
    SdfBrick b = bricks[brick];
    if (lid == 0) thin = 0;
    barrier(CLK_LOCAL_MEM_FENCE);
    const float3 centre = sdf_cell_centre((float3)(origin_x, origin_y, origin_z), cell,
                                          (int3)(b.coord[0], b.coord[1], b.coord[2]));
    if (reaches_thin_edit(edits, meshes, edit_indices + b.edit_offset, b.edit_count, centre, voxel, radius + window,
                          lid, wg))
        thin = 1;
    barrier(CLK_LOCAL_MEM_FENCE);
    if (lid == 0) {
        if (thin) b.edit_count = 0u;
        masked[brick] = b;
        passed[brick] = thin ? 0u : 1u;
    }
}

__kernel void brick_check(__global const SdfEdit* edits, __global const float* meshes, __global const uint* edit_indices,
                          __global const SdfBrick* bricks, __global const sample_t* pool, float origin_x,
                          float origin_y, float origin_z, float voxel, float clamp_c, float band, float dequant,
                          float tolerance, float window, __global float* errors, __global uint* passed,
                          __local float* stored, __local float* worst,
                          __local SdfPrepared* chunk, uint chunk_size) {
    __local int failed;
    __local uint todo_count;
    __local ushort todo[BATCH];
    __local float value[BATCH];
    const uint brick = get_group_id(0);
    const uint lid = get_local_id(0), wg = get_local_size(0);
    const SdfBrick b = bricks[brick];
    __global const uint* list = edit_indices + b.edit_offset;
    const float3 origin = (float3)(origin_x, origin_y, origin_z);
    const int3 first = (int3)(b.coord[0], b.coord[1], b.coord[2]) * INTERIOR - APRON;
    for (uint idx = lid; idx < SAMPLE_COUNT; idx += wg) {
#if FORMAT == 2
        stored[idx] = pool[(size_t)brick * SAMPLE_COUNT + idx];
#else
        stored[idx] = (float)pool[(size_t)brick * SAMPLE_COUNT + idx] * dequant;
#endif
    }
    if (lid == 0) failed = passed[brick] == 0u; /* brick_thin failed it */
    /* Depth beyond which a check point needs no fold: the window and the sign test's depth, with a
     * margin of 1/64 voxel for the rounding of the folds. A stored sample is within half a
     * quantisation step of F clamped to the band, and F is 1-Lipschitz: a point sqrt(odd axes) / 2
     * voxels from a sample stored at s has |F| >= |s| - step / 2 - that distance, so where that is at
     * least `far`, F clamped to the window is +-window with the sample's sign, and deep enough for
     * the sign test: the list need not be folded there. */
    const float far = fmax(window, 0.5f * tolerance) + voxel * 0.015625f;
#if FORMAT == 2
    const float half_step = 0.0f;
#else
    const float half_step = 0.5f * dequant;
#endif
    /* A cell all of whose corners are stored deeper than far + its half diagonal (+ half a step)
     * lies beyond the window on one side: at every check point in it or on its boundary, F and the
     * interpolation clamp to the same +-window, an error of 0, so those points are skipped. */
    __local uchar deep[CELLS * CELLS * CELLS];
    barrier(CLK_LOCAL_MEM_FENCE); /* every sample stored */
    for (uint c = lid; c < CELLS * CELLS * CELLS; c += wg) {
        const int3 lo = (int3)(c % CELLS, (c / CELLS) % CELLS, c / (CELLS * CELLS));
        float shallowest = INFINITY;
        for (int c8 = 0; c8 < 8; ++c8)
            shallowest = fmin(shallowest, fabs(stored[lo.x + (c8 & 1) + SAMPLES * (lo.y + ((c8 >> 1) & 1) +
                                                                           SAMPLES * (lo.z + (c8 >> 2)))]));
        deep[c] = shallowest - half_step >= far + 0.8660254f * voxel;
    }
    barrier(CLK_LOCAL_MEM_FENCE);
    float mine = 0.0f;
    for (uint start = 0; start < CHECK_COUNT; start += BATCH) {
        barrier(CLK_LOCAL_MEM_FENCE);
        if (failed) break; /* read by every work-item between the same barriers */
        if (lid == 0) todo_count = 0u;
        barrier(CLK_LOCAL_MEM_FENCE);
        const uint end = min((uint)CHECK_COUNT, start + BATCH);
        for (uint t = start + lid; t < end; t += wg) {
            const int3 h = check_coord(t);
            const int3 cell = min(h >> 1, (int3)(CELLS - 1)); /* a cell holding all the point's samples */
            if (deep[cell.x + CELLS * (cell.y + CELLS * cell.z)]) continue;
            float deepest;
            const float interpolated = interpolate(stored, h, &deepest);
            const int odd = (h.x & 1) + (h.y & 1) + (h.z & 1);
            const float reach = (odd == 1 ? 0.5f : odd == 2 ? 0.70710678f : 0.8660254f) * voxel;
            if (fabs(deepest) - half_step - reach >= far) {
                const float e = point_error(interpolated, copysign(far, deepest), tolerance, window);
                if (e < 0.0f || e > tolerance) failed = 1;
                mine = fmax(mine, e);
            } else {
                /* the list's order follows the atomics, but nothing computed depends on it: each
                 * point folds its own value, and the error's maximum and `failed` are order-free */
                todo[atomic_inc(&todo_count)] = (ushort)(t - start);
            }
        }
        barrier(CLK_LOCAL_MEM_FENCE);
        const uint count = todo_count;
        for (uint k = lid; k < count; k += wg) value[k] = clamp_c;
        for (uint base = 0; base < b.edit_count; base += chunk_size) {
            const uint n = min(chunk_size, b.edit_count - base);
            barrier(CLK_LOCAL_MEM_FENCE);
            for (uint j = lid; j < n; j += wg) chunk[j] = sdf_prepare(edits[list[base + j]]);
            barrier(CLK_LOCAL_MEM_FENCE);
            /* SDF_LANES points per value: lane l holds point k0 + l (the last point repeated past the end) */
            for (uint k0 = lid * SDF_LANES; k0 < count; k0 += wg * SDF_LANES) {
                float x[SDF_LANES], y[SDF_LANES], z[SDF_LANES], v[SDF_LANES];
                for (uint l = 0; l < SDF_LANES; ++l) {
                    const uint k = min(k0 + l, count - 1u);
                    const int3 h = check_coord(start + todo[k]);
                    const float3 p = origin + (convert_float3(first) + convert_float3(h) * 0.5f + 0.5f) * voxel;
                    x[l] = p.x;
                    y[l] = p.y;
                    z[l] = p.z;
                    v[l] = value[k];
                }
                sdf_real px = load_lanes(x), py = load_lanes(y), pz = load_lanes(z), f = load_lanes(v);
                for (uint j = 0; j < n; ++j) {
                    const SdfPrepared e = chunk[j];
                    f = sdf_fold_of(&e, e.kind & 0xffu, (e.kind >> 8) & 0xffu, meshes, f, px, py, pz, clamp_c);
                }
                store_lanes(f, v);
                for (uint l = 0; l < SDF_LANES && k0 + l < count; ++l) value[k0 + l] = v[l];
            }
        }
        for (uint k = lid; k < count; k += wg) {
            float deepest;
            const float interpolated = interpolate(stored, check_coord(start + todo[k]), &deepest);
            const float e = point_error(interpolated, fmin(fmax(value[k], -band), band), tolerance, window);
            if (e < 0.0f || e > tolerance) failed = 1;
            mine = fmax(mine, e);
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
