/* mesh_sdf.cl: the signed distance of a closed triangle mesh at the points of a regular grid.
 *
 * One work-item per grid point p = origin + (i, j, k) * cell, i fastest. The nearest triangle is found
 * through a binary BVH over the triangles (SdfBvhNode, leaves ~triangle; nearer child first, a child
 * skipped when its box is no nearer than the best so far), the closest point by Ericson's region
 * test, which also names the feature it lies on (face, edge or vertex). The sign is that of
 * (p - closest) . n with n the feature's angle-weighted pseudo-normal (Baerentzen and Aanaes 2005),
 * exact for closed, consistently oriented meshes. Each triangle carries 7 pseudo-normals: face,
 * edges ab, bc, ca, vertices a, b, c (21 floats); its corners are 9 floats.
 * Arithmetic is written out in a fixed order (no dot/length), so every device gives the same bits. */
#include "sdf_types.h"

#define MESH_STACK 64

inline float m_dot(float3 a, float3 b) { return (a.x * b.x + a.y * b.y) + a.z * b.z; }

inline float3 m_load(__global const float* f) { return (float3)(f[0], f[1], f[2]); }

/* Squared distance from p to the box [lo, hi] (0 inside). */
inline float m_box_d2(__global const float* lo, __global const float* hi, float3 p) {
    const float3 d = fmax(fmax(m_load(lo) - p, p - m_load(hi)), (float3)(0.0f));
    return m_dot(d, d);
}

/* Closest point of triangle abc to p (Ericson, Real-Time Collision Detection 5.1.5); *feature is
 * 0 face, 1 edge ab, 2 edge bc, 3 edge ca, 4 vertex a, 5 vertex b, 6 vertex c. */
inline float3 m_closest(float3 p, float3 a, float3 b, float3 c, int* feature) {
    const float3 ab = b - a, ac = c - a, ap = p - a;
    const float d1 = m_dot(ab, ap), d2 = m_dot(ac, ap);
    if (d1 <= 0.0f && d2 <= 0.0f) { *feature = 4; return a; }
    const float3 bp = p - b;
    const float d3 = m_dot(ab, bp), d4 = m_dot(ac, bp);
    if (d3 >= 0.0f && d4 <= d3) { *feature = 5; return b; }
    const float vc = d1 * d4 - d3 * d2;
    if (vc <= 0.0f && d1 >= 0.0f && d3 <= 0.0f) { *feature = 1; return a + (d1 / (d1 - d3)) * ab; }
    const float3 cp = p - c;
    const float d5 = m_dot(ab, cp), d6 = m_dot(ac, cp);
    if (d6 >= 0.0f && d5 <= d6) { *feature = 6; return c; }
    const float vb = d5 * d2 - d1 * d6;
    if (vb <= 0.0f && d2 >= 0.0f && d6 <= 0.0f) { *feature = 3; return a + (d2 / (d2 - d6)) * ac; }
    const float va = d3 * d6 - d5 * d4;
    if (va <= 0.0f && (d4 - d3) >= 0.0f && (d5 - d6) >= 0.0f) {
        *feature = 2;
        return b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b);
    }
    const float denom = 1.0f / ((va + vb) + vc);
    *feature = 0;
    return a + ab * (vb * denom) + ac * (vc * denom);
}

/* The signed distance from p to the mesh. */
inline float m_distance(__global const SdfBvhNode* nodes, __global const float* corners, __global const float* normals,
                        float3 p) {
    float best = INFINITY;
    float3 best_q = p;
    int best_tri = -1, best_feature = 0;
    int stack[MESH_STACK];
    int sp = 0;
    int node = 0;
    for (;;) {
        __global const SdfBvhNode* n = nodes + node;
        const float da = m_box_d2(n->lo0, n->hi0, p), db = m_box_d2(n->lo1, n->hi1, p);
        int next = -1;
        for (int side = 0; side < 2; ++side) {
            /* nearer child first: side 0 takes the nearer one */
            const int first = db < da ? 1 : 0;
            const int child = side == 0 ? n->child[first] : n->child[1 - first];
            const float d = side == 0 ? fmin(da, db) : fmax(da, db);
            if (d >= best) continue;
            if (child < 0) {
                const int t = ~child;
                __global const float* v = corners + 9 * (size_t)t;
                int feature;
                const float3 q = m_closest(p, m_load(v), m_load(v + 3), m_load(v + 6), &feature);
                const float3 e = p - q;
                const float d2 = m_dot(e, e);
                if (d2 < best || (d2 == best && t < best_tri)) {
                    best = d2;
                    best_q = q;
                    best_tri = t;
                    best_feature = feature;
                }
            } else if (next < 0) {
                next = child;
            } else if (sp < MESH_STACK) {
                stack[sp++] = child;
            }
        }
        if (next >= 0) { node = next; continue; }
        if (sp == 0) break;
        node = stack[--sp];
    }
    const float3 nrm = m_load(normals + 21 * (size_t)best_tri + 3 * best_feature);
    const float s = m_dot(p - best_q, nrm) < 0.0f ? -1.0f : 1.0f;
    return s * sqrt(best);
}

__kernel void mesh_sdf(__global const SdfBvhNode* nodes, __global const float* corners,
                       __global const float* normals, float origin_x, float origin_y, float origin_z, float cell,
                       uint nx, uint ny, uint nz, __global float* out) {
    const uint id = get_global_id(0);
    if (id >= nx * ny * nz) return;
    const uint i = id % nx, j = (id / nx) % ny, k = id / (nx * ny);
    const float3 p = (float3)(origin_x, origin_y, origin_z) + (float3)((float)i, (float)j, (float)k) * cell;
    out[id] = m_distance(nodes, corners, normals, p);
}

/* The points of whole tiles of a sparse grid (SdfMeshGrid): tile t = (tiles[3t], tiles[3t+1],
 * tiles[3t+2]) holds the 9^3 points (8 t + l) of the regular grid, l in 0..8 (i fastest), 729 values a
 * tile in order. A point's value equals mesh_sdf's at the same (i, j, k). */
__kernel void mesh_sdf_tiles(__global const SdfBvhNode* nodes, __global const float* corners,
                             __global const float* normals, float origin_x, float origin_y, float origin_z, float cell,
                             __global const uint* tiles, uint count, __global float* out) {
    const uint id = get_global_id(0);
    if (id >= count * 729u) return;
    const uint t = id / 729u, l = id % 729u;
    const uint i = 8u * tiles[3u * t] + l % 9u, j = 8u * tiles[3u * t + 1u] + (l / 9u) % 9u,
               k = 8u * tiles[3u * t + 2u] + l / 81u;
    const float3 p = (float3)(origin_x, origin_y, origin_z) + (float3)((float)i, (float)j, (float)k) * cell;
    out[id] = m_distance(nodes, corners, normals, p);
}
