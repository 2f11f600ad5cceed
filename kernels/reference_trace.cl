/* reference_trace.cl: the device reference tracer. Sphere traces the ANALYTIC edit lists (no bricks)
 * for every pixel; every accuracy figure of the brick tracer is measured against its output.
 * host/reference/device_tracer.{h,cpp} builds the inputs; docs/reference.md documents the method. In short:
 *
 * The field. The tracer finds the zero set of F, the exact (unclamped, unculled) edit fold of
 * sdf_edit.h starting from SDF_FAR, the same F as eval_points.cl and the host reference. At a point
 * it folds only the edits whose box contains the point (box_i = level set { v_i <= C + k_i + margin }
 * of edit i, found through a BVH over the boxes), and carries two running values:
 *     lo = min(combine(lo, v), C)    starting at C          (a lower bound of F)
 *     hi = max(combine(hi, v), -C)   starting at SDF_FAR    (an upper bound of F)
 * Every combine is monotone in the field, so lo <= F <= hi holds through the folded edits; skipping
 * an add / subtract edit outside its box (v >= C + k) keeps both bounds valid (bit for bit unchanged
 * while they lie in [-C, C]: |F - v| >= k makes the blend term exactly 0), and an intersect edit
 * outside its box makes F >= C + k, so the fold restarts after it from lo = C, hi = SDF_FAR. Near the surface lo == hi == F almost everywhere
 * (the first edit with a value <= C - k collapses both to it); where the sign is undecided,
 * lo <= 0 < hi, the point falls back to the exact fold of all the geometry's edits (counted;
 * ref_fold_exact skips, bit for bit, the far edits that cannot change it).
 * So the sign of F is exact at every point the tracer looks at, whatever C is: C only trades the
 * number of edits per point against the largest step (lo <= C).
 *
 * Determinism: only + - * / sqrt fabs fmin fmax nextafter, written out in a fixed order (no
 * dot/length/normalize), FP_CONTRACT OFF and correctly rounded divide/sqrt (the program builder);
 * each work-item's output depends on its pixel only; the counters are per pixel (no atomics).
 */
#include "sdf_edit.h"
#include "sdf_camera.h"

/* Per geometry (mirrored by RefGeometry in host/reference/device_tracer.cpp, static_assert on size). */
typedef struct RefGeometry {
    float clip_lo[3];   /* the ray is traced where it is inside this box (holds the solid) */
    float clip_hi[3];
    float clamp_c;      /* C */
    float min_step;     /* smallest step, geometry units */
    float normal_h;     /* central-difference step of the normal, geometry units */
    uint edit_offset;   /* into edits and boxes */
    uint edit_count;
    uint node_offset;   /* into nodes; 0 nodes: no edits */
    uint node_count;
    uint isect_offset;  /* into isect: ascending geometry-local indices of the intersect edits */
    uint isect_count;
    uint pad;
} RefGeometry;

#ifndef REF_LIST_CAP
#define REF_LIST_CAP 256
#endif
#define REF_STACK 64
#define REF_BISECT_MAX 64

/* aux.y flags (SDF_REF_UNCONVERGED = 1 is in sdf_types.h). */
#define REF_FLAG_INSIDE 2u   /* the hit is the ray's first point: it starts inside the solid */
#define REF_FLAG_FALLBACK 4u /* some point of this ray needed the exact fold of all edits */
#define REF_FLAG_OVERFLOW 8u /* some point of this ray had more than REF_LIST_CAP boxes */

typedef struct RefScene {
    __global const RefGeometry* geoms;
    __global const SdfEdit* edits;
    __global const float* meshes; /* the mesh pool (sdf_types.h) */
    __global const SdfBounds* boxes;
    __global const SdfBvhNode* nodes;
    __global const uint* isect;
    uint exact;
} RefScene;

typedef struct RefCounts {
    uint overflow; /* points with more than REF_LIST_CAP candidate edits */
    uint fallback; /* points that needed the exact fold */
} RefCounts;

inline int ref_in_child0(__global const SdfBvhNode* n, float3 p) {
    return p.x >= n->lo0[0] && p.x <= n->hi0[0] && p.y >= n->lo0[1] && p.y <= n->hi0[1] && p.z >= n->lo0[2] &&
           p.z <= n->hi0[2];
}

inline int ref_in_child1(__global const SdfBvhNode* n, float3 p) {
    return p.x >= n->lo1[0] && p.x <= n->hi1[0] && p.y >= n->lo1[1] && p.y <= n->hi1[1] && p.z >= n->lo1[2] &&
           p.z <= n->hi1[2];
}

