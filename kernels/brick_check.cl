/* brick_check.cl: stage "check" (adaptive builds). One work-group per brick of a level whose bricks
 * may be leaves. The brick's S^3 samples are computed exactly as brick_evaluate stores them (same
 * fold, same clamp to +-band, same quantisation), then compared with the band-limited field at the
 * check points: every point of the half-voxel lattice over the samples that is not a sample itself
 * (cell centres, face and edge midpoints), where the trilinear interpolation the tracer uses is the
 * mean of 2, 4 or 8 samples. Both are compared clamped to +-window (the finest level's band: what
 * a uniform build at the finest size stores; deeper values only bound sphere-tracing steps, and a
 * kink of the field far from the surface must not force a refinement). A check point fails when
 * |interpolated - field| > tolerance there, or when
 * the two differ in sign and the field is at least tolerance / 2 deep (a thin feature that the
 * samples step over). Check points half a voxel apart cannot see a feature narrower than that, so
 * a brick whose list holds an edit thinner than its voxel (sdf_feature_size) whose surface comes
 * within `radius` (the cull's: the brick and its apron; cell: the cull's cell size) plus the window of the brick's centre fails
 * too, whatever its points show. Every edit the cull drops fails that distance test, so culling on and
 * off agree. A work-group stops at the first round of check points in which one fails. Writes the
 * brick's worst error (INFINITY when it failed) and whether it passed. Compile-time: SAMPLES,
 * APRON, FORMAT as brick_evaluate. */
#include "sdf_build.h"

#define SAMPLE_COUNT (SAMPLES * SAMPLES * SAMPLES)
#define INTERIOR (SAMPLES - 2 * APRON)
#define CHECK_AXIS (2 * SAMPLES - 1)
#define CHECK_COUNT (CHECK_AXIS * CHECK_AXIS * CHECK_AXIS)

/* F_C at p over the brick's whole list, in list order (the bits brick_evaluate computes). */
inline float check_field(__global const SdfEdit* edits, __global const float* meshes, __global const uint* list, uint n, float3 p,
                         float clamp_c) {
    float f = clamp_c;
    for (uint j = 0; j < n; ++j) {
        const SdfPrepared e = sdf_prepare(edits[list[j]]);
        f = sdf_fold(&e, meshes, f, p, clamp_c);
    }
    return f;
}

/* Whether the brick's list reaches an edit thinner than its voxel (see above). */
inline int reaches_thin_edit(__global const SdfEdit* edits, __global const float* meshes, __global const uint* list,
                             uint n, float3 centre, float voxel, float reach, uint lid, uint wg) {
    int thin = 0;
    for (uint j = lid; j < n; j += wg) {
        const SdfEdit e = edits[list[j]];
        const SdfPrepared pe = sdf_prepare(e);
        thin |= sdf_feature_size(e, meshes) < voxel && fabs(sdf_prepared_value(&pe, meshes, centre)) < reach;
    }
    return thin;
}

/* The error at check point t (half-voxel lattice index) of the brick whose samples are `stored` and
 * `field` (F clamped to the band); negative when the sign test fails there. */
inline float check_point(__global const SdfEdit* edits, __global const float* meshes, __global const uint* list, uint n,
                         __local const float* stored, __local const float* field, int3 h, float3 origin, int3 first,
                         float voxel, float clamp_c, float band, float tolerance, float window, float far) {
    const int3 lo = h >> 1, hi = (h + 1) >> 1;
    float sum = 0.0f, deepest = 0.0f;
    for (int c8 = 0; c8 < 8; ++c8) {
        const int3 c = (int3)((c8 & 1) ? hi.x : lo.x, (c8 & 2) ? hi.y : lo.y, (c8 & 4) ? hi.z : lo.z);
        const int at = c.x + SAMPLES * (c.y + SAMPLES * c.z);
        sum += stored[at];
        deepest = fabs(field[at]) > fabs(deepest) ? field[at] : deepest;
    }
    const float interpolated = sum * 0.125f;
    /* F is 1-Lipschitz and the point lies sqrt(odd axes) / 2 voxels from each of its samples: where
     * one sample is deep enough, |F| here is at least `far`, so F clamped to the window is +-window
     * with that sample's sign and the sign test's depth is met: the list need not be folded here. */
    const int odd = (h.x & 1) + (h.y & 1) + (h.z & 1);
    const float reach = (odd == 1 ? 0.5f : odd == 2 ? 0.70710678f : 0.8660254f) * voxel;
    float exact;
    if (fabs(deepest) - reach >= far) {
        exact = copysign(far, deepest);
    } else {
        const float3 p = origin + (convert_float3(first) + convert_float3(h) * 0.5f + 0.5f) * voxel;
        exact = fmin(fmax(check_field(edits, meshes, list, n, p, clamp_c), -band), band);
    }
    const float error = fabs(fmin(fmax(interpolated, -window), window) - fmin(fmax(exact, -window), window));
    const int lost = (exact < 0.0f) != (interpolated < 0.0f) && fabs(exact) >= 0.5f * tolerance;
    return lost ? -1.0f : error;
}

