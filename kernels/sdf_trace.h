/* sdf_trace.h: rays through the two-level BVH of bricks (docs/tracing.md), shared by the primary
 * tracer and the shading kernel's secondary rays.
 *
 * Compile-time: SAMPLES (8 or 10), APRON (1 or 2), FORMAT (0 int8, 1 int16, 2 float), METHOD (0 sphere
 * tracing over trilinear samples, 1 analytic: the cubic of the trilinear cell, roots isolated as in
 * Marmitt et al. 2004, 2 hybrid: sphere steps while far from the surface, then analytic cells),
 * NORMALS (0 central differences, 1 tetrahedron, 2 continuous: per-sample gradients interpolated
 * trilinearly).
 *
 * Frames. A world ray (o, d), |d| = 1, maps into an instance's geometry frame as (M (o - T), M d); the
 * parameter t is shared, and a geometry-frame length L corresponds to L * len_scale in t, where
 * len_scale = 1 / |M d|. In a brick, positions are in sample space: s = (p - brick_min) / voxel +
 * APRON - 0.5, so sample (i, j, k) sits at s = (i, j, k) and the trilinear cell c spans [c, c + 1]. The
 * interior of the brick is s in [APRON - 0.5, SAMPLES - APRON - 0.5]; neighbouring bricks compute the
 * samples they share from the same lattice points, so the field is continuous from brick to brick.
 *
 * Hits. The surface is the first t where the trilinear field is <= 0. A ray that enters a brick
 * already inside the solid hits at the entry (a camera inside the solid sees the inner side of the
 * band around it). Bricks are visited near first and a brick is only
 * searched up to the nearest hit found so far; of equally near hits the one on the lowest (instance,
 * brick) wins, so the result does not depend on the order. */
#ifndef SDFBRICK_SDF_TRACE_H
#define SDFBRICK_SDF_TRACE_H

#include "sdf_types.h"

#define S SAMPLES
#define S3 (SAMPLES * SAMPLES * SAMPLES)
#define BVH_STACK 96              /* a wide node pushes at most 3 slots; a path of a radix tree over 63-bit
                                     keys, at most 63 binary nodes deep, visits at most 32 wide nodes */
#define SPHERE_MAX_STEPS 64       /* sphere tracing: steps per brick */
#define ROOT_ITERATIONS 8         /* analytic: regula falsi (Illinois) iterations per root */
#define HYBRID_NEAR 1.0f          /* hybrid: sphere steps while the field is above this many voxels */

#include "sdf_format.h"