inline int ref_in_gbox(__global const SdfBounds* b, float3 p) {
    return p.x >= b->lo[0] && p.x <= b->hi[0] && p.y >= b->lo[1] && p.y <= b->hi[1] && p.z >= b->lo[2] &&
           p.z <= b->hi[2];
}

/* The exact field: all edits in order from SDF_FAR, no clamp (what eval_points.cl computes). */
inline float ref_fold_all(const RefScene* s, const RefGeometry* g, float3 p) {
    float f = SDF_FAR;
    for (uint i = 0; i < g->edit_count; ++i) {
        const SdfPrepared e = sdf_prepare(s->edits[g->edit_offset + i]);
        f = sdf_apply_edit(&e, s->meshes, f, p);
    }
    return f;
}

/* The same value, bit for bit, skipping the edits that cannot change it: outside its box an edit's
 * value is >= C + k, so an add edit is a no-op while the running value is <= C and a subtract edit
 * while it is >= -C (|F - v| >= k: the blend term is exactly 0 and min / max return F). Intersect
 * edits are always evaluated. Costs a box test per edit plus the edits before the value first
 * drops to C (those have to be evaluated: there F > C, where far edits still matter). */
inline float ref_fold_exact(const RefScene* s, const RefGeometry* g, float3 p) {
    float f = SDF_FAR;
    const float c = g->clamp_c;
    for (uint i = 0; i < g->edit_count; ++i) {
        const uint op = s->edits[g->edit_offset + i].op;
        if (op != SDF_OP_INTERSECT && !ref_in_gbox(&s->boxes[g->edit_offset + i], p)) {
            if (op == SDF_OP_ADD && f <= c) continue;
            if (op == SDF_OP_SUBTRACT && f >= -c) continue;
        }
        const SdfPrepared e = sdf_prepare(s->edits[g->edit_offset + i]);
        f = sdf_apply_edit(&e, s->meshes, f, p);
    }
    return f;
}

inline void ref_fold_one(const RefScene* s, const RefGeometry* g, uint i, float3 p, float* lo, float* hi) {
    const SdfPrepared e = sdf_prepare(s->edits[g->edit_offset + i]);
    const float v = sdf_prepared_value(&e, s->meshes, p);
    *lo = fmin(sdf_combine(&e, *lo, v), g->clamp_c);
    *hi = fmax(sdf_combine(&e, *hi, v), -g->clamp_c);
}

/* (lo, hi) with lo <= F(p) <= hi, folding only the edits whose box holds p. */
inline float2 ref_bounds(const RefScene* s, const RefGeometry* g, float3 p, uint* list, RefCounts* counts) {
    /* The fold restarts after the last intersect edit whose box does not hold p. */
    uint first = 0;
    for (uint k = g->isect_count; k > 0; --k) {
        const uint idx = s->isect[g->isect_offset + k - 1u];
        if (!ref_in_gbox(&s->boxes[g->edit_offset + idx], p)) {
            first = idx + 1u;
            break;
        }
    }
    float lo = g->clamp_c, hi = SDF_FAR;
    if (g->node_count == 0u) return (float2)(lo, hi);

    /* Collect the edits (index >= first) whose box holds p. */
    uint n = 0;
    int overflow = 0;
    int stack[REF_STACK];
    int top = 0;
    stack[top++] = 0;
    while (top > 0 && !overflow) {
        const __global SdfBvhNode* node = &s->nodes[g->node_offset + (uint)stack[--top]];
        for (int c = 0; c < 2; ++c) {
            const int inside = c == 0 ? ref_in_child0(node, p) : ref_in_child1(node, p);
            if (!inside) continue;
            const int child = node->child[c];
            if (child >= 0) {
                if (top < REF_STACK) stack[top++] = child;
                else overflow = 1; /* cannot happen: the host checks the depth */
            } else {
                const uint idx = (uint)(~child);
                if (idx < first) continue;
                if (n < REF_LIST_CAP) list[n++] = idx;
                else overflow = 1;
            }
        }
    }
    if (overflow) {
        /* Exact and slower: every edit from `first` on, in order, box tested (same edits, same order). */
        counts->overflow += 1u;
        for (uint i = first; i < g->edit_count; ++i)
            if (ref_in_gbox(&s->boxes[g->edit_offset + i], p)) ref_fold_one(s, g, i, p, &lo, &hi);
        return (float2)(lo, hi);
    }
    /* Ascending order (insertion sort: the lists are short). */
    for (uint i = 1; i < n; ++i) {
        const uint x = list[i];
        uint j = i;
        while (j > 0u && list[j - 1u] > x) {
            list[j] = list[j - 1u];
            --j;
        }
        list[j] = x;
    }
    for (uint i = 0; i < n; ++i) ref_fold_one(s, g, list[i], p, &lo, &hi);
    return (float2)(lo, hi);
}

