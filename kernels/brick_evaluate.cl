/* brick_evaluate.cl: stage "evaluate". One work-group per leaf brick evaluates the brick's owned
 * samples (owned_regions[brick]: its interior and the apron regions no neighbour evaluates; see
 * sdf_apron.h; brick_apron.cl copies the rest). They are spread over the work-items (up to PER_ITEM
 * values of sdf_real each, SDF_LANES samples per value, held in private memory). The brick's edits,
 * prepared once per build (edit_prepare.cl), are staged through __local memory in chunks of
 * chunk_size: load, barrier, every work-item folds the chunk into its samples, barrier, next chunk. With SKIP_RECORDS each staged edit has a skip record
 * beside it in `skips` (two float4: radial_record). Samples are written to the brick pool clamped to
 * +-band and stored as FORMAT: 0 = int8 snorm, 1 = int16 snorm, 2 = float32.
 * Compile-time: SAMPLES (S: 8 or 10), APRON (1 or 2), SDF_LANES (1, or the SIMD width of a CPU
 * device: sdf_edit.h), PER_ITEM (ceil(S^3 / (local size x lanes))), FORMAT,
 * APRON_SHARED (0: every leaf owns all its samples, and the kernel reads no owned_regions),
 * SKIP_FAR (1: sphere and capsule edits skip the work-items, and with one lane the samples, they
 * cannot change, below), SKIP_RECORDS (1 only with SKIP_FAR and lanes: the work-item's test reads
 * skip records, below),
 * EVAL_PRIMS and EVAL_OPS (the primitives and operations whose folds are compiled, below).
 * Lane l of value s of work-item lid holds owned sample (s * local size + lid) * lanes + l (with one
 * lane, consecutive work-items hold consecutive samples); a value whose first lane is past the last
 * owned sample is not evaluated, and lanes past it repeat the last one and are not stored.
 * Sample (i, j, k) of the brick at coord lies at origin + ((coord * (S - 2 APRON) + (i, j, k) - APRON)
 * + 0.5) * voxel: voxel centres, APRON of them outside the brick on every side. voxel, band and the
 * quantisation scale are the finest level's; a brick of a coarser level (adaptive builds) scales them
 * by its power of two, exactly, and folds with its level's saturation level_clamp[level]. */
#include "sdf_apron.h"
#include "sdf_build.h"
#include "sdf_format.h"

/* Where the c-th owned sample is stored: a brick that owns every region (all) numbers its samples as
 * they are stored; another numbers its interior first and reads the shell's from the table
 * apron_owned_shell filled. */
inline uint owned_index(uint c, int all, __local const ushort* shell) {
    if (all) return c;
    return c < APRON_INTERIOR_COUNT ? apron_region_sample(APRON_INTERIOR_REGION, c) : (uint)shell[c - APRON_INTERIOR_COUNT];
}

/* The sample indices of the value whose first lane is owned sample c: lane l holds owned sample
 * min(c + l, owned - 1). */
inline sdf_index value_samples(uint c, uint owned, int all, __local const ushort* shell) {
#if SDF_LANES == 1
    return (int)owned_index(min(c, owned - 1u), all, shell);
#else
    if (all) return min((sdf_index)((int)c) + SDF_LANE_OFFSETS, (int)owned - 1);
    int a[SDF_LANES];
    for (uint l = 0; l < SDF_LANES; ++l) a[l] = (int)owned_index(min(c + l, owned - 1u), 0, shell);
    return SDF_REAL_CAT(vload, SDF_LANES)(0, a);
#endif
}

/* Stores the value whose first lane is owned sample c (lanes past the last owned sample are dropped). */
inline void store_samples(__global sample_t* out, uint c, uint owned, int all, __local const ushort* shell,
                          sdf_real field, float band, float quant_scale) {
    const sdf_real d = fmin(fmax(field, -band), band);
#if FORMAT == 2
    const sdf_real q = d;
#else
    const sdf_real q = rint(d * quant_scale);
#endif
    float lanes[SDF_LANES];
    sdf_spill_lanes(q, lanes);
    for (uint l = 0; l < SDF_LANES && c + l < owned; ++l) out[owned_index(c + l, all, shell)] = (sample_t)lanes[l];
}

/* A sphere (centre xyz, radius w) around the samples of the work-item's first active values (every
 * lane: lanes past the last owned sample repeat it); w includes 2^-20 of the centre's coordinates
 * for the rounding of the centre. */
