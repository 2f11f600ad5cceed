/* brick_evaluate.cl: stage "evaluate". One work-group per leaf brick; its S^3 samples are spread over
 * the work-items (PER_ITEM values of sdf_real each, SDF_LANES samples per value, held in private
 * memory). The brick's edits are staged through __local memory in chunks of chunk_size: load,
 * barrier, every work-item folds the chunk into its samples, barrier, next chunk. Samples are written
 * to the brick pool clamped to +-band and stored as FORMAT: 0 = int8 snorm, 1 = int16 snorm,
 * 2 = float32.
 * Compile-time: SAMPLES (S: 8 or 10), APRON (1 or 2), SDF_LANES (1, or the SIMD width of a CPU
 * device: sdf_edit.h), PER_ITEM (ceil(S^3 / (local size x lanes))), FORMAT.
 * Lane l of value s of work-item lid holds sample (s * local size + lid) * lanes + l (with one lane,
 * consecutive work-items hold consecutive samples); samples past S^3 - 1 repeat the last one and are
 * not stored.
 * Sample (i, j, k) of the brick at coord lies at origin + ((coord * (S - 2 APRON) + (i, j, k) - APRON)
 * + 0.5) * voxel: voxel centres, APRON of them outside the brick on every side. voxel, band and the
 * quantisation scale are the finest level's; a brick of a coarser level (adaptive builds) scales them
 * by its power of two, exactly, and folds with its level's saturation level_clamp[level]. */
#include "sdf_build.h"

#define SAMPLE_COUNT (SAMPLES * SAMPLES * SAMPLES)
#define INTERIOR (SAMPLES - 2 * APRON)

#include "sdf_format.h"

#if SDF_LANES == 1
typedef int sdf_index;
#define SDF_LANE_OFFSETS 0
#define SDF_CONVERT_REAL convert_float
#else
typedef SDF_REAL_CAT(int, SDF_LANES) sdf_index;
#define SDF_CONVERT_REAL SDF_REAL_CAT(convert_float, SDF_LANES)
#if SDF_LANES == 2
#define SDF_LANE_OFFSETS ((sdf_index)(0, 1))
#elif SDF_LANES == 4
#define SDF_LANE_OFFSETS ((sdf_index)(0, 1, 2, 3))
#elif SDF_LANES == 8
#define SDF_LANE_OFFSETS ((sdf_index)(0, 1, 2, 3, 4, 5, 6, 7))
#else
#define SDF_LANE_OFFSETS ((sdf_index)(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15))
#endif
#endif

/* Stores the samples of one value whose first lane is sample idx (lanes past the last sample are
 * dropped). */
inline void store_samples(__global sample_t* out, uint idx, sdf_real field, float band, float quant_scale) {
    const sdf_real d = fmin(fmax(field, -band), band);
#if FORMAT == 2
    const sdf_real q = d;
#else
    const sdf_real q = rint(d * quant_scale);
#endif
#if SDF_LANES == 1
    if (idx < SAMPLE_COUNT) out[idx] = (sample_t)q;
#else
    float lanes[SDF_LANES];
    SDF_REAL_CAT(vstore, SDF_LANES)(q, 0, lanes);
    for (uint l = 0; l < SDF_LANES && idx + l < SAMPLE_COUNT; ++l) out[idx + l] = (sample_t)lanes[l];
#endif
}

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
    const int3 first = (int3)(b.coord[0], b.coord[1], b.coord[2]) * INTERIOR - APRON;
    sdf_real px[PER_ITEM], py[PER_ITEM], pz[PER_ITEM], field[PER_ITEM];
    for (uint s = 0; s < PER_ITEM; ++s) {
        const sdf_index idx = min((sdf_index)((s * wg + lid) * SDF_LANES) + SDF_LANE_OFFSETS, SAMPLE_COUNT - 1);
        px[s] = origin_x + (SDF_CONVERT_REAL(first.x + idx % SAMPLES) + 0.5f) * voxel;
        py[s] = origin_y + (SDF_CONVERT_REAL(first.y + (idx / SAMPLES) % SAMPLES) + 0.5f) * voxel;
        pz[s] = origin_z + (SDF_CONVERT_REAL(first.z + idx / (SAMPLES * SAMPLES)) + 0.5f) * voxel;
        field[s] = clamp_c;
    }
    for (uint base = 0; base < b.edit_count; base += chunk_size) {
        const uint n = min(chunk_size, b.edit_count - base);
        barrier(CLK_LOCAL_MEM_FENCE);
        for (uint j = lid; j < n; j += wg) chunk[j] = sdf_prepare(edits[edit_indices[b.edit_offset + base + j]]);
        barrier(CLK_LOCAL_MEM_FENCE);
        for (uint j = 0; j < n; ++j) {
            const SdfPrepared e = chunk[j];
            for (uint s = 0; s < PER_ITEM; ++s) field[s] = sdf_fold_at(&e, meshes, field[s], px[s], py[s], pz[s], clamp_c);
        }
    }
    __global sample_t* out = pool + (size_t)brick * SAMPLE_COUNT;
    for (uint s = 0; s < PER_ITEM; ++s) store_samples(out, (s * wg + lid) * SDF_LANES, field[s], band, quant_scale);
}