inline float tr_dot(float3 a, float3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline float3 tr_normalize(float3 a) {
    const float l = sqrt(tr_dot(a, a));
    return l > 0.0f ? a / l : (float3)(0.0f);
}
inline float tr_lerp(float a, float b, float t) { return a + (b - a) * t; }
inline float tr_min3(float3 a) { return fmin(fmin(a.x, a.y), a.z); }

/* 1 / d with zero components replaced by a tiny value of the same sign (no 0 * inf = NaN in slabs). */
inline float3 tr_inverse(float3 d) {
    const float tiny = 1e-20f;
    return (float3)(1.0f / (fabs(d.x) < tiny ? copysign(tiny, d.x) : d.x),
                    1.0f / (fabs(d.y) < tiny ? copysign(tiny, d.y) : d.y),
                    1.0f / (fabs(d.z) < tiny ? copysign(tiny, d.z) : d.z));
}

/* ---- the field inside one brick ---- */

inline float tr_sample(__global const sample_t* brick, int i, int j, int k) {
    return (float)brick[i + S * (j + S * k)];
}

/* Trilinear value (stored units) at sample-space point s, clamped to the brick's samples. */
inline float tr_field(__global const sample_t* brick, float3 s) {
    s = clamp(s, (float3)(0.0f), (float3)((float)(S - 1)));
    const int3 c = min(convert_int3(floor(s)), (int3)(S - 2));
    const float3 f = s - convert_float3(c);
    const float c00 = tr_lerp(tr_sample(brick, c.x, c.y, c.z), tr_sample(brick, c.x + 1, c.y, c.z), f.x);
    const float c10 = tr_lerp(tr_sample(brick, c.x, c.y + 1, c.z), tr_sample(brick, c.x + 1, c.y + 1, c.z), f.x);
    const float c01 = tr_lerp(tr_sample(brick, c.x, c.y, c.z + 1), tr_sample(brick, c.x + 1, c.y, c.z + 1), f.x);
    const float c11 =
        tr_lerp(tr_sample(brick, c.x, c.y + 1, c.z + 1), tr_sample(brick, c.x + 1, c.y + 1, c.z + 1), f.x);
    return tr_lerp(tr_lerp(c00, c10, f.y), tr_lerp(c01, c11, f.y), f.z);
}

#if NORMALS == 2
/* Gradient at sample (i, j, k) by central differences of the samples (one-sided at the brick's edge). */
inline float3 tr_sample_gradient(__global const sample_t* brick, int i, int j, int k) {
    const int i0 = max(i - 1, 0), i1 = min(i + 1, S - 1);
    const int j0 = max(j - 1, 0), j1 = min(j + 1, S - 1);
    const int k0 = max(k - 1, 0), k1 = min(k + 1, S - 1);
    return (float3)((tr_sample(brick, i1, j, k) - tr_sample(brick, i0, j, k)) / (float)(i1 - i0),
                    (tr_sample(brick, i, j1, k) - tr_sample(brick, i, j0, k)) / (float)(j1 - j0),
                    (tr_sample(brick, i, j, k1) - tr_sample(brick, i, j, k0)) / (float)(k1 - k0));
}
#endif

/* Field gradient (sample space, any scale) at s, by the method NORMALS. */
inline float3 tr_gradient(__global const sample_t* brick, float3 s) {
#if NORMALS == 0
    const float h = 0.5f;
    return (float3)(tr_field(brick, s + (float3)(h, 0.0f, 0.0f)) - tr_field(brick, s - (float3)(h, 0.0f, 0.0f)),
                    tr_field(brick, s + (float3)(0.0f, h, 0.0f)) - tr_field(brick, s - (float3)(0.0f, h, 0.0f)),
                    tr_field(brick, s + (float3)(0.0f, 0.0f, h)) - tr_field(brick, s - (float3)(0.0f, 0.0f, h)));
#elif NORMALS == 1
    const float h = 0.5f;
    const float3 k0 = (float3)(1.0f, -1.0f, -1.0f), k1 = (float3)(-1.0f, -1.0f, 1.0f);
    const float3 k2 = (float3)(-1.0f, 1.0f, -1.0f), k3 = (float3)(1.0f, 1.0f, 1.0f);
    return k0 * tr_field(brick, s + h * k0) + k1 * tr_field(brick, s + h * k1) + k2 * tr_field(brick, s + h * k2) +
           k3 * tr_field(brick, s + h * k3);
#else
    s = clamp(s, (float3)(0.0f), (float3)((float)(S - 1)));
    const int3 c = min(convert_int3(floor(s)), (int3)(S - 2));
    const float3 f = s - convert_float3(c);
    float3 g[8];
    for (int n = 0; n < 8; ++n) g[n] = tr_sample_gradient(brick, c.x + (n & 1), c.y + ((n >> 1) & 1), c.z + (n >> 2));
    const float3 gx0 = g[0] + (g[1] - g[0]) * f.x, gx1 = g[2] + (g[3] - g[2]) * f.x;
    const float3 gx2 = g[4] + (g[5] - g[4]) * f.x, gx3 = g[6] + (g[7] - g[6]) * f.x;
    const float3 gy0 = gx0 + (gx1 - gx0) * f.y, gy1 = gx2 + (gx3 - gx2) * f.y;
    return gy0 + (gy1 - gy0) * f.z;
#endif
}

#if METHOD >= 1
/* The 8 corner samples of cell c: corner n = dx + 2 dy + 4 dz is component n. */
inline float8 tr_corners(__global const sample_t* brick, int3 c) {
    return (float8)(tr_sample(brick, c.x, c.y, c.z), tr_sample(brick, c.x + 1, c.y, c.z),
                    tr_sample(brick, c.x, c.y + 1, c.z), tr_sample(brick, c.x + 1, c.y + 1, c.z),
                    tr_sample(brick, c.x, c.y, c.z + 1), tr_sample(brick, c.x + 1, c.y, c.z + 1),
                    tr_sample(brick, c.x, c.y + 1, c.z + 1), tr_sample(brick, c.x + 1, c.y + 1, c.z + 1));
}

/* Adds corner (dx, dy, dz)'s value v to the cubic k: the product of the three linear weights, where
 * along an axis corner 0 weighs (1 - a) - u b and corner 1 a + u b. */
inline float4 tr_cubic_term(float4 k, float v, int dx, int dy, int dz, float3 a, float3 b) {
    const float ax = dx ? a.x : 1.0f - a.x, bx = dx ? b.x : -b.x;
    const float ay = dy ? a.y : 1.0f - a.y, by = dy ? b.y : -b.y;
    const float az = dz ? a.z : 1.0f - a.z, bz = dz ? b.z : -b.z;
    k.s0 += v * (ax * ay * az);
    k.s1 += v * (bx * ay * az + ax * by * az + ax * ay * bz);
    k.s2 += v * (bx * by * az + bx * ay * bz + ax * by * bz);
    k.s3 += v * (bx * by * bz);
    return k;
}

/* The trilinear field of the cell with corners v along s(u) = a + u * b (u in cell units of the ray)
 * as the cubic k[3] u^3 + k[2] u^2 + k[1] u + k[0], summed over the corners in order. */
inline float4 tr_cell_cubic(float8 v, float3 a, float3 b) {
    float4 k = (float4)(0.0f);
    k = tr_cubic_term(k, v.s0, 0, 0, 0, a, b);
    k = tr_cubic_term(k, v.s1, 1, 0, 0, a, b);
    k = tr_cubic_term(k, v.s2, 0, 1, 0, a, b);
    k = tr_cubic_term(k, v.s3, 1, 1, 0, a, b);
    k = tr_cubic_term(k, v.s4, 0, 0, 1, a, b);
    k = tr_cubic_term(k, v.s5, 1, 0, 1, a, b);
    k = tr_cubic_term(k, v.s6, 0, 1, 1, a, b);
    k = tr_cubic_term(k, v.s7, 1, 1, 1, a, b);
    return k;
}

inline float tr_cubic(float4 k, float u) { return ((k.s3 * u + k.s2) * u + k.s1) * u + k.s0; }

/* First root of the cubic in [u0, u1] where f(u0) > 0 >= f(u1): Illinois regula falsi, fixed count. */
inline float tr_root(float4 k, float u0, float f0, float u1, float f1) {
    int side = 0;
    for (int it = 0; it < ROOT_ITERATIONS; ++it) {
        const float u = u0 + (u1 - u0) * (f0 / (f0 - f1));
        const float f = tr_cubic(k, u);
        if (f > 0.0f) {
            u0 = u;
            f0 = f;
            if (side == -1) f1 *= 0.5f;
            side = -1;
        } else {
            u1 = u;
            f1 = f;
            if (side == 1) f0 *= 0.5f;
            side = 1;
        }
    }
    return u0 + (u1 - u0) * (f0 / (f0 - f1));
}

/* First u in [0, len] where the cubic is <= 0, or -1: the interval is cut at the roots of the
 * derivative, and the first piece that ends at or below zero holds the root. With any_hit, the end
 * of that piece, unrefined (an any-hit ray needs only whether there is a root: the root iterations
 * were 30% of the shading kernel with hybrid secondary rays on an H200, docs/performance.md). */
inline float tr_cubic_first_root(float4 k, float len, int any_hit) {
    float cuts[4];
    int n = 0;
    cuts[n++] = 0.0f;
    const float qa = 3.0f * k.s3, qb = 2.0f * k.s2, qc = k.s1;
    if (qa != 0.0f) {
        const float disc = qb * qb - 4.0f * qa * qc;
        if (disc >= 0.0f) {
            const float r = sqrt(disc);
            float e0 = (-qb - r) / (2.0f * qa), e1 = (-qb + r) / (2.0f * qa);
            if (e0 > e1) {
                const float t = e0;
                e0 = e1;
                e1 = t;
            }
            if (e0 > 0.0f && e0 < len) cuts[n++] = e0;
            if (e1 > 0.0f && e1 < len && e1 != e0) cuts[n++] = e1;
        }
    } else if (qb != 0.0f) {
        const float e = -qc / qb;
        if (e > 0.0f && e < len) cuts[n++] = e;
    }
    cuts[n++] = len;
    float u0 = cuts[0], f0 = tr_cubic(k, u0);
    if (f0 <= 0.0f) return u0;
    for (int i = 1; i < n; ++i) {
        const float u1 = cuts[i], f1 = tr_cubic(k, u1);
        if (f1 <= 0.0f) return any_hit ? u1 : tr_root(k, u0, f0, u1, f1);
        u0 = u1;
        f0 = f1;
    }
    return -1.0f;
}

/* The first u >= u_start (t - t0, within [0, span]) where the trilinear field is <= 0, or -1:
 * walks the trilinear cells in sample space from the one holding s0 + u_start * ds (a 3D DDA) and
 * solves each cell's cubic. At most 3 * S cells (a ray crosses at most 3 (S - 1) - 2 of them); running
 * out of cells before leaving the brick sets *capped. */
inline float tr_cells(__global const sample_t* brick, float3 s0, float3 ds, float u, float span, uint* steps,
                      uint* capped, int any_hit) {
    const float3 inv_ds = tr_inverse(ds);
    int3 c = clamp(convert_int3(floor(s0 + u * ds)), (int3)(0), (int3)(S - 2));
    const int3 step = (int3)(ds.x >= 0.0f ? 1 : -1, ds.y >= 0.0f ? 1 : -1, ds.z >= 0.0f ? 1 : -1);
    for (int i = 0; i < 3 * S; ++i) {
        const float3 next = convert_float3(c + max(step, (int3)(0)));
        const float3 exit_u = (next - s0) * inv_ds;
        const float u_exit = fmin(tr_min3(exit_u), span);
        ++*steps;
        /* corners all above zero: no root in this cell */
        const float8 v = tr_corners(brick, c);
        const float4 v4 = fmin(v.lo, v.hi);
        if (fmin(fmin(v4.x, v4.y), fmin(v4.z, v4.w)) <= 0.0f && u_exit >= u) {
            const float3 a = s0 + u * ds - convert_float3(c);
            const float4 k = tr_cell_cubic(v, a, ds);
            const float r = tr_cubic_first_root(k, u_exit - u, any_hit);
            if (r >= 0.0f) return u + r;
        }
        if (u_exit >= span) return -1.0f;
        u = u_exit;
        if (exit_u.x <= exit_u.y && exit_u.x <= exit_u.z) c.x += step.x;
        else if (exit_u.y <= exit_u.z) c.y += step.y;
        else c.z += step.z;
        if (any(c < (int3)(0)) || any(c > (int3)(S - 2))) return -1.0f;
    }
    *capped = 1u;
    return -1.0f;
}
#endif

/* Searches one brick for the surface on the ray segment [t0, t1]: returns the hit t or -1 (with
 * any_hit, for the analytic cells, some t >= 0 where the field is <= 0: not refined to the first).
 * o, d: the ray in the geometry frame; lo: the brick's minimum corner. A search that stops at a loop
 * bound (not at a hit or the segment's end) sets *capped. */
inline float tr_brick(__global const sample_t* brick, float3 lo, float3 o, float3 d, float t0, float t1,
                      float inv_voxel, float len_scale, float voxel_to_stored, uint* steps, uint* capped,
                      int any_hit) {
    const float3 s0 = (o + t0 * d - lo) * inv_voxel + (float)APRON - 0.5f;
    const float3 ds = d * inv_voxel;
#if METHOD == 0
    /* Sphere tracing: the field (stored units, to voxels by 1 / voxel_to_stored) bounds the step. */
    const float to_t = len_scale / (inv_voxel * voxel_to_stored); /* stored units -> t */
    const float eps = SDF_SPHERE_EPS * voxel_to_stored;
    float t = t0, t_prev = t0, f_prev = 0.0f;
    for (int i = 0; i < SPHERE_MAX_STEPS; ++i) {
        const float f = tr_field(brick, s0 + (t - t0) * ds);
        ++*steps;
        if (f <= eps) {
            if (f < 0.0f && i > 0) return t_prev + (t - t_prev) * (f_prev / (f_prev - f)); /* overshot: secant */
            return t;
        }
        t_prev = t;
        f_prev = f;
        t += f * to_t;
        if (t > t1) return -1.0f;
    }
    *capped = 1u;
    return -1.0f;
#elif METHOD == 1
    const float u = tr_cells(brick, s0, ds, 0.0f, t1 - t0, steps, capped, any_hit);
    return u >= 0.0f ? t0 + u : -1.0f;
#else
    /* Hybrid: sphere steps while the field is above HYBRID_NEAR voxels, then the cells from the last
     * point that was still that far (a step may have crossed a thin feature's near side). Running out
     * of sphere steps hands over to the cells too, so only the cell walk can stop at a bound. */
    const float to_t = len_scale / (inv_voxel * voxel_to_stored); /* stored units -> t */
    const float near_field = HYBRID_NEAR * voxel_to_stored;
    const float span = t1 - t0;
    float u = 0.0f, u_far = 0.0f;
    for (int i = 0; i < SPHERE_MAX_STEPS; ++i) {
        const float f = tr_field(brick, s0 + u * ds);
        ++*steps;
        if (f <= near_field) break;
        u_far = u;
        u += f * to_t;
        if (u > span) return -1.0f;
    }
    const float r = tr_cells(brick, s0, ds, u_far, span, steps, capped, any_hit);
    return r >= 0.0f ? t0 + r : -1.0f;
#endif
}

/* ---- traversal ---- */

/* The scene's bricks and trees, as kernel arguments pass them. */
typedef struct TraceScene {
    __global const SdfBvhWideNode* tlas;
    __global const SdfInstance* instances;
    __global const SdfBrickGeometry* geometries;
    __global const SdfBvhWideNode* nodes;
    __global const sample_t* pool;
    __global const uint* shifts; /* per brick: its voxel is the geometry's finest voxel * 2^shift */
} TraceScene;

typedef struct TraceHit {
    float t;         /* < 0: no hit */
    uint brick;      /* global brick index */
    uint instance;
    float3 lo;       /* the brick's minimum corner (geometry frame) */
    float inv_voxel; /* 1 / the brick's voxel */
    float3 o, d;     /* the ray in that instance's geometry frame */
    uint visits;     /* BVH nodes visited (both levels) */
    uint steps;      /* in-brick steps or cells */
    uint capped;     /* 1 when a brick's search stopped at a loop bound */
} TraceHit;

/* Stack entries: a wide node's index, or TR_LEAF | node << 2 | slot for a leaf slot, searched when it
 * is popped (so nothing of a visited node stays in registers while a brick or an instance is searched). */
#define TR_LEAF 0x80000000u
#define TR_NONE 0xFFFFFFFFu

/* Puts the entries a < b in order of their keys (ties keep the slot order). */
inline void tr_order(float* key, uint* entry, int a, int b) {
    if (!(key[b] < key[a])) return;
    const float k = key[a];
    const uint e = entry[a];
    key[a] = key[b];
    entry[a] = entry[b];
    key[b] = k;
    entry[b] = e;
}

/* Slab test of slot k of a wide node against the ray segment [t_min, t_far]: the entry; *exit the exit. */
inline float tr_slot_slab(__global const SdfBvhWideNode* node, int k, float3 o, float3 inv_d, float t_min,
                          float t_far, float* exit) {
    const float3 lo = (float3)(node->lo_x[k], node->lo_y[k], node->lo_z[k]);
    const float3 hi = (float3)(node->hi_x[k], node->hi_y[k], node->hi_z[k]);
    const float3 a = (lo - o) * inv_d, b = (hi - o) * inv_d;
    *exit = fmin(fmin(fmin(fmax(a.x, b.x), fmax(a.y, b.y)), fmax(a.z, b.z)), t_far);
    return fmax(fmax(fmax(fmin(a.x, b.x), fmin(a.y, b.y)), fmin(a.z, b.z)), t_min);
}

/* Visits wide node i: the slots the segment [t_min, t_far] enters, nearest entry first; returns the
 * nearest (TR_NONE if none) and pushes the others, the farthest first. With any_hit the slots stay in
 * slot order: whether a hit exists does not depend on the order, and on an H200 the sorting cost the
 * shading kernel 4% with sphere rays and 8% with hybrid ones (docs/measurements/roof/d22). Internal
 * slots are not tested again when popped (their own slots are; a test there cost the shading kernel
 * 17% on an H200, docs/performance.md); leaf slots are, against the nearest hit by then. */
inline uint tr_visit(__global const SdfBvhWideNode* nodes, uint i, float3 o, float3 inv_d, float t_min, float t_far,
                     uint* stack, int* sp, int any_hit) {
    __global const float4* v = (__global const float4*)(nodes + i);
    /* four slab tests in one, with the operations of tr_slot_slab in the same order */
    const float4 ax = (v[0] - o.x) * inv_d.x, bx = (v[3] - o.x) * inv_d.x;
    const float4 ay = (v[1] - o.y) * inv_d.y, by = (v[4] - o.y) * inv_d.y;
    const float4 az = (v[2] - o.z) * inv_d.z, bz = (v[5] - o.z) * inv_d.z;
    const float4 n = fmax(fmax(fmax(fmin(ax, bx), fmin(ay, by)), fmin(az, bz)), t_min);
    const float4 x = fmin(fmin(fmin(fmax(ax, bx), fmax(ay, by)), fmax(az, bz)), t_far);
    const int4 c = as_int4(v[6]);
    const int4 in = n <= x && c != (int4)(SDF_WIDE_EMPTY);
    const uint4 leaf = (uint4)(TR_LEAF | (i << 2)) + (uint4)(0u, 1u, 2u, 3u);
    const uint4 e = select(select(leaf, as_uint4(c), c >= (int4)(0)), (uint4)(TR_NONE), as_uint4(!in));
    float key[4] = {in.x ? n.x : INFINITY, in.y ? n.y : INFINITY, in.z ? n.z : INFINITY, in.w ? n.w : INFINITY};
    uint entry[4] = {e.x, e.y, e.z, e.w};
    if (any_hit) { /* the first slot entered goes next, the others are pushed */
        uint first = TR_NONE;
        for (int k = 3; k >= 0; --k)
            if (entry[k] != TR_NONE) {
                if (first != TR_NONE) stack[(*sp)++] = first;
                first = entry[k];
            }
        return first;
    }
    tr_order(key, entry, 0, 1);
    tr_order(key, entry, 2, 3);
    tr_order(key, entry, 0, 2);
    tr_order(key, entry, 1, 3);
    tr_order(key, entry, 1, 2);
    for (int k = 3; k >= 1; --k)
        if (entry[k] != TR_NONE) stack[(*sp)++] = entry[k];
    return entry[0];
}

/* The next entry: the nearest slot of the node just visited, else the last one pushed; TR_NONE when
 * the tree is done. */
inline uint tr_next(uint nearest, const uint* stack, int* sp) {
    if (nearest != TR_NONE) return nearest;
    if (*sp == 0) return TR_NONE;
    return stack[--*sp];
}

/* The far end of the search: t_max, or the nearest hit so far. */
inline float tr_bound(const TraceHit* hit, float t_max) { return hit->t < 0.0f ? t_max : fmin(hit->t, t_max); }

/* Whether a hit at t on brick b of instance replaces *hit: nearer, or as near on a lower (instance,
 * brick). So the nearest hit does not depend on the order in which the bricks are searched. */
inline int tr_nearer(const TraceHit* hit, float t, uint instance, uint b) {
    if (hit->t < 0.0f || t < hit->t) return 1;
    return t == hit->t && (instance < hit->instance || (instance == hit->instance && b < hit->brick));
}

/* Nearer hit than hit->t (any_hit: any hit) in [t_min, t_max] among one geometry's bricks. */
inline void tr_blas(const TraceScene* sc, SdfBrickGeometry g, uint instance, float3 o, float3 d, float t_min,
                    float t_max, float len_scale, int any_hit, TraceHit* hit) {
    const float3 inv_d = tr_inverse(d);
    const float voxel_to_stored = g.voxel / g.dequant;
    uint stack[BVH_STACK];
    int sp = 0;
    for (uint e = g.root; e != TR_NONE;) {
        if (!(e & TR_LEAF)) {
            ++hit->visits;
            e = tr_next(tr_visit(sc->nodes, e, o, inv_d, t_min, tr_bound(hit, t_max), stack, &sp, any_hit), stack, &sp);
            continue;
        }
        __global const SdfBvhWideNode* node = sc->nodes + ((e & ~TR_LEAF) >> 2);
        const int k = (int)(e & 3u);
        float limit;
        const float enter = tr_slot_slab(node, k, o, inv_d, t_min, tr_bound(hit, t_max), &limit);
        if (enter <= limit) {
            const uint b = g.brick_offset + (uint)(~node->child[k]);
            const float inv_voxel = ldexp(g.inv_voxel, -(int)sc->shifts[b]);
            const float3 lo = (float3)(node->lo_x[k], node->lo_y[k], node->lo_z[k]);
            const float t = tr_brick(sc->pool + (size_t)b * S3, lo, o, d, enter, limit, inv_voxel, len_scale,
                                     voxel_to_stored, &hit->steps, &hit->capped, any_hit);
            if (t >= 0.0f && tr_nearer(hit, t, instance, b)) {
                hit->t = t;
                hit->brick = b;
                hit->instance = instance;
                hit->lo = lo;
                hit->inv_voxel = inv_voxel;
                hit->o = o;
                hit->d = d;
                if (any_hit) return;
            }
        }
        e = tr_next(TR_NONE, stack, &sp);
    }
}

/* Nearest hit (with any_hit: any hit) of the world ray o + t d, t in [t_min, t_max]: the top level
 * over instances, then each instance's bricks in its geometry frame. */
inline TraceHit tr_trace(const TraceScene* sc, float3 o, float3 d, float t_min, float t_max, int any_hit) {
    TraceHit hit;
    hit.t = -1.0f;
    hit.brick = SDF_NO_BRICK;
    hit.instance = 0u;
    hit.visits = 0u;
    hit.steps = 0u;
    hit.capped = 0u;
    hit.lo = hit.o = hit.d = (float3)(0.0f);
    hit.inv_voxel = 0.0f;
    const float3 inv_d = tr_inverse(d);
    uint stack[BVH_STACK];
    int sp = 0;
    for (uint e = 0u; e != TR_NONE;) {
        if (!(e & TR_LEAF)) {
            ++hit.visits;
            e = tr_next(tr_visit(sc->tlas, e, o, inv_d, t_min, tr_bound(&hit, t_max), stack, &sp, any_hit), stack, &sp);
            continue;
        }
        __global const SdfBvhWideNode* node = sc->tlas + ((e & ~TR_LEAF) >> 2);
        const int k = (int)(e & 3u);
        e = tr_next(TR_NONE, stack, &sp);
        float exit;
        if (tr_slot_slab(node, k, o, inv_d, t_min, tr_bound(&hit, t_max), &exit) > exit) continue;
        const uint inst = (uint)(~node->child[k]);
        const SdfInstance in = sc->instances[inst];
        const SdfBrickGeometry g = sc->geometries[in.geometry];
        if (g.root == SDF_NO_NODE) continue;
        const float* m = in.world_to_geometry;
        const float3 r0 = (float3)(m[0], m[1], m[2]), r1 = (float3)(m[3], m[4], m[5]), r2 = (float3)(m[6], m[7], m[8]);
        const float3 q = o - (float3)(in.translation[0], in.translation[1], in.translation[2]);
        const float3 og = (float3)(tr_dot(r0, q), tr_dot(r1, q), tr_dot(r2, q));
        const float3 dg = (float3)(tr_dot(r0, d), tr_dot(r1, d), tr_dot(r2, d));
        tr_blas(sc, g, inst, og, dg, t_min, t_max, 1.0f / sqrt(tr_dot(dg, dg)), any_hit, &hit);
        if (any_hit && hit.t >= 0.0f) return hit;
    }
    return hit;
}

/* World unit normal at a hit (by the method NORMALS); -d where the stored field is flat (a ray that
 * entered a brick deep inside the solid, where every sample is -band). */
inline float3 tr_normal(const TraceScene* sc, const TraceHit* hit, float3 d) {
    const SdfInstance in = sc->instances[hit->instance];
    const float3 s = (hit->o + hit->t * hit->d - hit->lo) * hit->inv_voxel + (float)APRON - 0.5f;
    const float3 n = tr_gradient(sc->pool + (size_t)hit->brick * S3, s);
    const float* m = in.world_to_geometry;
    /* world = M^T n */
    if (n.x == 0.0f && n.y == 0.0f && n.z == 0.0f) return -d;
    return tr_normalize((float3)(m[0] * n.x + m[3] * n.y + m[6] * n.z, m[1] * n.x + m[4] * n.y + m[7] * n.z,
                                 m[2] * n.x + m[5] * n.y + m[8] * n.z));
}

#endif /* SDFBRICK_SDF_TRACE_H */