inline float4 item_sphere(const sdf_real* px, const sdf_real* py, const sdf_real* pz, uint active) {
    sdf_real lx = SDF_SPLAT(INFINITY), ly = lx, lz = lx, hx = SDF_SPLAT(-INFINITY), hy = hx, hz = hx;
    for (uint s = 0; s < PER_ITEM; ++s)
        if (s < active) {
            lx = fmin(lx, px[s]);
            ly = fmin(ly, py[s]);
            lz = fmin(lz, pz[s]);
            hx = fmax(hx, px[s]);
            hy = fmax(hy, py[s]);
            hz = fmax(hz, pz[s]);
        }
    const float3 lo = (float3)(sdf_lanes_min(lx), sdf_lanes_min(ly), sdf_lanes_min(lz));
    const float3 hi = (float3)(sdf_lanes_max(hx), sdf_lanes_max(hy), sdf_lanes_max(hz));
    const float3 c = 0.5f * (lo + hi), h = hi - c;
    const float w = sqrt(h.x * h.x + h.y * h.y + h.z * h.z) + (fabs(c.x) + fabs(c.y) + fabs(c.z)) * 9.5367431640625e-07f;
    return (float4)(c, w);
}

/* The skip record of a sphere or capsule (prim) edit: the centre and g = inv_scale out_scale, then
 * inv_scale, a capsule's half length (0 for a sphere), out_scale and sdf_radial_offset at the
 * brick's saturation. */
inline void radial_values(const SdfPrepared* e, uint prim, float clamp_c, float4* a, float4* b) {
    *a = (float4)(e->t[0], e->t[1], e->t[2], e->inv_scale * e->out_scale);
    *b = (float4)(e->inv_scale, prim == SDF_PRIM_CAPSULE ? fabs(e->prm[0]) : 0.0f, e->out_scale,
                  sdf_radial_offset(e, prim, clamp_c));
}

/* Whether every sample of the work-item passes sdf_fold_radial's skip test for the sphere or capsule
 * edit whose record is (a, b), bound being that test's bound at the item's extreme F (item_extreme).
 * The samples lie within item.w of item.xyz, so in the edit's frame they are at least
 * (|item.xyz - t| - item.w) / scale from its centre, and from a capsule's segment at least that less
 * its half length. The factor 1 + 2^-14 covers the rounding of both tests. */
inline int item_beyond(float4 a, float4 b, float4 item, float bound) {
    const float dx = item.x - a.x, dy = item.y - a.y, dz = item.z - a.z;
    const float reach = fma(fma(item.w, b.x, b.y), b.z, bound) * 1.00006103515625f;
    return fma(dz, dz, fma(dy, dy, dx * dx)) * a.w * a.w >= reach * reach;
}

/* With CPU lanes (SKIP_RECORDS) the work-group writes each staged edit's record once into __local
 * memory, which saves every work-item the loads and products of the test (PoCL here: drops'
 * evaluation 13% shorter, docs/performance.md), and the test runs in the loop over the chunk. With
 * one lane (GPUs) the records' local memory cost more than that (an H100: drops' evaluation 3.00 ->
 * 3.47 ms), and the test runs inside the fold, per primitive (FOLD_RADIAL_OP). */
inline void radial_record(const SdfPrepared* e, float clamp_c, __local float4* r) {
    const uint prim = e->kind & 0xffu;
    float4 a = (float4)(0.0f), b = (float4)(0.0f);
    if (prim == SDF_PRIM_SPHERE || prim == SDF_PRIM_CAPSULE) radial_values(e, prim, clamp_c, &a, &b);
    r[0] = a;
    r[1] = b;
}

/* Where the test passed, every value keeps what the fold gives there (sdf_radial_kept: a smooth
 * subtract turns -0 into +0). */
inline void radial_kept_values(uint op, float blend, sdf_real* field, uint active) {
    for (uint s = 0; s < PER_ITEM; ++s)
        if (s < active) field[s] = sdf_radial_kept(blend, op, field[s]);
}

/* EVAL_PRIMS and EVAL_OPS: bit p set for each primitive p, bit o for each operation o that the
 * geometry's edits use (the host sets them; unset, every one). The folds of the others are not
 * compiled: on an H100 drops' evaluation (sphere adds alone) took 3.00 ms instead of 3.87, with 71
 * registers instead of 76, and rubble's (four primitives, adds) 12.7 instead of 14.8, with the same
 * bits (docs/performance.md). */
