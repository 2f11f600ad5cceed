/* bvh_build.cl: stage "bvh". A linear BVH (Karras 2012, "Maximizing parallelism in the construction of
 * BVHs, octrees and k-d trees") over leaves that are already sorted by a unique 64-bit key: the leaf
 * bricks of construction come out in Morton order (children are written in Morton order under their
 * parent, level by level), so no sort is needed; the host sorts the few instance keys of the top level.
 *
 *   bvh_morton_bricks  key of every leaf brick: the Morton code of its lattice coordinate (21 bits per
 *                      axis), and a flag when the order is not strictly increasing (never expected).
 *   bvh_hit_marks      which leaf bricks can hold a hit (a sample at or below the hit threshold); the
 *                      others, outside the surface everywhere, stay out of the tree.
 *   bvh_keep           the kept bricks' keys, in order (an exclusive scan of the marks places them),
 *                      and their brick numbers: the tree's leaf j is brick ids[j].
 *   bvh_hierarchy      n - 1 internal nodes, one work-item each: the node's key range and split, its
 *                      two children (internal or leaf) and the parent links.
 *   bvh_refit          bottom-up from every leaf: each node stores its two children's boxes. A node's
 *                      counter tells the second of its two children to arrive to finish the node: it
 *                      waits until the sibling's box is visible, writes the union into the parent and
 *                      goes on up. The union (min/max) does not depend on which child came second, so
 *                      the tree is the same bit for bit on every run and device: the atomic only
 *                      counts, it never orders a result.
 *   bvh_parity         which internal nodes sit at even depth in their tree (the root at 0): those
 *                      become the wide nodes, numbered by an exclusive scan of the marks.
 *   bvh_widen          the 4-wide nodes the tracer walks (SdfBvhWideNode).
 * Node i's children: child[c] >= 0 is internal node child[c] (+ node_offset in the shared array),
 * child[c] < 0 is leaf ~child[c], a brick number (ids[j] for the tree's leaf j). */
#include "sdf_morton.h"

#define NO_PARENT 0xFFFFFFFFu

#define BVH_FLAG_UNSORTED 1u
#define BVH_FLAG_TOO_LARGE 2u

/* flags: BVH_FLAG_UNSORTED when a key is not above the previous one, BVH_FLAG_TOO_LARGE when a
 * coordinate needs more than 21 bits (atomic_or sets flags: the result does not depend on order). */
__kernel void bvh_morton_bricks(__global const SdfBrick* bricks, uint n, uint finest, uint log2b, __global ulong* keys,
                                __global uint* flags) {
    const uint i = get_global_id(0);
    if (i >= n) return;
    const ulong key = sdf_brick_key(bricks[i], finest, log2b);
    keys[i] = key;
    const uint shift = (finest - bricks[i].level) * log2b;
    if ((uint)(bricks[i].coord[0] | bricks[i].coord[1] | bricks[i].coord[2]) >= (1u << (21u - shift)))
        atomic_or(flags, BVH_FLAG_TOO_LARGE);
    if (i > 0 && sdf_brick_key(bricks[i - 1], finest, log2b) >= key) atomic_or(flags, BVH_FLAG_UNSORTED);
}

#define BVH_MARK_GROUP 64

/* marks[b] = 1 when some sample of brick b < n (pool: samples3 values of the format, 0 int8, 1 int16,
 * 2 float; samples3 a multiple of 8) is at or below threshold (stored units), else 0. The trilinear
 * field between samples that all lie above it does too, so such a brick holds no hit. `parts`
 * work-items share a brick (a power of two up to BVH_MARK_GROUP: several on GPUs, where they read its
 * samples side by side; 1 on CPUs, where work-items run one after another); each stops at its first
 * low sample. */
