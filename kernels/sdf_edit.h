/* sdf_edit.h: evaluation of edits and edit lists, shared by every kernel that reads the field.
 *
 * Determinism (docs/design.md#determinism): only + - * / sqrt fma fabs fmin fmax floor, with FP_CONTRACT
 * OFF (the program builder puts the pragma first) and correctly rounded divide/sqrt where the device
 * supports it. fma is written out where it is meant (OpenCL C requires it correctly rounded, so every
 * device gives its bits); the compiler fuses nothing. No built-in dot/length/normalize/distance/mix:
 * their rounding and fusing are not specified, so the sums are written out here in a fixed order.
 * The formulas are documented in docs/scene-format.md; host/reference/ evaluates the same
 * definitions independently in double precision.
 *
 * Lanes. The field functions below take the point as components of type sdf_real: float, or, in a
 * program built with -DSDF_LANES=N (N = 2, 4, 8 or 16), floatN, one point per lane (brick_evaluate
 * on CPU devices, whose compilers map floatN onto SIMD registers). Every lane goes through the same
 * operations in the same order as the float build, and vector operations round each lane as the
 * scalar operation does, so a lane's result is bit for bit the float result. Edit parameters stay
 * scalar (uniform across the lanes). The float3 wrappers exist in float builds only.
 */
#ifndef SDFBRICK_SDF_EDIT_H
#define SDFBRICK_SDF_EDIT_H

#include "sdf_types.h"

#ifndef SDF_LANES
#define SDF_LANES 1
#endif
#if SDF_LANES == 1
typedef float sdf_real;
#else
#define SDF_REAL_CAT(a, b) SDF_REAL_CAT_(a, b)
#define SDF_REAL_CAT_(a, b) a##b
typedef SDF_REAL_CAT(float, SDF_LANES) sdf_real;
#endif
#define SDF_SPLAT(x) ((sdf_real)(x))

/* Integer lanes beside sdf_real (one index per lane), their conversion, and the lane numbers. */
#if SDF_LANES == 1
typedef int sdf_index;
#define SDF_CONVERT_REAL convert_float
#define SDF_LANE_OFFSETS 0
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

/* The largest and the smallest lane of v (halves at a time: neither depends on the lanes' order). */
inline float sdf_lanes_max(sdf_real v) {
#if SDF_LANES == 1
    return v;
#else
#if SDF_LANES == 16
    const float8 m8 = fmax(v.lo, v.hi);
    const float4 m4 = fmax(m8.lo, m8.hi);
#elif SDF_LANES == 8
    const float4 m4 = fmax(v.lo, v.hi);
#elif SDF_LANES == 4
    const float4 m4 = v;
#endif
#if SDF_LANES >= 4
    const float2 m2 = fmax(m4.lo, m4.hi);
#else
    const float2 m2 = v;
#endif
    return fmax(m2.x, m2.y);
#endif
}
inline float sdf_lanes_min(sdf_real v) { return -sdf_lanes_max(-v); }

/* The lanes of v into a[0 .. SDF_LANES) in private memory, to be taken one at a time. */
inline void sdf_spill_lanes(sdf_real v, float* a) {
#if SDF_LANES == 1
    a[0] = v;
#else
    SDF_REAL_CAT(vstore, SDF_LANES)(v, 0, a);
#endif
}