#ifndef EVAL_PRIMS
#define EVAL_PRIMS 0xffffffffu
#endif
#ifndef EVAL_OPS
#define EVAL_OPS 0xffffffffu
#endif
#define HAS_PRIM(P) (((EVAL_PRIMS) >> (P)) & 1u)
#define HAS_OP(O) (((EVAL_OPS) >> (O)) & 1u)
#define HAS_OTHER_OP (((EVAL_OPS) & ~((1u << SDF_OP_ADD) | (1u << SDF_OP_SUBTRACT))) != 0u)

/* The work-item's largest F (an add, op) or smallest (a subtract), which bounds every sample's. An
 * edit the test skips leaves them as they were (sdf_radial_kept changes at most a zero's sign), so
 * in CPU lanes both are kept (x) and computed again only when a test needs them and an edit folded
 * since (x->stale): the same bounds, for fewer operations (PoCL here: drops' evaluation at 0.125
 * 220-232 -> 177-185 ms). With one lane a work-item's few values cost less than keeping them (an
 * H100: drops' 2.571 -> 2.592 ms kept, sculpt_dense's 20.56-20.58 -> 20.89). */
typedef struct {
    float2 f;
    int stale;
} Extremes;
inline float item_extreme(Extremes* x, uint op, const sdf_real* field, uint active) {
#if SDF_LANES == 1
    float extreme = op == SDF_OP_ADD ? -INFINITY : INFINITY;
    for (uint s = 0; s < PER_ITEM; ++s)
        if (s < active) extreme = op == SDF_OP_ADD ? fmax(extreme, field[s]) : fmin(extreme, field[s]);
    return extreme;
#else
    if (x->stale) {
        sdf_real hi = SDF_SPLAT(-INFINITY), lo = SDF_SPLAT(INFINITY);
        for (uint s = 0; s < PER_ITEM; ++s)
            if (s < active) {
                if (HAS_OP(SDF_OP_ADD)) hi = fmax(hi, field[s]);
                if (HAS_OP(SDF_OP_SUBTRACT)) lo = fmin(lo, field[s]);
            }
        x->f = (float2)(HAS_OP(SDF_OP_ADD) ? sdf_lanes_max(hi) : 0.0f, HAS_OP(SDF_OP_SUBTRACT) ? sdf_lanes_min(lo) : 0.0f);
        x->stale = 0;
    }
    return op == SDF_OP_ADD ? x->f.x : x->f.y;
#endif
}
inline int radial_skips(__local const float4* r, uint op, float4 item, Extremes* x, const sdf_real* field, uint active) {
    const float4 a = r[0], b = r[1];
    return item_beyond(a, b, item, sdf_radial_bound(op, item_extreme(x, op, field, active), b.w));
}

#if SDF_LANES == 1
/* Whether an add or subtract edit e of another primitive than a sphere or capsule cannot change any
 * of the work-item's values: its value v at the item's centre, less the item's radius (the field is
 * 1-Lipschitz, as the cull assumes) and a margin for the rounding of v there and at the samples
 * (sdf_value_margin), is above F + k for every sample (an add) or above k - F (a subtract). Then
 * |F - v| > k leaves no smooth term, and min(F, v) or max(F, -v) returns F (strictly: the margin is
 * above 0), which sdf_radial_kept gives. One evaluation a work-item instead of one a value; in CPU
 * lanes a work-item's samples spread too far for the test to pass often, and it is not compiled. */
inline int item_far(const SdfPrepared* e, uint prim, uint op, __global const float* meshes, float4 item, Extremes* x,
                    const float* field, uint active) {
    if (!((op == SDF_OP_ADD && HAS_OP(SDF_OP_ADD)) || (op == SDF_OP_SUBTRACT && HAS_OP(SDF_OP_SUBTRACT)))) return 0;
    const float v = sdf_edit_value_of(e, prim, meshes, item.x, item.y, item.z);
    const float margin = sdf_value_margin(e, fmax(fmax(fabs(item.x), fabs(item.y)), fabs(item.z)) + item.w);
    const float most = item_extreme(x, op, field, active);
    return v - item.w - margin > (op == SDF_OP_ADD ? most : -most) + e->blend;
}
#endif

