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
 * off agree. Writes the brick's worst error and whether it passed. Compile-time: SAMPLES,
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

__kernel void brick_check(__global const SdfEdit* edits, __global const float* meshes, __global const uint* edit_indices,
                          __global const SdfBrick* bricks, float origin_x, float origin_y, float origin_z,
                          float voxel, float clamp_c, float band, float quant_scale, float dequant, float tolerance, float window, float cell, float radius,
                          __global float* errors, __global uint* passed, __local float* stored, __local float* worst) {
    const uint brick = get_group_id(0);
    const uint lid = get_local_id(0), wg = get_local_size(0);
    const SdfBrick b = bricks[brick];
    __global const uint* list = edit_indices + b.edit_offset;
    const float3 origin = (float3)(origin_x, origin_y, origin_z);
    const int3 first = (int3)(b.coord[0], b.coord[1], b.coord[2]) * INTERIOR - APRON;
    for (uint idx = lid; idx < SAMPLE_COUNT; idx += wg) {
        const int3 ijk = (int3)(idx % SAMPLES, (idx / SAMPLES) % SAMPLES, idx / (SAMPLES * SAMPLES));
        const float3 p = origin + (convert_float3(first + ijk) + 0.5f) * voxel;
        const float d = fmin(fmax(check_field(edits, meshes, list, b.edit_count, p, clamp_c), -band), band);
#if FORMAT == 2
        stored[idx] = d;
#else
        stored[idx] = rint(d * quant_scale) * dequant;
#endif
    }
    barrier(CLK_LOCAL_MEM_FENCE);
    float mine = 0.0f;
    int lost = 0;
    const float3 centre = sdf_cell_centre(origin, cell, (int3)(b.coord[0], b.coord[1], b.coord[2]));
    for (uint j = lid; j < b.edit_count; j += wg) {
        const SdfEdit e = edits[list[j]];
        const SdfPrepared pe = sdf_prepare(e);
        lost |= sdf_feature_size(e, meshes) < voxel && fabs(sdf_prepared_value(&pe, meshes, centre)) < radius + window;
    }
    for (uint t = lid; t < CHECK_COUNT; t += wg) {
        const int3 h = (int3)(t % CHECK_AXIS, (t / CHECK_AXIS) % CHECK_AXIS, t / (CHECK_AXIS * CHECK_AXIS));
        if (((h.x | h.y | h.z) & 1) == 0) continue; /* a sample itself */
        const int3 lo = h >> 1, hi = (h + 1) >> 1;
        float sum = 0.0f;
        for (int n = 0; n < 8; ++n) {
            const int3 c = (int3)((n & 1) ? hi.x : lo.x, (n & 2) ? hi.y : lo.y, (n & 4) ? hi.z : lo.z);
            sum += stored[c.x + SAMPLES * (c.y + SAMPLES * c.z)];
        }
        const float interpolated = sum * 0.125f;
        const float3 p = origin + (convert_float3(first) + convert_float3(h) * 0.5f + 0.5f) * voxel;
        const float exact = fmin(fmax(check_field(edits, meshes, list, b.edit_count, p, clamp_c), -band), band);
        const float error = fabs(fmin(fmax(interpolated, -window), window) - fmin(fmax(exact, -window), window));
        lost |= (exact < 0.0f) != (interpolated < 0.0f) && fabs(exact) >= 0.5f * tolerance;
        mine = fmax(mine, error);
    }
    worst[lid] = lost ? -mine - 1.0f : mine; /* negative: a sign was lost */
    barrier(CLK_LOCAL_MEM_FENCE);
    if (lid == 0) {
        float w = 0.0f;
        int any_lost = 0;
        for (uint i = 0; i < wg; ++i) {
            any_lost |= worst[i] < 0.0f;
            w = fmax(w, worst[i] < 0.0f ? -worst[i] - 1.0f : worst[i]);
        }
        errors[brick] = w;
        passed[brick] = w <= tolerance && !any_lost ? 1u : 0u;
    }
}
