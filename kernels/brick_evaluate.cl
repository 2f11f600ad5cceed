/* brick_evaluate.cl: stage "evaluate". One work-group per leaf brick; its S^3 samples are spread over
 * the work-items (PER_ITEM each, held in private memory). The brick's edits are staged through
 * __local memory in chunks of chunk_size: load, barrier, every work-item folds the chunk into its
 * samples, barrier, next chunk. Samples are written to the brick pool clamped to +-band and stored
 * as FORMAT: 0 = int8 snorm, 1 = int16 snorm, 2 = float32.
 * Compile-time: SAMPLES (S: 8 or 10), APRON (1 or 2), PER_ITEM (ceil(S^3 / local size)), FORMAT.
 * Sample (i, j, k) of the brick at coord lies at origin + ((coord * (S - 2 APRON) + (i, j, k) - APRON)
 * + 0.5) * voxel: voxel centres, APRON of them outside the brick on every side. voxel, band and the
 * quantisation scale are the finest level's; a brick of a coarser level (adaptive builds) scales them
 * by its power of two, exactly, and folds with its level's saturation level_clamp[level]. */
#include "sdf_build.h"

#define SAMPLE_COUNT (SAMPLES * SAMPLES * SAMPLES)
#define INTERIOR (SAMPLES - 2 * APRON)

#include "sdf_format.h"

__kernel void brick_evaluate(__global const SdfEdit* edits, __global const float* meshes, __global const uint* edit_indices,
                             __global const SdfBrick* bricks,
                             float origin_x, float origin_y, float origin_z, float finest_voxel,
                             __global const float* level_clamp, float finest_band, float finest_quant_scale,
                             uint finest, uint log2b,
                             __global sample_t* pool, __local SdfPrepared* chunk, uint chunk_size) {
    const uint brick = get_group_id(0);
    const uint lid = get_local_id(0), wg = get_local_size(0);
    const SdfBrick b = bricks[brick];
    const int shift = (int)((finest - b.level) * log2b);
    const float voxel = ldexp(finest_voxel, shift), band = ldexp(finest_band, shift);
    const float quant_scale = ldexp(finest_quant_scale, -shift), clamp_c = level_clamp[b.level];
    const float3 origin = (float3)(origin_x, origin_y, origin_z);
    const int3 first = (int3)(b.coord[0], b.coord[1], b.coord[2]) * INTERIOR - APRON;
    float3 p[PER_ITEM];
    float field[PER_ITEM];
    for (uint s = 0; s < PER_ITEM; ++s) {
        const uint idx = min(lid + s * wg, (uint)SAMPLE_COUNT - 1u);
        const int3 ijk = (int3)(idx % SAMPLES, (idx / SAMPLES) % SAMPLES, idx / (SAMPLES * SAMPLES));
        p[s] = origin + (convert_float3(first + ijk) + 0.5f) * voxel;
        field[s] = clamp_c;
    }
    for (uint base = 0; base < b.edit_count; base += chunk_size) {
        const uint n = min(chunk_size, b.edit_count - base);
        barrier(CLK_LOCAL_MEM_FENCE);
        for (uint j = lid; j < n; j += wg) chunk[j] = sdf_prepare(edits[edit_indices[b.edit_offset + base + j]]);
        barrier(CLK_LOCAL_MEM_FENCE);
        for (uint j = 0; j < n; ++j) {
            const SdfPrepared e = chunk[j];
            for (uint s = 0; s < PER_ITEM; ++s) field[s] = sdf_fold(&e, meshes, field[s], p[s], clamp_c);
        }
    }
    __global sample_t* out = pool + (size_t)brick * SAMPLE_COUNT;
    for (uint s = 0; s < PER_ITEM; ++s) {
        const uint idx = lid + s * wg;
        if (idx >= SAMPLE_COUNT) break;
        const float d = fmin(fmax(field[s], -band), band);
#if FORMAT == 2
        out[idx] = d;
#else
        out[idx] = (sample_t)rint(d * quant_scale);
#endif
    }
}