__attribute__((reqd_work_group_size(BVH_MARK_GROUP, 1, 1)))
__kernel void bvh_hit_marks(__global const uchar* pool, uint n, uint samples3, uint format, float threshold,
                            uint parts, __global uint* marks) {
    local uint found[BVH_MARK_GROUP]; /* per brick of the work-group */
    const uint lid = get_local_id(0), b = get_global_id(0) / parts, part = get_global_id(0) % parts;
    int mine = 0;
    if (b < n) {
        const size_t first = (size_t)b * samples3;
        for (uint s = 8u * part; s < samples3 && !mine; s += 8u * parts) {
            const size_t at = first + s;
            const float8 v = format == 0u   ? convert_float8(vload8(0, (__global const char*)pool + at))
                             : format == 1u ? convert_float8(vload8(0, (__global const short*)pool + at))
                                            : vload8(0, (__global const float*)pool + at);
            mine = any(v <= (float8)(threshold));
        }
    }
    if (parts == 1u) {
        if (b < n) marks[b] = (uint)mine;
        return;
    }
    const uint slot = lid / parts;
    if (part == 0u) found[slot] = 0u;
    barrier(CLK_LOCAL_MEM_FENCE);
    if (mine) atomic_or(&found[slot], 1u); /* only sets: the result does not depend on order */
    barrier(CLK_LOCAL_MEM_FENCE);
    if (part == 0u && b < n) marks[b] = found[slot];
}

/* The marked bricks' keys at their places (at: the exclusive scan of marks), and ids[at[b]] = b. */
__kernel void bvh_keep(__global const ulong* keys, __global const uint* marks, __global const uint* at, uint n,
                       __global ulong* kept_keys, __global uint* ids) {
    const uint b = get_global_id(0);
    if (b >= n || marks[b] == 0u) return;
    kept_keys[at[b]] = keys[b];
    ids[at[b]] = b;
}

/* Length of the common prefix of keys i and j; -1 when j is outside [0, n). */
inline int bvh_delta(__global const ulong* keys, int n, int i, int j) {
    if (j < 0 || j >= n) return -1;
    return (int)clz(keys[i] ^ keys[j]);
}

__kernel void bvh_hierarchy(__global const ulong* keys, __global const uint* ids, uint n_leaves, uint node_offset,
                            __global SdfBvhNode* nodes, __global uint* node_parent, __global uint* leaf_parent) {
    const int i = (int)get_global_id(0);
    const int n = (int)n_leaves;
    if (i >= n - 1) return;
    /* direction of the range, and its other end j */
    const int d = bvh_delta(keys, n, i, i + 1) - bvh_delta(keys, n, i, i - 1) > 0 ? 1 : -1;
    const int delta_min = bvh_delta(keys, n, i, i - d);
    int l_max = 2;
    while (bvh_delta(keys, n, i, i + l_max * d) > delta_min) l_max *= 2;
    int l = 0;
    for (int t = l_max / 2; t >= 1; t /= 2) {
        if (bvh_delta(keys, n, i, i + (l + t) * d) > delta_min) l += t;
    }
    const int j = i + l * d;
    /* split: the last key of the range that shares more than delta_node bits with key i */
    const int delta_node = bvh_delta(keys, n, i, j);
    int s = 0;
    int t = l;
    do {
        t = (t + 1) / 2;
        if (bvh_delta(keys, n, i, i + (s + t) * d) > delta_node) s += t;
    } while (t > 1);
    const int split = i + s * d + min(d, 0);
    const int lo = min(i, j), hi = max(i, j);

    SdfBvhNode node;
    for (int a = 0; a < 3; ++a) {
        node.lo0[a] = node.lo1[a] = INFINITY;
        node.hi0[a] = node.hi1[a] = -INFINITY;
    }
    node.pad[0] = node.pad[1] = 0u;
    const uint me = node_offset + (uint)i;
    if (lo == split) {
        node.child[0] = ~(int)ids[split];
        leaf_parent[split] = me;
    } else {
        node.child[0] = (int)(node_offset + (uint)split);
        node_parent[split] = me;
    }
    if (hi == split + 1) {
        node.child[1] = ~(int)ids[split + 1];
        leaf_parent[split + 1] = me;
    } else {
        node.child[1] = (int)(node_offset + (uint)(split + 1));
        node_parent[split + 1] = me;
    }
    nodes[me] = node;
    if (i == 0) node_parent[0] = NO_PARENT;
}