#if SKIP_RECORDS && !(SKIP_FAR && SDF_LANES > 1)
#error "skip records serve the work-item test in lanes only"
#endif

/* Folds edit e into this work-item's first active values, the primitive and operation branched on
 * once per edit, outside the loop over the values. (Short lists used to branch once per value, which
 * an H200 once measured faster on rain; with the work-item's skip tests an H100 took rain's
 * evaluation from 2.40 ms to 1.37 branching once per edit, board's from 0.95 to 0.77, and no scene's
 * longer: docs/measurements/roof/d76.txt.) */
#define FOLD_UNIT_VALUES(PRIM, OP, UNIT, KNOWN)                                                            \
    for (uint s = 0; s < PER_ITEM; ++s)                                                                    \
        if (s < active) field[s] = sdf_fold_unit(e, PRIM, OP, UNIT, KNOWN, meshes, field[s], px[s], py[s], pz[s], clamp_c)
#define FOLD_VALUES(PRIM, OP) FOLD_UNIT_VALUES(PRIM, OP, 0, 0)
/* Hoisted, an add or subtract whose scales are 1 folds without their products (sdf_edit_value_unit). */
#define FOLD_SCALED(PRIM, OP)                                                                              \
    if (unit) {                                                                                            \
        FOLD_UNIT_VALUES(PRIM, OP, 1, 1);                                                                  \
    } else {                                                                                               \
        FOLD_UNIT_VALUES(PRIM, OP, 0, 1);                                                                  \
    }
#define FOLD_PRIM(PRIM)                                                                                    \
    switch (op) {                                                                                          \
        case SDF_OP_ADD: if (HAS_OP(SDF_OP_ADD)) { FOLD_SCALED(PRIM, SDF_OP_ADD); } break;                 \
        case SDF_OP_SUBTRACT: if (HAS_OP(SDF_OP_SUBTRACT)) { FOLD_SCALED(PRIM, SDF_OP_SUBTRACT); } break;  \
        default: if (HAS_OTHER_OP) FOLD_VALUES(PRIM, op); break;                                           \
    }
/* A sphere or capsule (PRIM) edit of operation OP with one lane: the work-item's skip test first
 * (item_beyond), then sdf_fold_radial per value where it failed. In lanes the test ran in the loop
 * over the chunk (radial_skips) and the whole fold follows. On an H200, drops' evaluation (no shared
 * aprons) took 5.15 ms with the per-value test alone and 3.70 with both (docs/performance.md). */
#if SKIP_FAR && SDF_LANES == 1
#define FOLD_RADIAL_VALUES(PRIM, OP, UNIT)                                                                 \
    for (uint s = 0; s < PER_ITEM; ++s)                                                                    \
        if (s < active) field[s] = sdf_fold_radial(e, PRIM, OP, UNIT, 1, field[s], px[s], py[s], pz[s], clamp_c, b.w)
#define FOLD_RADIAL_OP(PRIM, OP)                                                                           \
    {                                                                                                      \
        float4 a, b;                                                                                       \
        radial_values(e, PRIM, clamp_c, &a, &b);                                                           \
        if (!item_beyond(a, b, item, sdf_radial_bound(OP, item_extreme(extremes, OP, field, active), b.w))) { \
            if (unit) {                                                                                    \
                FOLD_RADIAL_VALUES(PRIM, OP, 1);                                                           \
            } else {                                                                                       \
                FOLD_RADIAL_VALUES(PRIM, OP, 0);                                                           \
            }                                                                                              \
        } else {                                                                                           \
            radial_kept_values(OP, e->blend, field, active);                                               \
            folded = 0;                                                                                    \
        }                                                                                                  \
    }
#define FOLD_RADIAL(PRIM)                                                                                  \
    switch (op) {                                                                                          \
        case SDF_OP_ADD: if (HAS_OP(SDF_OP_ADD)) FOLD_RADIAL_OP(PRIM, SDF_OP_ADD); break;                  \
        case SDF_OP_SUBTRACT: if (HAS_OP(SDF_OP_SUBTRACT)) FOLD_RADIAL_OP(PRIM, SDF_OP_SUBTRACT); break;   \
        default: if (HAS_OTHER_OP) FOLD_VALUES(PRIM, op); break;                                           \
    }
/* Another primitive than a sphere or capsule with one lane: the work-item's test (item_far) first,
 * with PRIM a constant, so that a geometry compiles the values of its own primitives alone. */