/* What the march reads at p: (lo, hi) with a decided sign (hi <= 0: inside, lo > 0: outside). */
inline float2 ref_sample(const RefScene* s, const RefGeometry* g, float3 p, uint* list, RefCounts* counts) {
    if (s->exact) {
        const float f = ref_fold_all(s, g, p);
        return (float2)(f, f);
    }
    const float2 b = ref_bounds(s, g, p, list, counts);
    if (b.x <= 0.0f && b.y > 0.0f) {
        counts->fallback += 1u;
        const float f = ref_fold_exact(s, g, p);
        return (float2)(f, f);
    }
    return b;
}

/* The value of F at p (the normal's taps): exact, falling back when lo != hi. */
inline float ref_value(const RefScene* s, const RefGeometry* g, float3 p, uint* list, RefCounts* counts) {
    if (s->exact) return ref_fold_all(s, g, p);
    const float2 b = ref_bounds(s, g, p, list, counts);
    if (b.x == b.y) return b.x;
    counts->fallback += 1u;
    return ref_fold_exact(s, g, p);
}

inline float3 ref_point(float3 o, float3 d, float t) { return o + t * d; }

/* Clips o + t d, t >= 0, to the box; returns 0 when it misses. */
inline int ref_clip(float3 o, float3 d, const float lo[3], const float hi[3], float* t0, float* t1) {
    float a = 0.0f, b = INFINITY;
    const float oo[3] = {o.x, o.y, o.z};
    const float dd[3] = {d.x, d.y, d.z};
    if (!(lo[0] <= hi[0] && lo[1] <= hi[1] && lo[2] <= hi[2])) return 0;
    for (int i = 0; i < 3; ++i) {
        if (dd[i] == 0.0f) {
            if (oo[i] < lo[i] || oo[i] > hi[i]) return 0;
            continue;
        }
        const float ta = (lo[i] - oo[i]) / dd[i];
        const float tb = (hi[i] - oo[i]) / dd[i];
        a = fmax(a, fmin(ta, tb));
        b = fmin(b, fmax(ta, tb));
    }
    *t0 = a;
    *t1 = b;
    return a <= b;
}

/* The world ray (eye, dir) in the instance's geometry frame (sdf_types.h, SdfInstance). */
inline void ref_ray_to_geometry(const SdfInstance* inst, float3 eye, float3 dir, float3* og, float3* dg) {
    const float* m = inst->world_to_geometry;
    const float3 r = eye - (float3)(inst->translation[0], inst->translation[1], inst->translation[2]);
    *og = (float3)(m[0] * r.x + m[1] * r.y + m[2] * r.z, m[3] * r.x + m[4] * r.y + m[5] * r.z,
                   m[6] * r.x + m[7] * r.y + m[8] * r.z);
    *dg = (float3)(m[0] * dir.x + m[1] * dir.y + m[2] * dir.z, m[3] * dir.x + m[4] * dir.y + m[5] * dir.z,
                   m[6] * dir.x + m[7] * dir.y + m[8] * dir.z);
}