inline float sdf_dot2(float ax, float ay, float bx, float by) { return ax * bx + ay * by; }
inline float sdf_dot3(float3 a, float3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline float sdf_len3(float3 a) { return sqrt(sdf_dot3(a, a)); }
inline float sdf_max3(float3 a) { return fmax(fmax(a.x, a.y), a.z); }
inline float sdf_min3(float3 a) { return fmin(fmin(a.x, a.y), a.z); }

/* Sums of squares over lanes as chains of fma (one rounding a term after the first: fewer operations
 * than products and sums, and as exact or more). */
inline sdf_real sdf_squares2(sdf_real x, sdf_real y) { return fma(y, y, x * x); }
inline sdf_real sdf_squares3(sdf_real x, sdf_real y, sdf_real z) { return fma(z, z, fma(y, y, x * x)); }
inline sdf_real sdf_len2(sdf_real x, sdf_real y) { return sqrt(sdf_squares2(x, y)); }
inline sdf_real sdf_norm3(sdf_real x, sdf_real y, sdf_real z) { return sqrt(sdf_squares3(x, y, z)); }

/* Rotate (x, y, z) in place by the conjugate of the unit quaternion q = (x, y, z, w):
 * t = 2 cross(u, v); v' = v + w t + cross(u, t), u = -q.xyz. A cross product's a b - c d is
 * fma(a, b, (-c) d), and v + w t is fma(w, t, v). */
inline void sdf_rotate_inverse(const float q[4], sdf_real* x, sdf_real* y, sdf_real* z) {
    const sdf_real ux = SDF_SPLAT(-q[0]), uy = SDF_SPLAT(-q[1]), uz = SDF_SPLAT(-q[2]), w = SDF_SPLAT(q[3]);
    const sdf_real nx = SDF_SPLAT(q[0]), ny = SDF_SPLAT(q[1]), nz = SDF_SPLAT(q[2]); /* -u */
    const sdf_real vx = *x, vy = *y, vz = *z;
    const sdf_real tx = 2.0f * fma(uy, vz, nz * vy), ty = 2.0f * fma(uz, vx, nx * vz), tz = 2.0f * fma(ux, vy, ny * vx);
    *x = fma(w, tx, vx) + fma(uy, tz, nz * ty);
    *y = fma(w, ty, vy) + fma(uz, tx, nx * tz);
    *z = fma(w, tz, vz) + fma(ux, ty, ny * tx);
}

inline sdf_real sdf_box(sdf_real x, sdf_real y, sdf_real z, float bx, float by, float bz) {
    const sdf_real qx = fabs(x) - bx, qy = fabs(y) - by, qz = fabs(z) - bz;
    return sdf_norm3(fmax(qx, 0.0f), fmax(qy, 0.0f), fmax(qz, 0.0f)) + fmin(fmax(fmax(qx, qy), qz), 0.0f);
}

inline sdf_real sdf_cone(sdf_real x, sdf_real y, sdf_real z, float h, float r1, float r2) {
    const sdf_real qx = sdf_len2(x, z), qy = y;
    const float k1x = r2, k1y = h;
    const float k2x = r2 - r1, k2y = 2.0f * h;
    const sdf_real cax = qx - fmin(qx, select(SDF_SPLAT(r2), SDF_SPLAT(r1), qy < 0.0f));
    const sdf_real cay = fabs(qy) - h;
    const sdf_real t = clamp(((k1x - qx) * k2x + (k1y - qy) * k2y) / sdf_dot2(k2x, k2y, k2x, k2y), 0.0f, 1.0f);
    const sdf_real cbx = qx - k1x + k2x * t;
    const sdf_real cby = qy - k1y + k2y * t;
    const sdf_real s = select(SDF_SPLAT(1.0f), SDF_SPLAT(-1.0f), cbx < 0.0f && cay < 0.0f);
    return s * sqrt(fmin(cax * cax + cay * cay, cbx * cbx + cby * cby));
}

inline sdf_real sdf_menger(sdf_real x, sdf_real y, sdf_real z, float half_size, int iterations) {
    const sdf_real ux = x / half_size, uy = y / half_size, uz = z / half_size;
    sdf_real d = sdf_box(ux, uy, uz, 1.0f, 1.0f, 1.0f);
    float sc = 1.0f;
    for (int i = 0; i < iterations; ++i) {
        const sdf_real px = ux * sc, py = uy * sc, pz = uz * sc;
        /* mod(p, 2) - 1 */
        const sdf_real ax = px - 2.0f * floor(px * 0.5f) - 1.0f, ay = py - 2.0f * floor(py * 0.5f) - 1.0f,
                       az = pz - 2.0f * floor(pz * 0.5f) - 1.0f;
        sc *= 3.0f;
        const sdf_real rx = fabs(1.0f - 3.0f * fabs(ax)), ry = fabs(1.0f - 3.0f * fabs(ay)), rz = fabs(1.0f - 3.0f * fabs(az));
        const sdf_real da = fmax(rx, ry), db = fmax(ry, rz), dc = fmax(rz, rx);
        d = fmax(d, (fmin(fmin(da, db), dc) - 1.0f) / sc);
    }
    return d * half_size;
}

/* Distance of a primitive in its local frame (before scale and Lipschitz division). */
inline sdf_real sdf_primitive(uint kind, const float prm[4], sdf_real x, sdf_real y, sdf_real z) {
    switch (kind) {
        case SDF_PRIM_SPHERE: return sdf_norm3(x, y, z) - prm[0];
        case SDF_PRIM_BOX: return sdf_box(x, y, z, prm[0], prm[1], prm[2]);
        case SDF_PRIM_ROUND_BOX: return sdf_box(x, y, z, prm[0] - prm[3], prm[1] - prm[3], prm[2] - prm[3]) - prm[3];
        case SDF_PRIM_TORUS: return sdf_len2(sdf_len2(x, z) - prm[0], y) - prm[1];
        case SDF_PRIM_CAPSULE: return sdf_norm3(x, y - clamp(y, -prm[0], prm[0]), z) - prm[1];
        case SDF_PRIM_CYLINDER: {
            const sdf_real dx = sdf_len2(x, z) - prm[1], dy = fabs(y) - prm[0];
            return fmin(fmax(dx, dy), 0.0f) + sdf_len2(fmax(dx, 0.0f), fmax(dy, 0.0f));
        }
        case SDF_PRIM_CONE: return sdf_cone(x, y, z, prm[0], prm[1], prm[2]);
        case SDF_PRIM_ELLIPSOID:
            return (sdf_norm3(x / prm[0], y / prm[1], z / prm[2]) - 1.0f) * fmin(fmin(prm[0], prm[1]), prm[2]);
        case SDF_PRIM_MENGER: return sdf_menger(x, y, z, prm[0], (int)prm[1]);
        default: return SDF_SPLAT(SDF_FAR);
    }
}

/* A mesh edit's local distance: the trilinear interpolant of its grid (pool header `index`), and
 * outside the grid's box the distance to the box plus the interpolant at the box's nearest point.
 * The grid holds exact distances (1-Lipschitz), so each partial derivative of the interpolant is at
 * most 1 in magnitude: the interpolant is sqrt(3)-Lipschitz, and so is the continuation outside the
 * box (a face region adds a unit normal slope to two tangential ones, an edge region one, a corner
 * none). The edit divides by L = sqrt(3) (SdfEdit.inv_lipschitz). */
inline float sdf_mesh(__global const float* meshes, uint index, float3 p) {
    __global const SdfMeshGrid* g = (__global const SdfMeshGrid*)meshes + index;
    const uint nx = g->dims[0], ny = g->dims[1];
    const float3 top = (float3)((float)(nx - 1u), (float)(ny - 1u), (float)(g->dims[2] - 1u));
    const float3 u = (p - (float3)(g->origin[0], g->origin[1], g->origin[2])) * g->inv_cell;
    const float3 c = fmin(fmax(u, (float3)(0.0f)), top);
    const float outside = sdf_len3(u - c) * g->cell;
    const float3 base = fmin(floor(c), top - 1.0f);
    float3 f = c - base;
    const uint i = (uint)base.x, j = (uint)base.y, k = (uint)base.z;
    __global const float* v = meshes + g->offset + i + nx * (j + ny * k);
    uint sy = nx, sz = nx * ny;
    if (g->tiles != 0u) {
        /* sparse: the cell's tile, or the coarse grid where the tile is far from the surface */
        const uint tx = i >> 3, ty = j >> 3, tz = k >> 3, tnx = (nx + 6u) >> 3, tny = (ny + 6u) >> 3;
        const uint block = as_uint(meshes[g->tiles + tx + tnx * (ty + tny * tz)]);
        if (block != SDF_MESH_NO_TILE) {
            v = meshes + block + (i & 7u) + 9u * ((j & 7u) + 9u * (k & 7u));
            sy = 9u;
            sz = 81u;
        } else {
            /* far from the surface: a lower bound from the exact distances at the corners and centre */
            const float3 q = c - (float3)((float)(tx << 3), (float)(ty << 3), (float)(tz << 3));
            const float centre = meshes[g->centres + tx + tnx * (ty + tny * tz)];
            float bound = fabs(centre) - sdf_len3(q - (float3)(4.0f)) * g->cell;
            v = meshes + g->coarse + tx + (tnx + 1u) * (ty + (tny + 1u) * tz);
            sy = tnx + 1u;
            sz = (tnx + 1u) * (tny + 1u);
            for (uint n = 0u; n < 8u; ++n) {
                const float3 o = (float3)((float)(n & 1u), (float)((n >> 1) & 1u), (float)(n >> 2)) * 8.0f;
                const float d = fabs(v[(n & 1u) + sy * ((n >> 1) & 1u) + sz * (n >> 2)]);
                bound = fmax(bound, d - sdf_len3(q - o) * g->cell);
            }
            return copysign(bound, centre) + outside;
        }
    }
    const float x00 = v[0] + (v[1] - v[0]) * f.x;
    const float x10 = v[sy] + (v[sy + 1u] - v[sy]) * f.x;
    const float x01 = v[sz] + (v[sz + 1u] - v[sz]) * f.x;
    const float x11 = v[sz + sy] + (v[sz + sy + 1u] - v[sz + sy]) * f.x;
    const float y0 = x00 + (x10 - x00) * f.y;
    const float y1 = x01 + (x11 - x01) * f.y;
    return (y0 + (y1 - y0) * f.z) + outside;
}


/* The mesh lookup of every lane (a gather: one lane at a time). */
inline sdf_real sdf_mesh_lanes(__global const float* meshes, uint index, sdf_real x, sdf_real y, sdf_real z) {
#if SDF_LANES == 1
    return sdf_mesh(meshes, index, (float3)(x, y, z));
#else
    float px[SDF_LANES], py[SDF_LANES], pz[SDF_LANES], v[SDF_LANES];
    SDF_REAL_CAT(vstore, SDF_LANES)(x, 0, px);
    SDF_REAL_CAT(vstore, SDF_LANES)(y, 0, py);
    SDF_REAL_CAT(vstore, SDF_LANES)(z, 0, pz);
    for (int i = 0; i < SDF_LANES; ++i) v[i] = sdf_mesh(meshes, index, (float3)(px[i], py[i], pz[i]));
    return SDF_REAL_CAT(vload, SDF_LANES)(0, v);
#endif
}

/* The thinnest part of an edit's primitive (geometry units): twice its smallest radius or half
 * extent (a cone: the larger of its end radii against its half height; a Menger sponge: its
 * smallest hole; a mesh: two cells of its distance grid, the finest detail its field holds). A
 * feature that thin, added or cut away, lies between samples spaced further apart, so a brick whose
 * list holds such an edit cannot be a leaf at a voxel above this (stage check). */
inline float sdf_feature_size(SdfEdit e, __global const float* meshes) {
    const float* prm = e.params;
    float f;
    switch (e.primitive) {
        case SDF_PRIM_SPHERE: f = prm[0]; break;
        case SDF_PRIM_BOX:
        case SDF_PRIM_ROUND_BOX: f = fmin(fmin(prm[0], prm[1]), prm[2]); break;
        case SDF_PRIM_TORUS: f = prm[1]; break;
        case SDF_PRIM_CAPSULE: f = prm[1]; break;
        case SDF_PRIM_CYLINDER: f = fmin(prm[0], prm[1]); break;
        case SDF_PRIM_CONE: f = fmin(prm[0], fmax(prm[1], prm[2])); break;
        case SDF_PRIM_ELLIPSOID: f = fmin(fmin(prm[0], prm[1]), prm[2]); break;
        case SDF_PRIM_MENGER: f = prm[0] / pown(3.0f, (int)prm[1]); break;
        case SDF_PRIM_MESH: f = ((__global const SdfMeshGrid*)meshes)[(uint)prm[3]].cell; break;
        default: f = 0.0f; break;
    }
    return 2.0f * f * e.transform.scale;
}

/* An edit prepared for evaluation (SdfPrepared, sdf_types.h): the reciprocals that evaluation
 * multiplies by, computed once per edit instead of dividing at every point.
 *   value(p) = primitive((R^-1 (p - t)) * (1/s)) * (s/L)         (R skipped when it is the identity)
 *   smooth term of a combine: w^2 * (0.25/k), w = max(k - |a - b|, 0)    (= h^2 k / 4, h = w / k)
 * Every kernel that reads the field evaluates through this, so all of them agree bit for bit; the
 * construction stages that stage edit lists read them prepared once per build (edit_prepare.cl). */
#define SDF_KIND_ROTATED 0x10000u

inline SdfPrepared sdf_prepare(SdfEdit e) {
    SdfPrepared r;
    for (int i = 0; i < 3; ++i) r.t[i] = e.transform.translation[i];
    for (int i = 0; i < 4; ++i) {
        r.q[i] = e.transform.rotation[i];
        r.prm[i] = e.params[i];
    }
    r.inv_scale = 1.0f / e.transform.scale;
    r.out_scale = e.transform.scale * e.inv_lipschitz;
    r.blend = e.blend;
    r.blend_q = e.blend > 0.0f ? 0.25f / e.blend : 0.0f;
    const int identity = e.transform.rotation[0] == 0.0f && e.transform.rotation[1] == 0.0f &&
                         e.transform.rotation[2] == 0.0f && e.transform.rotation[3] == 1.0f;
    r.kind = e.primitive | (e.op << 8) | (identity ? 0u : SDF_KIND_ROTATED);
    return r;
}

/* (x, y, z) (geometry frame) in the frame of edit e, in place: translated, rotated, and scaled
 * unless scaled is 0 (from a caller that knows e's inv_scale is 1: the products are then exact and
 * change no bit). */
inline void sdf_edit_frame_of(const SdfPrepared* e, int scaled, sdf_real* x, sdf_real* y, sdf_real* z) {
    *x = *x - e->t[0];
    *y = *y - e->t[1];
    *z = *z - e->t[2];
    if (e->kind & SDF_KIND_ROTATED) sdf_rotate_inverse(e->q, x, y, z);
    if (scaled) {
        *x = *x * e->inv_scale;
        *y = *y * e->inv_scale;
        *z = *z * e->inv_scale;
    }
}

/* Whether e's frame needs its products with inv_scale, where the caller does not know. CPU lanes test
 * the scale (three vector products per edit); with one lane (GPUs) a test per point costs more than
 * the products: drops' evaluate on an H200 took 8.32 ms with the test and 8.15 ms without. */
#if SDF_LANES > 1
#define SDF_SCALED(e) ((e)->inv_scale != 1.0f)
#else
#define SDF_SCALED(e) 1
#endif

/* Value of one prepared edit at (x, y, z) (geometry frame) whose primitive is prim (= e->kind & 0xff:
 * a caller that has branched on the primitive passes it as a constant, and the switch folds away);
 * meshes is the mesh pool (sdf_types.h). unit (a constant): the caller knows e's inv_scale and
 * out_scale are 1, and their products, exact, are left out (same bits). */
inline sdf_real sdf_edit_value_unit(const SdfPrepared* e, uint prim, int unit, __global const float* meshes, sdf_real x,
                                    sdf_real y, sdf_real z) {
    sdf_real dx = x, dy = y, dz = z;
    sdf_edit_frame_of(e, !unit && SDF_SCALED(e), &dx, &dy, &dz);
    const sdf_real v = prim == SDF_PRIM_MESH ? sdf_mesh_lanes(meshes, (uint)e->prm[3], dx, dy, dz)
                                             : sdf_primitive(prim, e->prm, dx, dy, dz);
    if (unit) return v;
#if SDF_LANES > 1
    if (e->out_scale == 1.0f) return v;
#endif
    return v * e->out_scale;
}
inline sdf_real sdf_edit_value_of(const SdfPrepared* e, uint prim, __global const float* meshes, sdf_real x, sdf_real y,
                                  sdf_real z) {
    return sdf_edit_value_unit(e, prim, 0, meshes, x, y, z);
}

/* Whether e's inv_scale and out_scale are both 1 (the unit argument above). */
inline int sdf_unit_scale(const SdfPrepared* e) { return e->inv_scale == 1.0f && e->out_scale == 1.0f; }

/* Value of one prepared edit at (x, y, z). */
inline sdf_real sdf_edit_value(const SdfPrepared* e, __global const float* meshes, sdf_real x, sdf_real y, sdf_real z) {
    return sdf_edit_value_of(e, e->kind & 0xffu, meshes, x, y, z);
}

/* Compact-support quadratic smooth minimum / maximum: exactly min / max when |a - b| >= k
 * (then w = 0 and the smooth term is 0 * 0 * q = 0). The term w^2 q is taken from the minimum or
 * added to the maximum in one rounding (sdf_smooth_below, sdf_smooth_above), which gives -0 and +0
 * as a subtraction or addition of +0 does. */
inline sdf_real sdf_smooth_below(sdf_real lo, sdf_real w, float q) { return fma(w * w, SDF_SPLAT(-q), lo); }
inline sdf_real sdf_smooth_above(sdf_real hi, sdf_real w, float q) { return fma(w * w, SDF_SPLAT(q), hi); }
inline sdf_real sdf_smooth_min(sdf_real a, sdf_real b, float k, float q) {
    const sdf_real w = fmax(k - fabs(a - b), 0.0f);
    return sdf_smooth_below(fmin(a, b), w, q);
}
inline sdf_real sdf_smooth_max(sdf_real a, sdf_real b, float k, float q) {
    const sdf_real w = fmax(k - fabs(a - b), 0.0f);
    return sdf_smooth_above(fmax(a, b), w, q);
}

/* Combine the field so far with one prepared edit's value v, the edit's operation being op (= its
 * kind >> 8 & 0xff; a constant folds the switch away as in sdf_edit_value_of). */
inline sdf_real sdf_combine_of(const SdfPrepared* e, uint op, sdf_real field, sdf_real v) {
    const int smooth = e->blend > 0.0f;
    switch (op) {
        case SDF_OP_ADD: return smooth ? sdf_smooth_min(field, v, e->blend, e->blend_q) : fmin(field, v);
        case SDF_OP_SUBTRACT: return smooth ? sdf_smooth_max(field, -v, e->blend, e->blend_q) : fmax(field, -v);
        case SDF_OP_INTERSECT: return smooth ? sdf_smooth_max(field, v, e->blend, e->blend_q) : fmax(field, v);
        default: return field;
    }
}

/* Combine the field so far with one prepared edit's value v. */
inline sdf_real sdf_combine(const SdfPrepared* e, sdf_real field, sdf_real v) {
    return sdf_combine_of(e, (e->kind >> 8) & 0xffu, field, v);
}

#if SDF_LANES == 1
/* Value of one prepared edit at p. */
inline float sdf_prepared_value(const SdfPrepared* e, __global const float* meshes, float3 p) {
    return sdf_edit_value(e, meshes, p.x, p.y, p.z);
}

/* Apply one prepared edit to the field at p. */
inline float sdf_apply_edit(const SdfPrepared* e, __global const float* meshes, float field, float3 p) {
    return sdf_combine(e, field, sdf_prepared_value(e, meshes, p));
}
#endif

#endif /* SDFBRICK_SDF_EDIT_H */
