/* sdf_edit.h: evaluation of edits and edit lists, shared by every kernel that reads the field.
 *
 * Determinism (docs/design.md#determinism): only + - * / sqrt fabs fmin fmax floor, with FP_CONTRACT OFF
 * (the program builder puts the pragma first) and correctly rounded divide/sqrt where the device
 * supports it. No built-in dot/length/normalize/distance/mix: their rounding and fusing are not
 * specified, so the sums are written out here in a fixed order.
 * The formulas are documented in docs/scene-format.md; host/reference/ evaluates the same
 * definitions independently in double precision.
 */
#ifndef SDFBRICK_SDF_EDIT_H
#define SDFBRICK_SDF_EDIT_H

#include "sdf_types.h"

inline float sdf_dot2(float ax, float ay, float bx, float by) { return ax * bx + ay * by; }
inline float sdf_dot3(float3 a, float3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline float sdf_len2(float x, float y) { return sqrt(x * x + y * y); }
inline float sdf_len3(float3 a) { return sqrt(sdf_dot3(a, a)); }
inline float sdf_max3(float3 a) { return fmax(fmax(a.x, a.y), a.z); }
inline float sdf_min3(float3 a) { return fmin(fmin(a.x, a.y), a.z); }

/* Rotate v by the conjugate of the unit quaternion q = (x, y, z, w):
 * t = 2 cross(u, v); v' = v + w t + cross(u, t), u = -q.xyz. */
inline float3 sdf_rotate_inverse(const float q[4], float3 v) {
    const float3 u = (float3)(-q[0], -q[1], -q[2]);
    const float w = q[3];
    const float3 t = (float3)(2.0f * (u.y * v.z - u.z * v.y),
                              2.0f * (u.z * v.x - u.x * v.z),
                              2.0f * (u.x * v.y - u.y * v.x));
    const float3 c = (float3)(u.y * t.z - u.z * t.y, u.z * t.x - u.x * t.z, u.x * t.y - u.y * t.x);
    return v + w * t + c;
}

inline float sdf_box(float3 p, float3 b) {
    const float3 q = fabs(p) - b;
    return sdf_len3(fmax(q, (float3)(0.0f))) + fmin(sdf_max3(q), 0.0f);
}

inline float sdf_cone(float3 p, float h, float r1, float r2) {
    const float qx = sdf_len2(p.x, p.z), qy = p.y;
    const float k1x = r2, k1y = h;
    const float k2x = r2 - r1, k2y = 2.0f * h;
    const float cax = qx - fmin(qx, qy < 0.0f ? r1 : r2);
    const float cay = fabs(qy) - h;
    const float t = clamp(sdf_dot2(k1x - qx, k1y - qy, k2x, k2y) / sdf_dot2(k2x, k2y, k2x, k2y), 0.0f, 1.0f);
    const float cbx = qx - k1x + k2x * t;
    const float cby = qy - k1y + k2y * t;
    const float s = (cbx < 0.0f && cay < 0.0f) ? -1.0f : 1.0f;
    return s * sqrt(fmin(sdf_dot2(cax, cay, cax, cay), sdf_dot2(cbx, cby, cbx, cby)));
}

inline float sdf_menger(float3 p, float half_size, int iterations) {
    const float3 u = p / half_size;
    float d = sdf_box(u, (float3)(1.0f));
    float sc = 1.0f;
    for (int i = 0; i < iterations; ++i) {
        const float3 x = u * sc;
        const float3 a = x - 2.0f * floor(x * 0.5f) - 1.0f; /* mod(x, 2) - 1 */
        sc *= 3.0f;
        const float3 r = fabs(1.0f - 3.0f * fabs(a));
        const float da = fmax(r.x, r.y), db = fmax(r.y, r.z), dc = fmax(r.z, r.x);
        d = fmax(d, (fmin(fmin(da, db), dc) - 1.0f) / sc);
    }
    return d * half_size;
}

/* Distance of a primitive in its local frame (before scale and Lipschitz division). */
inline float sdf_primitive(uint kind, const float prm[4], float3 p) {
    switch (kind) {
        case SDF_PRIM_SPHERE: return sdf_len3(p) - prm[0];
        case SDF_PRIM_BOX: return sdf_box(p, (float3)(prm[0], prm[1], prm[2]));
        case SDF_PRIM_ROUND_BOX:
            return sdf_box(p, (float3)(prm[0] - prm[3], prm[1] - prm[3], prm[2] - prm[3])) - prm[3];
        case SDF_PRIM_TORUS: return sdf_len2(sdf_len2(p.x, p.z) - prm[0], p.y) - prm[1];
        case SDF_PRIM_CAPSULE: {
            const float3 q = (float3)(p.x, p.y - clamp(p.y, -prm[0], prm[0]), p.z);
            return sdf_len3(q) - prm[1];
        }
        case SDF_PRIM_CYLINDER: {
            const float dx = sdf_len2(p.x, p.z) - prm[1], dy = fabs(p.y) - prm[0];
            return fmin(fmax(dx, dy), 0.0f) + sdf_len2(fmax(dx, 0.0f), fmax(dy, 0.0f));
        }
        case SDF_PRIM_CONE: return sdf_cone(p, prm[0], prm[1], prm[2]);
        case SDF_PRIM_ELLIPSOID: {
            const float3 r = (float3)(prm[0], prm[1], prm[2]);
            return (sdf_len3(p / r) - 1.0f) * sdf_min3(r);
        }
        case SDF_PRIM_MENGER: return sdf_menger(p, prm[0], (int)prm[1]);
        default: return SDF_FAR;
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
    const float3 f = c - base;
    const uint i = (uint)base.x, j = (uint)base.y, k = (uint)base.z;
    __global const float* v = meshes + g->offset + i + nx * (j + ny * k);
    const uint sy = nx, sz = nx * ny;
    const float x00 = v[0] + (v[1] - v[0]) * f.x;
    const float x10 = v[sy] + (v[sy + 1u] - v[sy]) * f.x;
    const float x01 = v[sz] + (v[sz + 1u] - v[sz]) * f.x;
    const float x11 = v[sz + sy] + (v[sz + sy + 1u] - v[sz + sy]) * f.x;
    const float y0 = x00 + (x10 - x00) * f.y;
    const float y1 = x01 + (x11 - x01) * f.y;
    return (y0 + (y1 - y0) * f.z) + outside;
}

/* An edit prepared for evaluation (kernel side only, 64 bytes like SdfEdit): the reciprocals that
 * evaluation multiplies by, computed once per edit instead of dividing at every point.
 *   value(p) = primitive((R^-1 (p - t)) * (1/s)) * (s/L)         (R skipped when it is the identity)
 *   smooth term of a combine: w^2 * (0.25/k), w = max(k - |a - b|, 0)    (= h^2 k / 4, h = w / k)
 * Every kernel that reads the field evaluates through this, so all of them agree bit for bit. */
#define SDF_KIND_ROTATED 0x10000u
typedef struct SdfPrepared {
    float t[3];
    float inv_scale;   /* 1 / s */
    float q[4];        /* rotation (x, y, z, w) */
    float prm[4];
    float out_scale;   /* s / L */
    float blend;       /* k; 0 = hard */
    float blend_q;     /* 0.25 / k; 0 when hard */
    uint kind;         /* primitive | op << 8 | SDF_KIND_ROTATED when the rotation is not the identity */
} SdfPrepared;

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

/* Value of one prepared edit at p (geometry frame); meshes is the mesh pool (sdf_types.h). */
inline float sdf_prepared_value(const SdfPrepared* e, __global const float* meshes, float3 p) {
    float3 d = p - (float3)(e->t[0], e->t[1], e->t[2]);
    if (e->kind & SDF_KIND_ROTATED) d = sdf_rotate_inverse(e->q, d);
    const uint prim = e->kind & 0xffu;
    const float3 x = d * e->inv_scale;
    const float v = prim == SDF_PRIM_MESH ? sdf_mesh(meshes, (uint)e->prm[3], x) : sdf_primitive(prim, e->prm, x);
    return v * e->out_scale;
}

/* Compact-support quadratic smooth minimum / maximum: exactly min / max when |a - b| >= k
 * (then w = 0 and the smooth term is 0 * 0 * q = 0). */
inline float sdf_smooth_min(float a, float b, float k, float q) {
    const float w = fmax(k - fabs(a - b), 0.0f);
    return fmin(a, b) - w * w * q;
}
inline float sdf_smooth_max(float a, float b, float k, float q) {
    const float w = fmax(k - fabs(a - b), 0.0f);
    return fmax(a, b) + w * w * q;
}

/* Combine the field so far with one prepared edit's value v. */
inline float sdf_combine(const SdfPrepared* e, float field, float v) {
    const int smooth = e->blend > 0.0f;
    switch ((e->kind >> 8) & 0xffu) {
        case SDF_OP_ADD: return smooth ? sdf_smooth_min(field, v, e->blend, e->blend_q) : fmin(field, v);
        case SDF_OP_SUBTRACT: return smooth ? sdf_smooth_max(field, -v, e->blend, e->blend_q) : fmax(field, -v);
        case SDF_OP_INTERSECT: return smooth ? sdf_smooth_max(field, v, e->blend, e->blend_q) : fmax(field, v);
        default: return field;
    }
}

/* Apply one prepared edit to the field at p. */
inline float sdf_apply_edit(const SdfPrepared* e, __global const float* meshes, float field, float3 p) {
    return sdf_combine(e, field, sdf_prepared_value(e, meshes, p));
}

#endif /* SDFBRICK_SDF_EDIT_H */