#define FOLD_NEAR(PRIM)                                                                                    \
    if (item_far(e, PRIM, op, meshes, item, extremes, field, active)) {                                    \
        radial_kept_values(op, e->blend, field, active);                                                   \
        folded = 0;                                                                                        \
    } else {                                                                                               \
        FOLD_PRIM(PRIM);                                                                                   \
    }
#else
#define FOLD_RADIAL(PRIM) FOLD_PRIM(PRIM) /* in lanes, or SKIP_FAR 0: every sample is evaluated */
#define FOLD_NEAR(PRIM) FOLD_PRIM(PRIM)
#endif
/* Folds e; marks the extremes stale unless the work-item's skip test kept every value. */
inline void fold_values(const SdfPrepared* e, __global const float* meshes, sdf_real* field, const sdf_real* px,
                        const sdf_real* py, const sdf_real* pz, float clamp_c, uint active, float4 item,
                        Extremes* extremes) {
    const uint prim = e->kind & 0xffu, op = (e->kind >> 8) & 0xffu;
    int folded = 1;
    const int unit = sdf_unit_scale(e);
    switch (prim) {
        case SDF_PRIM_SPHERE: if (HAS_PRIM(SDF_PRIM_SPHERE)) FOLD_RADIAL(SDF_PRIM_SPHERE); break;
        case SDF_PRIM_BOX: if (HAS_PRIM(SDF_PRIM_BOX)) FOLD_NEAR(SDF_PRIM_BOX); break;
        case SDF_PRIM_ROUND_BOX: if (HAS_PRIM(SDF_PRIM_ROUND_BOX)) FOLD_NEAR(SDF_PRIM_ROUND_BOX); break;
        case SDF_PRIM_TORUS: if (HAS_PRIM(SDF_PRIM_TORUS)) FOLD_NEAR(SDF_PRIM_TORUS); break;
        case SDF_PRIM_CAPSULE: if (HAS_PRIM(SDF_PRIM_CAPSULE)) FOLD_RADIAL(SDF_PRIM_CAPSULE); break;
        case SDF_PRIM_CYLINDER: if (HAS_PRIM(SDF_PRIM_CYLINDER)) FOLD_NEAR(SDF_PRIM_CYLINDER); break;
        case SDF_PRIM_CONE: if (HAS_PRIM(SDF_PRIM_CONE)) FOLD_NEAR(SDF_PRIM_CONE); break;
        case SDF_PRIM_ELLIPSOID: if (HAS_PRIM(SDF_PRIM_ELLIPSOID)) FOLD_NEAR(SDF_PRIM_ELLIPSOID); break;
        /* Menger, mesh: long enough that the switch costs nothing */
        default: if (HAS_PRIM(SDF_PRIM_MENGER) || HAS_PRIM(SDF_PRIM_MESH)) FOLD_VALUES(prim, op); break;
    }
    if (folded) extremes->stale = 1;
}