/* Writes box into slot c of node. */
inline void bvh_store_slot(__global SdfBvhNode* node, int c, const float lo[3], const float hi[3]) {
    __global float* f = (__global float*)node + 6 * c;
    for (int a = 0; a < 3; ++a) {
        f[a] = lo[a];
        f[3 + a] = hi[a];
    }
}

#define BVH_FLAG_REFIT_STUCK 4u
#define BVH_SPIN_LIMIT (1 << 24)

__kernel void bvh_refit(__global const SdfBounds* leaf_boxes, __global const uint* ids, uint n_leaves, uint node_offset,
                        __global SdfBvhNode* nodes, __global const uint* node_parent,
                        __global const uint* leaf_parent, __global uint* arrivals, __global SdfBounds* root_boxes,
                        uint root_slot, __global uint* flags) {
    __global SdfBounds* root_box = root_boxes + root_slot;
    const uint i = get_global_id(0);
    if (i >= n_leaves) return;
    const SdfBounds leaf = leaf_boxes[ids[i]];
    float lo[3] = {leaf.lo[0], leaf.lo[1], leaf.lo[2]};
    float hi[3] = {leaf.hi[0], leaf.hi[1], leaf.hi[2]};
    if (n_leaves == 1u) { /* no internal node: a root whose two children are this leaf */
        SdfBvhNode root;
        for (int a = 0; a < 3; ++a) {
            root.lo0[a] = root.lo1[a] = lo[a];
            root.hi0[a] = root.hi1[a] = hi[a];
        }
        root.child[0] = root.child[1] = ~(int)ids[0];
        root.pad[0] = root.pad[1] = 0u;
        nodes[node_offset] = root;
        *root_box = leaf;
        return;
    }
    int child = ~(int)ids[i];
    uint node = leaf_parent[i];
    for (;;) {
        const int c = nodes[node].child[0] == child ? 0 : 1;
        bvh_store_slot(nodes + node, c, lo, hi);
        mem_fence(CLK_GLOBAL_MEM_FENCE);
        if (atomic_inc(&arrivals[node - node_offset]) == 0u) return; /* the sibling finishes this node */
        /* The sibling has arrived, but OpenCL 1.2 does not promise that its box is visible yet across
         * work-groups: read the slot (volatile: from memory, not a stale cache line) until it no longer
         * holds the empty box bvh_hierarchy put there. A box is never empty, so the wait ends. */
        volatile __global const float* f = (volatile __global const float*)(nodes + node) + 6 * (1 - c);
        float s[6];
        for (int spin = 0;; ++spin) {
            for (int a = 0; a < 6; ++a) s[a] = f[a];
            if (s[0] != INFINITY && s[1] != INFINITY && s[2] != INFINITY && s[3] != -INFINITY &&
                s[4] != -INFINITY && s[5] != -INFINITY)
                break;
            if (spin == BVH_SPIN_LIMIT) { /* never expected: report, do not hang */
                atomic_or(flags, BVH_FLAG_REFIT_STUCK);
                return;
            }
        }
        for (int a = 0; a < 3; ++a) {
            lo[a] = fmin(lo[a], s[a]);
            hi[a] = fmax(hi[a], s[3 + a]);
        }
        const uint parent = node_parent[node - node_offset];
        if (parent == NO_PARENT) {
            SdfBounds box;
            for (int a = 0; a < 3; ++a) {
                box.lo[a] = lo[a];
                box.hi[a] = hi[a];
            }
            *root_box = box;
            return;
        }
        child = (int)node;
        node = parent;
    }
}

