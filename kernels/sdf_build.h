/* sdf_build.h: what every construction stage computes the same way (so that count, cull and
 * evaluate agree bit for bit).
 *
 * The band-limited field. Construction stores and tests F_C, the edit fold of sdf_edit.h with its
 * running value saturated to [-C, C] after every edit, starting from C:
 *     F_0 = C,  F_i = clamp(combine(op_i, k_i, F_{i-1}, v_i(p)), -C, C).
 * Why: an add or subtract edit whose value is >= C + k everywhere in a region, or an intersect edit
 * whose value is <= -(C + k) there, leaves F_C bit for bit unchanged in that region (|F - v| >= k makes
 * the smooth term exactly 0 and min/max return F). So culling such edits cannot change one bit of a
 * test or a sample, whatever the edits before and after them: culling on and off give identical
 * bricks. C = band + guard * (largest blend radius); docs/construction.md gives the argument, and how
 * far F_C is from the unsaturated field for each guard.
 */
#ifndef SDFBRICK_SDF_BUILD_H
#define SDFBRICK_SDF_BUILD_H

#include "sdf_edit.h"

/* The running value's saturation to [-C, C] after a combine of operation op. Where op is a constant
 * of the caller's (known: brick_evaluate's hoisted folds), an add or a subtract saturates one side:
 * the value before it is in [-C, C], and an add's min(F, v) less the smooth term (w^2 q >= 0) cannot
 * rise above F, nor a subtract's max(F, -v) plus it fall below F; the same bits. Where op is read at
 * run time its test cost more than the side it saves (an H100: edits_65536's evaluation 5.65 ->
 * 5.74 ms, drops' adaptive check 5.11 -> 5.38), so both sides are taken. */
inline sdf_real sdf_saturate(uint op, int known, sdf_real f, float clamp_c) {
    if (known && op == SDF_OP_ADD) return fmax(f, -clamp_c);
    if (known && op == SDF_OP_SUBTRACT) return fmin(f, clamp_c);
    return fmin(fmax(f, -clamp_c), clamp_c);
}
/* One step of the band-limited fold, at (x, y, z) (lanes: sdf_edit.h), for an edit of primitive prim
 * and operation op (constants fold the switches away: sdf_edit_value_unit, which also says what unit
 * is; known: op is a constant, sdf_saturate). */
inline sdf_real sdf_fold_unit(const SdfPrepared* e, uint prim, uint op, int unit, int known, __global const float* meshes,
                              sdf_real field, sdf_real x, sdf_real y, sdf_real z, float clamp_c) {
    const sdf_real f = sdf_combine_of(e, op, field, sdf_edit_value_unit(e, prim, unit, meshes, x, y, z));
    return sdf_saturate(op, known, f, clamp_c);
}
inline sdf_real sdf_fold_of(const SdfPrepared* e, uint prim, uint op, __global const float* meshes, sdf_real field,
                            sdf_real x, sdf_real y, sdf_real z, float clamp_c) {
    return sdf_fold_unit(e, prim, op, 0, 0, meshes, field, x, y, z, clamp_c);
}

#if SDF_LANES == 1
/* One step of the band-limited fold, at p. */
inline float sdf_fold(const SdfPrepared* e, __global const float* meshes, float field, float3 p, float clamp_c) {
    return sdf_fold_of(e, e->kind & 0xffu, (e->kind >> 8) & 0xffu, meshes, field, p.x, p.y, p.z, clamp_c);
}
#endif

/* Spheres and capsules. Their value is (sqrt(d2) - r) s for the squared distance d2 of the point
 * from the centre (point or segment) in the edit's frame and its output scale s. An add changes the
 * fold F only where that value is below F + k, a subtract only where it is below k - F; beyond, the
 * combine returns F (an add: min(F, v) - 0; a subtract: max(F, -v) + 0, which turns -0 into +0, as
 * the skip does). So a point where d2 s^2 >= bound^2, bound = max(+-F + offset, 0) with offset =
 * k + r s plus 2^-16 of (C + k + |r| s) for the rounding of every step, skips the square root and
 * the combine and keeps bit for bit the F that evaluating gives. */