__kernel void brick_evaluate(__global const SdfPrepared* edits, __global const float* meshes, __global const uint* edit_indices,
                             __global const SdfBrick* bricks, __global const uint* owned_regions,
                             float origin_x, float origin_y, float origin_z, float finest_voxel,
                             __global const float* level_clamp, float finest_band, float finest_quant_scale,
                             uint finest, uint log2b,
                             __global sample_t* pool, __local SdfPrepared* chunk, __local float4* skips,
                             uint chunk_size) {
    const uint brick = get_group_id(0);
    const uint lid = get_local_id(0), wg = get_local_size(0);
    const SdfBrick b = bricks[brick];
    __local ushort shell[APRON_SHELL];
    const int shift = (int)((finest - b.level) * log2b);
    /* Products with 2^shift and 2^-shift, exact as ldexp is (the same bits: shift is below 64), but
     * without the range handling NVIDIA's ldexp expands to. */
    const float up = as_float((uint)(127 + shift) << 23), down = as_float((uint)(127 - shift) << 23);
    const float voxel = finest_voxel * up, band = finest_band * up;
    const float quant_scale = finest_quant_scale * down, clamp_c = level_clamp[b.level];
    const int3 first = (int3)(b.coord[0], b.coord[1], b.coord[2]) * INTERIOR - APRON;
#if SDF_LANES == 1
    /* With one lane the samples' coordinates come from a table per axis, filled once per brick (the
     * same expression, so the same bits). */
    __local float coords[3 * SAMPLES];
    for (uint i = lid; i < 3u * SAMPLES; i += wg) {
        const uint a = i / SAMPLES;
        const float o = a == 0u ? origin_x : a == 1u ? origin_y : origin_z;
        const int f = a == 0u ? first.x : a == 1u ? first.y : first.z;
        coords[i] = o + ((float)(f + (int)(i % SAMPLES)) + 0.5f) * voxel;
    }
#endif
#if APRON_SHARED
    const uint mask = owned_regions[brick];
    const int all = mask == APRON_ALL_REGIONS;
    const uint owned = all ? SAMPLE_COUNT : apron_owned_count(mask);
    if (!all) apron_owned_shell(mask, shell); /* the same branch in every work-item */
    const uint span = wg * SDF_LANES; /* owned samples per value slot of the work-group */
    const uint active = lid * SDF_LANES < owned ? min((uint)PER_ITEM, (owned - lid * SDF_LANES + span - 1u) / span) : 0u;
#else
    const int all = 1;
    const uint owned = SAMPLE_COUNT, active = PER_ITEM; /* a build that shares nothing */
#endif
    barrier(CLK_LOCAL_MEM_FENCE); /* the tables above */
    sdf_real px[PER_ITEM], py[PER_ITEM], pz[PER_ITEM], field[PER_ITEM];
    for (uint s = 0; s < PER_ITEM; ++s) {
        const sdf_index idx = value_samples((s * wg + lid) * SDF_LANES, owned, all, shell);
#if SDF_LANES == 1
        px[s] = coords[idx % SAMPLES];
        py[s] = coords[SAMPLES + (idx / SAMPLES) % SAMPLES];
        pz[s] = coords[2 * SAMPLES + idx / (SAMPLES * SAMPLES)];
#else
        px[s] = origin_x + (SDF_CONVERT_REAL(first.x + idx % SAMPLES) + 0.5f) * voxel;
        py[s] = origin_y + (SDF_CONVERT_REAL(first.y + (idx / SAMPLES) % SAMPLES) + 0.5f) * voxel;
        pz[s] = origin_z + (SDF_CONVERT_REAL(first.z + idx / (SAMPLES * SAMPLES)) + 0.5f) * voxel;
#endif
        field[s] = clamp_c;
    }
#if SKIP_FAR
    const float4 item = item_sphere(px, py, pz, active);
#else
    const float4 item = (float4)(0.0f); /* unused */
#endif
    Extremes extremes = {(float2)(0.0f), 1};
    for (uint base = 0; base < b.edit_count; base += chunk_size) {
        const uint n = min(chunk_size, b.edit_count - base);
        barrier(CLK_LOCAL_MEM_FENCE);
        for (uint j = lid; j < n; j += wg) {
            const SdfPrepared e = edits[edit_indices[b.edit_offset + base + j]];
            chunk[j] = e;
#if SKIP_RECORDS
            radial_record(&e, clamp_c, skips + 2 * j);
#endif
        }
        barrier(CLK_LOCAL_MEM_FENCE);
        for (uint j = 0; j < n; ++j) {
#if SKIP_RECORDS
            /* The skip test for the whole work-item, from the edit's record (in lanes). */
            const uint kind = chunk[j].kind, prim = kind & 0xffu, op = (kind >> 8) & 0xffu;
            if (((prim == SDF_PRIM_SPHERE && HAS_PRIM(SDF_PRIM_SPHERE)) ||
                 (prim == SDF_PRIM_CAPSULE && HAS_PRIM(SDF_PRIM_CAPSULE))) &&
                ((op == SDF_OP_ADD && HAS_OP(SDF_OP_ADD)) || (op == SDF_OP_SUBTRACT && HAS_OP(SDF_OP_SUBTRACT))) &&
                radial_skips(skips + 2 * j, op, item, &extremes, field, active)) {
                radial_kept_values(op, chunk[j].blend, field, active);
                continue;
            }
#endif
            const SdfPrepared e = chunk[j];
            fold_values(&e, meshes, field, px, py, pz, clamp_c, active, item, &extremes);
        }
    }
    __global sample_t* out = pool + (size_t)brick * SAMPLE_COUNT;
    for (uint s = 0; s < active; ++s)
        store_samples(out, (s * wg + lid) * SDF_LANES, owned, all, shell, field[s], band, quant_scale);
}