__kernel void brick_check(__global const SdfEdit* edits, __global const float* meshes, __global const uint* edit_indices,
                          __global const SdfBrick* bricks, float origin_x, float origin_y, float origin_z,
                          float voxel, float clamp_c, float band, float quant_scale, float dequant, float tolerance,
                          float window, float cell, float radius, __global float* errors, __global uint* passed,
                          __local float* stored, __local float* field, __local float* worst) {
    __local int failed;
    const uint brick = get_group_id(0);
    const uint lid = get_local_id(0), wg = get_local_size(0);
    const SdfBrick b = bricks[brick];
    __global const uint* list = edit_indices + b.edit_offset;
    const float3 origin = (float3)(origin_x, origin_y, origin_z);
    const int3 first = (int3)(b.coord[0], b.coord[1], b.coord[2]) * INTERIOR - APRON;
    if (lid == 0) failed = 0;
    barrier(CLK_LOCAL_MEM_FENCE);
    const float3 centre = sdf_cell_centre(origin, cell, (int3)(b.coord[0], b.coord[1], b.coord[2]));
    if (reaches_thin_edit(edits, meshes, list, b.edit_count, centre, voxel, radius + window, lid, wg)) failed = 1;
    barrier(CLK_LOCAL_MEM_FENCE);
    if (!failed) {
        for (uint idx = lid; idx < SAMPLE_COUNT; idx += wg) {
            const int3 ijk = (int3)(idx % SAMPLES, (idx / SAMPLES) % SAMPLES, idx / (SAMPLES * SAMPLES));
            const float3 p = origin + (convert_float3(first + ijk) + 0.5f) * voxel;
            const float d = fmin(fmax(check_field(edits, meshes, list, b.edit_count, p, clamp_c), -band), band);
            field[idx] = d;
#if FORMAT == 2
            stored[idx] = d;
#else
            stored[idx] = rint(d * quant_scale) * dequant;
#endif
        }
    }
    barrier(CLK_LOCAL_MEM_FENCE);
    /* Depth beyond which a check point needs no fold: the window and the sign test's depth, with a
     * margin of 1/64 voxel for the rounding of the folds. */
    const float far = fmax(window, 0.5f * tolerance) + voxel * 0.015625f;
    float mine = 0.0f;
    const uint rounds = (CHECK_COUNT + wg - 1) / wg;
    for (uint r = 0; r < rounds && !failed; ++r) {
        const uint t = r * wg + lid;
        const int3 h = (int3)(t % CHECK_AXIS, (t / CHECK_AXIS) % CHECK_AXIS, t / (CHECK_AXIS * CHECK_AXIS));
        if (t < CHECK_COUNT && ((h.x | h.y | h.z) & 1) != 0) { /* not a sample itself */
            const float e = check_point(edits, meshes, list, b.edit_count, stored, field, h, origin, first, voxel,
                                        clamp_c, band, tolerance, window, far);
            if (e < 0.0f || e > tolerance) failed = 1;
            mine = fmax(mine, e);
        }
        /* every work-item reads `failed` between the same two barriers, so all leave together */
        barrier(CLK_LOCAL_MEM_FENCE);
        const int stop = failed;
        barrier(CLK_LOCAL_MEM_FENCE);
        if (stop) break;
    }
    worst[lid] = mine;
    barrier(CLK_LOCAL_MEM_FENCE);
    if (lid == 0) {
        float w = 0.0f;
        for (uint i = 0; i < wg; ++i) w = fmax(w, worst[i]);
        errors[brick] = failed ? INFINITY : w;
        passed[brick] = failed ? 0u : 1u;
    }
}