inline float sdf_radial_offset(const SdfPrepared* e, uint prim, float clamp_c) {
    const float rs = (prim == SDF_PRIM_CAPSULE ? e->prm[1] : e->prm[0]) * e->out_scale;
    return e->blend + rs + (clamp_c + e->blend + fabs(rs)) * 1.52587890625e-05f;
}
inline float sdf_radial_bound(uint op, float field, float offset) {
    return fmax((op == SDF_OP_ADD ? field : -field) + offset, 0.0f);
}
/* What the fold gives where a sphere or capsule edit of operation op cannot change it (above). */
inline sdf_real sdf_radial_kept(float blend, uint op, sdf_real field) {
    return op == SDF_OP_ADD || !(blend > 0.0f) ? field : field + 0.0f;
}

#if SDF_LANES == 1
/* sdf_fold_of for a sphere or capsule (prim) edit of operation add or subtract (op), skipping where
 * it cannot change the fold. unit (a constant): the caller knows e's inv_scale and out_scale are 1,
 * so their products, exact, are left out (same bits); known: op is a constant (sdf_saturate). */
inline float sdf_fold_radial(const SdfPrepared* e, uint prim, uint op, int unit, int known, float field, float x,
                             float y, float z, float clamp_c, float offset) {
    float dx = x, dy = y, dz = z;
    sdf_edit_frame_of(e, !unit, &dx, &dy, &dz); /* as sdf_edit_value_of */
    if (prim == SDF_PRIM_CAPSULE) dy = dy - clamp(dy, -e->prm[0], e->prm[0]);
    const float d2 = sdf_squares3(dx, dy, dz); /* sdf_norm3's sum */
    const float bound = sdf_radial_bound(op, field, offset);
    if ((unit ? d2 : d2 * e->out_scale * e->out_scale) >= bound * bound) return sdf_radial_kept(e->blend, op, field);
    const float l = sqrt(d2) - (prim == SDF_PRIM_CAPSULE ? e->prm[1] : e->prm[0]);
    return sdf_saturate(op, known, sdf_combine_of(e, op, field, unit ? l : l * e->out_scale), clamp_c);
}
#endif

/* A margin for the rounding of a prepared edit's value at points whose coordinates are at most
 * magnitude in size, as in sdf_reach_limit: relative to the coordinates and the edit's size. */
inline float sdf_value_margin(const SdfPrepared* e, float magnitude) {
    const float reach = fmax(fmax(fabs(e->t[0]), fabs(e->t[1])), fabs(e->t[2])) +
                        fmax(fmax(fabs(e->prm[0]), fabs(e->prm[1])), fmax(fabs(e->prm[2]), fabs(e->prm[3]))) /
                            e->inv_scale;
    return (magnitude + reach) * 6.103515625e-05f; /* 2^-14 */
}

/* How far the fold saturated at [-S, S] (S > C) may sit from F_C, for smooth edit e whose value at
 * the centre of a cell is v, over points within radius of that centre: k/4 when e's smooth zone can
 * meet the saturation level +-C there (an add or subtract blends with F = C where |v - C| < k, an
 * intersect with F = -C where |v + C| < k), plus a rounding allowance for the chain of combines;
 * 0 for a hard edit (min, max and clamp are exact in float, so they add no difference).
 * docs/construction.md ("Sparse coarse levels") gives the argument. These are the terms of that
 * excess that do not depend on v; sdf_saturation_excess adds them up for one v. */
inline float4 sdf_excess_terms(const SdfPrepared* e, float clamp_c, float saturation, float radius, float magnitude) {
    if (!(e->blend > 0.0f)) return (float4)(0.0f, -INFINITY, 0.0f, 0.0f);
    const float margin = sdf_value_margin(e, magnitude);
    const uint op = (e->kind >> 8) & 0xffu;
    const float level = op == SDF_OP_INTERSECT ? -clamp_c : clamp_c;
    const float rounding = (saturation + e->blend) * 9.5367431640625e-07f; /* 2^-20 */
    return (float4)(level, e->blend + radius + margin, 0.25f * e->blend, rounding);
}

/* The excess itself from e's terms (sdf_excess_terms: level, reach, k/4, rounding; they do not depend
 * on v, so a work-group computes them once per edit) and e's value v. */
inline sdf_real sdf_saturation_excess(float4 terms, sdf_real v) {
    return select(SDF_SPLAT(0.0f), SDF_SPLAT(terms.z), fabs(v - terms.x) < terms.y) + terms.w;
}