/* Two slots of a wide node, from one child of a binary node: an internal child gives its own two
 * children, a leaf gives itself and an unused slot. */
typedef struct BvhPair {
    float lo[2][3], hi[2][3];
    int child[2];
} BvhPair;

inline BvhPair bvh_pair(__global const SdfBvhNode* nodes, int child, const float* lo, const float* hi) {
    BvhPair p;
    if (child >= 0) {
        const SdfBvhNode m = nodes[child];
        for (int a = 0; a < 3; ++a) {
            p.lo[0][a] = m.lo0[a];
            p.hi[0][a] = m.hi0[a];
            p.lo[1][a] = m.lo1[a];
            p.hi[1][a] = m.hi1[a];
        }
        p.child[0] = m.child[0];
        p.child[1] = m.child[1];
        return p;
    }
    for (int a = 0; a < 3; ++a) {
        p.lo[0][a] = lo[a];
        p.hi[0][a] = hi[a];
        p.lo[1][a] = p.hi[1][a] = 0.0f;
    }
    p.child[0] = child;
    p.child[1] = SDF_WIDE_EMPTY;
    return p;
}

/* even[node_offset + i] = 1 when internal node i of the tree is at even depth, else 0; counts[slot]
 * counts the tree's marks (the atomic only counts). A tree of one leaf has only its root. */
__kernel void bvh_parity(__global const uint* node_parent, uint n_leaves, uint node_offset, __global uint* even,
                         __global uint* counts, uint slot) {
    const uint i = get_global_id(0);
    if (i >= max(n_leaves, 2u) - 1u) return;
    uint depth = 0;
    if (n_leaves > 1u) {
        uint node = i; /* index within the tree; parents are stored as indices in the shared array */
        for (int up = 0; up < 64 && node_parent[node] != NO_PARENT; ++up) {
            node = node_parent[node] - node_offset;
            ++depth;
        }
    }
    even[node_offset + i] = (depth & 1u) == 0u ? 1u : 0u;
    if ((depth & 1u) == 0u) atomic_inc(&counts[slot]);
}

/* Wide node map[i] from binary node i at even depth: slots 0-1 from child 0, 2-3 from child 1
 * (bvh_pair), an internal grandchild named by its own wide index map[g]; a repeated leaf (a tree of
 * one leaf) is taken once. Indices are those of the shared array, so one launch covers every tree
 * in it. Pure copies: the same bits on every device. */
__kernel void bvh_widen(__global const SdfBvhNode* nodes, uint count, __global const uint* even,
                        __global const uint* map, __global SdfBvhWideNode* wide) {
    const uint i = get_global_id(0);
    if (i >= count || even[i] == 0u) return;
    const SdfBvhNode n = nodes[i];
    BvhPair p = bvh_pair(nodes, n.child[0], n.lo0, n.hi0);
    BvhPair q = bvh_pair(nodes, n.child[1], n.lo1, n.hi1);
    if (n.child[1] == n.child[0]) q.child[0] = SDF_WIDE_EMPTY;
    p.child[0] = p.child[0] >= 0 ? (int)map[p.child[0]] : p.child[0];
    p.child[1] = p.child[1] >= 0 ? (int)map[p.child[1]] : p.child[1];
    q.child[0] = q.child[0] >= 0 ? (int)map[q.child[0]] : q.child[0];
    q.child[1] = q.child[1] >= 0 ? (int)map[q.child[1]] : q.child[1];
    __global float4* out = (__global float4*)(wide + map[i]);
    for (int a = 0; a < 3; ++a) {
        out[a] = (float4)(p.lo[0][a], p.lo[1][a], q.lo[0][a], q.lo[1][a]);
        out[3 + a] = (float4)(p.hi[0][a], p.hi[1][a], q.hi[0][a], q.hi[1][a]);
    }
    out[6] = as_float4((int4)(p.child[0], p.child[1], q.child[0], q.child[1]));
    out[7] = (float4)(0.0f);
}