__kernel void reference_trace(__global const SdfCamera* camera, __global const SdfInstance* instances,
                              uint instance_count, __global const RefGeometry* geoms,
                              __global const SdfEdit* edits, __global const float* meshes,
                              __global const SdfBounds* boxes, __global const SdfBvhNode* nodes, __global const uint* isect, uint max_steps,
                              uint exact, __global float4* out_hit, __global uint2* out_aux,
                              __global uint2* out_counts) {
    const uint x = get_global_id(0), y = get_global_id(1);
    const SdfCamera cam = *camera;
    if (x >= cam.width || y >= cam.height) return;
    const uint pixel = y * cam.width + x;

    RefScene s;
    s.geoms = geoms;
    s.edits = edits;
    s.meshes = meshes;
    s.boxes = boxes;
    s.nodes = nodes;
    s.isect = isect;
    s.exact = exact;
    RefCounts counts;
    counts.overflow = 0u;
    counts.fallback = 0u;
    uint list[REF_LIST_CAP];

    const float3 eye = sdf_camera_eye(&cam);
    const float3 dir = sdf_camera_dir(&cam, x, y);

    float best_t = INFINITY;
    uint best_instance = 0u;
    int best_inside = 0;
    float unconverged_t = INFINITY;
    uint steps = 0u;

    for (uint k = 0; k < instance_count; ++k) {
        const SdfInstance inst = instances[k];
        const RefGeometry g = geoms[inst.geometry];
        float3 og, dg;
        ref_ray_to_geometry(&inst, eye, dir, &og, &dg);
        /* p_g(t) = og + t dg with |dg| = 1 / scale: a step of D geometry units along the ray is
         * D / |dg| in t (world units). */
        const float dg_len = sdf_len3(dg);
        float t0, t1;
        if (!ref_clip(og, dg, g.clip_lo, g.clip_hi, &t0, &t1)) continue;
        float t = t0, t_prev = t0;
        int have_prev = 0;
        uint n = 0u;
        for (;;) {
            if (n >= max_steps) {
                unconverged_t = fmin(unconverged_t, t);
                break;
            }
            ++n;
            const float2 b = ref_sample(&s, &g, ref_point(og, dg, t), list, &counts);
            if (b.y <= 0.0f) { /* inside: F(t) <= 0 */
                float hit_t = t;
                if (have_prev) { /* F(t_prev) > 0 >= F(t): bisect to adjacent floats */
                    float a = t_prev, c = t;
                    for (int i = 0; i < REF_BISECT_MAX; ++i) {
                        const float mid = a + 0.5f * (c - a);
                        if (mid <= a || mid >= c) break;
                        const float2 bm = ref_sample(&s, &g, ref_point(og, dg, mid), list, &counts);
                        if (bm.y <= 0.0f) c = mid;
                        else a = mid;
                    }
                    hit_t = c;
                }
                if (hit_t < best_t) {
                    best_t = hit_t;
                    best_instance = k;
                    best_inside = !have_prev;
                }
                break;
            }
            if (t > t1) break; /* left the clip box: no surface on this instance */
            const float step = fmax(fmin(b.x, g.clamp_c), g.min_step) / dg_len;
            t_prev = t;
            have_prev = 1;
            float t_next = t + step;
            if (!(t_next > t)) t_next = nextafter(t, INFINITY);
            t = t_next;
        }
        steps += n;
    }

    uint flags = 0u;
    float4 hit = (float4)(0.0f, 0.0f, 0.0f, SDF_MISS);
    if (unconverged_t < best_t) {
        flags |= SDF_REF_UNCONVERGED; /* a nearer surface than any hit found may have been missed */
    } else if (best_t < INFINITY) {
        const SdfInstance inst = instances[best_instance];
        const RefGeometry g = geoms[inst.geometry];
        float3 og, dg;
        ref_ray_to_geometry(&inst, eye, dir, &og, &dg);
        const float3 p = ref_point(og, dg, best_t);
        const float h = g.normal_h;
        const float gx = ref_value(&s, &g, p + (float3)(h, 0.0f, 0.0f), list, &counts) -
                         ref_value(&s, &g, p - (float3)(h, 0.0f, 0.0f), list, &counts);
        const float gy = ref_value(&s, &g, p + (float3)(0.0f, h, 0.0f), list, &counts) -
                         ref_value(&s, &g, p - (float3)(0.0f, h, 0.0f), list, &counts);
        const float gz = ref_value(&s, &g, p + (float3)(0.0f, 0.0f, h), list, &counts) -
                         ref_value(&s, &g, p - (float3)(0.0f, 0.0f, h), list, &counts);
        /* geometry -> world: M^T n, then normalised */
        const float* m = inst.world_to_geometry;
        float3 nw = (float3)(m[0] * gx + m[3] * gy + m[6] * gz, m[1] * gx + m[4] * gy + m[7] * gz,
                             m[2] * gx + m[5] * gy + m[8] * gz);
        const float len = sdf_len3(nw);
        if (len > 0.0f && len < INFINITY) nw = nw / len;
        else nw = -dir; /* no gradient (flat or broken field): face the eye */
        hit = (float4)(nw.x, nw.y, nw.z, best_t);
        if (best_inside) flags |= REF_FLAG_INSIDE;
    }
    if (counts.fallback > 0u) flags |= REF_FLAG_FALLBACK;
    if (counts.overflow > 0u) flags |= REF_FLAG_OVERFLOW;
    out_hit[pixel] = hit;
    out_aux[pixel] = (uint2)(steps, flags);
    out_counts[pixel] = (uint2)(counts.overflow, counts.fallback);
}