/* An edit's combine as data, for a fold without a branch per edit (a branch serialises the loads of
 * the edit's parameters from __local memory): (sign of v, k or 0 when hard, k's q, rule: 1 = min
 * (add), 2 = max (subtract, intersect), 0 = none). sdf_fold_select gives bit for bit what
 * sdf_combine gives. */
inline float4 sdf_fold_params(const SdfPrepared* e) {
    const uint op = (e->kind >> 8) & 0xffu;
    const float rule = op == SDF_OP_ADD ? 1.0f : (op == SDF_OP_SUBTRACT || op == SDF_OP_INTERSECT) ? 2.0f : 0.0f;
    return (float4)(op == SDF_OP_SUBTRACT ? -1.0f : 1.0f, e->blend > 0.0f ? e->blend : 0.0f, e->blend_q, rule);
}

inline sdf_real sdf_fold_select(float4 f, sdf_real field, sdf_real v) {
    const sdf_real b = f.x * v; /* exact: v or -v */
    const sdf_real w = fmax(f.y - fabs(field - b), 0.0f);
    const sdf_real lo = fmin(field, b), hi = fmax(field, b);
    const int smooth = f.y > 0.0f;
    const sdf_real joined = smooth ? sdf_smooth_below(lo, w, f.z) : lo, cut = smooth ? sdf_smooth_above(hi, w, f.z) : hi;
    return f.w == 1.0f ? joined : f.w == 2.0f ? cut : field;
}

/* Centre of cell coord (in cells of size cell) of a lattice whose origin is origin. Computed in a
 * float4 whose fourth lane is 0: a float3 is four lanes in a CPU register, and the fourth was
 * whatever the stack or register held before, often an integer's bits, which read as a denormal and
 * cost the x86 a microcode assist per operation (PoCL, 2 cores: the sibling cull that makes
 * engraved_slab's finest lists took about 12 ms instead of 1.1 in captures where it did). Same values. */
inline float3 sdf_cell_centre(float3 origin, float cell, int3 coord) {
    const float4 o = (float4)(origin.x, origin.y, origin.z, 0.0f);
    const float4 c = (float4)((float)coord.x, (float)coord.y, (float)coord.z, 0.0f);
    return (o + (c + 0.5f) * cell).xyz;
}

/* Local coordinate (each axis in [0, B)) of the child with Morton index i; log2b = log2(B).
 * Bit 3j of i is bit j of x, bit 3j+1 of y, bit 3j+2 of z. */
inline int3 sdf_morton_child(uint i, uint log2b) {
    int3 c = (int3)(0);
    for (uint j = 0; j < log2b; ++j) {
        c.x |= (int)((i >> (3u * j)) & 1u) << j;
        c.y |= (int)((i >> (3u * j + 1u)) & 1u) << j;
        c.z |= (int)((i >> (3u * j + 2u)) & 1u) << j;
    }
    return c;
}

/* Whether an edit may change F_C anywhere within distance radius of point c, where v is its value at
 * c (1-Lipschitz: the value anywhere in that ball is within radius of v): sdf_within_reach(op, v,
 * limit) with the limit below. margin covers the rounding of v here and at the other points, relative
 * to the coordinates' magnitude and the edit's size (its reach: sdf_edit_reach, which edit_prepare.cl
 * keeps per edit). NaN keeps the edit. */
inline float sdf_edit_reach(const SdfEdit* e) {
    const float t = e->transform.translation[0], u = e->transform.translation[1], w = e->transform.translation[2];
    return fmax(fmax(fabs(t), fabs(u)), fabs(w)) +
           e->transform.scale * fmax(fmax(fabs(e->params[0]), fabs(e->params[1])),
                                     fmax(fabs(e->params[2]), fabs(e->params[3])));
}

inline float sdf_reach_limit(float blend, float reach, float clamp_c, float radius, float magnitude) {
    const float margin = (magnitude + reach) * 6.103515625e-05f; /* 2^-14 */
    return clamp_c + blend + radius + margin;
}

/* The test for an edit of operation op whose limit is sdf_reach_limit (per lane). */
inline sdf_index sdf_within_reach(uint op, sdf_real v, float limit) {
    return op == SDF_OP_INTERSECT ? !(v <= -limit) : !(v >= limit);
}

#endif /* SDFBRICK_SDF_BUILD_H */
