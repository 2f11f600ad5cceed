/* edit_deps.cl: dependencies between edits (stage "dependencies", docs/construction.md). A smooth
 * edit j (blend > 0) depends on every earlier edit i < j whose influence box overlaps j's (closed
 * boxes: touching counts). host/construct/edit_deps.cpp drives the kernels:
 *
 *   grid_stats   per work-group: union of the finite box coordinates, sum of the box extents
 *   grid_refs    per work-group: how many grid cells the boxes cover (to cap the grid's memory)
 *   fill_uint    zero the cell counters
 *   grid_count   per box, count it in every cell it covers (atomic increments: only counts)
 *   (scan)       cell starts
 *   grid_fill    cell lists (atomic slots: the order inside a cell list is not deterministic...)
 *   grid_sort    ... until each cell list is sorted ascending
 *   deps_count   per smooth edit, its dependencies
 *   (scan)       list offsets (CSR)
 *   deps_write   per smooth edit, its list, then sorted ascending: the output is deterministic.
 *
 * The grid: cubic cells of side 1/inv from origin, dims dx * dy * dz cells, x fastest. A coordinate
 * maps to its cell by grid_coord, clamped to the grid (infinite coordinates land in the edge cells,
 * NaN in cell 0). grid_coord is monotone, so a box covers the contiguous cell range
 * [coord(lo), coord(hi)] per axis, and where two boxes intersect, the cell of the intersection's low
 * corner is max(coord(lo_i), coord(lo_j)) per axis: a cell both boxes cover. A pair is reported only
 * in that cell, so exactly once.
 *
 * A box is valid when lo <= hi on every axis (false with NaN); invalid boxes are in no cell and
 * overlap nothing. */
#include "sdf_types.h"

inline uint grid_coord(float x, float origin, float inv, uint dims) {
    float f = (x - origin) * inv;
    f = fmax(f, 0.0f); /* NaN -> 0 */
    f = fmin(f, (float)(dims - 1u));
    return (uint)f;
}

inline int box_valid(const SdfBounds* b) {
    return b->lo[0] <= b->hi[0] && b->lo[1] <= b->hi[1] && b->lo[2] <= b->hi[2];
}

inline int boxes_overlap(const SdfBounds* a, const SdfBounds* b) {
    return a->lo[0] <= b->hi[0] && b->lo[0] <= a->hi[0] && a->lo[1] <= b->hi[1] && b->lo[1] <= a->hi[1] &&
           a->lo[2] <= b->hi[2] && b->lo[2] <= a->hi[2];
}

inline int is_finite_value(float v) { return fabs(v) <= FLT_MAX; } /* false for inf and NaN */

#define GRID_PARAMS float ox, float oy, float oz, float inv, uint dx, uint dy, uint dz

/* Cell range of a valid box. */
inline void grid_range(const SdfBounds* b, GRID_PARAMS, uint lo[3], uint hi[3]) {
    lo[0] = grid_coord(b->lo[0], ox, inv, dx);
    lo[1] = grid_coord(b->lo[1], oy, inv, dy);
    lo[2] = grid_coord(b->lo[2], oz, inv, dz);
    hi[0] = grid_coord(b->hi[0], ox, inv, dx);
    hi[1] = grid_coord(b->hi[1], oy, inv, dy);
    hi[2] = grid_coord(b->hi[2], oz, inv, dz);
}

/* Per work-group (local size a power of two): out[group * 10 + k] =
 *   k 0..2: min of the finite lo coordinates of valid boxes (+inf if none)
 *   k 3..5: max of the finite hi coordinates of valid boxes (-inf if none)
 *   k 6..8: sum of the extents of valid boxes with finite coordinates
 *   k 9:    how many such boxes (a float: exact below 2^24).
 * The tree reduction has a fixed order: the sums depend only on the local size. */
__kernel void grid_stats(__global const SdfBounds* boxes, uint n, __global float* out, __local float* scratch) {
    const uint gid = get_global_id(0), lid = get_local_id(0), wg = get_local_size(0);
    float v[10];
    for (int k = 0; k < 3; ++k) {
        v[k] = INFINITY;
        v[3 + k] = -INFINITY;
        v[6 + k] = 0.0f;
    }
    v[9] = 0.0f;
    if (gid < n) {
        const SdfBounds b = boxes[gid];
        if (box_valid(&b)) {
            int finite = 1;
            for (int k = 0; k < 3; ++k) {
                if (is_finite_value(b.lo[k])) v[k] = b.lo[k];
                if (is_finite_value(b.hi[k])) v[3 + k] = b.hi[k];
                finite &= is_finite_value(b.lo[k]) && is_finite_value(b.hi[k]);
            }
            if (finite) {
                for (int k = 0; k < 3; ++k) v[6 + k] = b.hi[k] - b.lo[k];
                v[9] = 1.0f;
            }
        }
    }
    for (int k = 0; k < 10; ++k) scratch[k * wg + lid] = v[k];
    barrier(CLK_LOCAL_MEM_FENCE);
    for (uint stride = wg >> 1; stride > 0; stride >>= 1) {
        if (lid < stride) {
            for (int k = 0; k < 3; ++k) {
                scratch[k * wg + lid] = fmin(scratch[k * wg + lid], scratch[k * wg + lid + stride]);
                scratch[(3 + k) * wg + lid] = fmax(scratch[(3 + k) * wg + lid], scratch[(3 + k) * wg + lid + stride]);
            }
            for (int k = 6; k < 10; ++k) scratch[k * wg + lid] = scratch[k * wg + lid] + scratch[k * wg + lid + stride];
        }
        barrier(CLK_LOCAL_MEM_FENCE);
    }
    if (lid < 10) out[get_group_id(0) * 10 + lid] = scratch[lid * wg];
}

/* Per work-group (local size a power of two): the number of cell references of its boxes. */
__kernel void grid_refs(__global const SdfBounds* boxes, uint n, GRID_PARAMS, __global ulong* out,
                        __local ulong* scratch) {
    const uint gid = get_global_id(0), lid = get_local_id(0), wg = get_local_size(0);
    ulong refs = 0;
    if (gid < n) {
        const SdfBounds b = boxes[gid];
        if (box_valid(&b)) {
            uint lo[3], hi[3];
            grid_range(&b, ox, oy, oz, inv, dx, dy, dz, lo, hi);
            refs = (ulong)(hi[0] - lo[0] + 1u) * (ulong)(hi[1] - lo[1] + 1u) * (ulong)(hi[2] - lo[2] + 1u);
        }
    }
    scratch[lid] = refs;
    barrier(CLK_LOCAL_MEM_FENCE);
    for (uint stride = wg >> 1; stride > 0; stride >>= 1) {
        if (lid < stride) scratch[lid] += scratch[lid + stride];
        barrier(CLK_LOCAL_MEM_FENCE);
    }
    if (lid == 0) out[get_group_id(0)] = scratch[0];
}

__kernel void fill_uint(__global uint* out, uint n, uint value) {
    const uint i = get_global_id(0);
    if (i < n) out[i] = value;
}

__kernel void grid_count(__global const SdfBounds* boxes, uint n, GRID_PARAMS, __global uint* counts) {
    const uint i = get_global_id(0);
    if (i >= n) return;
    const SdfBounds b = boxes[i];
    if (!box_valid(&b)) return;
    uint lo[3], hi[3];
    grid_range(&b, ox, oy, oz, inv, dx, dy, dz, lo, hi);
    for (uint z = lo[2]; z <= hi[2]; ++z)
        for (uint y = lo[1]; y <= hi[1]; ++y)
            for (uint x = lo[0]; x <= hi[0]; ++x) atomic_inc(&counts[(z * dy + y) * dx + x]);
}

/* cursor: the cell counts (grid_count's output); each slot taken decrements it, so it ends at 0. */
__kernel void grid_fill(__global const SdfBounds* boxes, uint n, GRID_PARAMS, __global const uint* starts,
                        __global uint* cursor, __global uint* items) {
    const uint i = get_global_id(0);
    if (i >= n) return;
    const SdfBounds b = boxes[i];
    if (!box_valid(&b)) return;
    uint lo[3], hi[3];
    grid_range(&b, ox, oy, oz, inv, dx, dy, dz, lo, hi);
    for (uint z = lo[2]; z <= hi[2]; ++z)
        for (uint y = lo[1]; y <= hi[1]; ++y)
            for (uint x = lo[0]; x <= hi[0]; ++x) {
                const uint cell = (z * dy + y) * dx + x;
                items[starts[cell] + atomic_dec(&cursor[cell]) - 1u] = i;
            }
}

/* Visits the dependencies of edit j (each exactly once, in no particular order); with out == 0 only
 * counts them. Returns the count. */
inline uint visit_dependencies(uint j, __global const SdfEdit* edits, __global const SdfBounds* boxes, GRID_PARAMS,
                               __global const uint* starts, __global const uint* items, __global uint* out) {
    if (!(edits[j].blend > 0.0f)) return 0u;
    const SdfBounds bj = boxes[j];
    if (!box_valid(&bj)) return 0u;
    uint lo[3], hi[3];
    grid_range(&bj, ox, oy, oz, inv, dx, dy, dz, lo, hi);
    uint count = 0;
    for (uint z = lo[2]; z <= hi[2]; ++z)
        for (uint y = lo[1]; y <= hi[1]; ++y)
            for (uint x = lo[0]; x <= hi[0]; ++x) {
                const uint cell = (z * dy + y) * dx + x;
                const uint end = starts[cell + 1u];
                for (uint k = starts[cell]; k < end; ++k) {
                    const uint i = items[k];
                    if (i >= j) break; /* cell lists are ascending */
                    const SdfBounds bi = boxes[i];
                    if (!boxes_overlap(&bi, &bj)) continue;
                    /* Report in the cell of the intersection's low corner only. j covers this cell, so
                     * per axis: this is max(coord(lo_i), coord(lo_j)) iff it is coord(lo_j) (i covers
                     * the cell, so coord(lo_i) <= it) or it is coord(lo_i). */
                    if (x != lo[0] && grid_coord(bi.lo[0], ox, inv, dx) != x) continue;
                    if (y != lo[1] && grid_coord(bi.lo[1], oy, inv, dy) != y) continue;
                    if (z != lo[2] && grid_coord(bi.lo[2], oz, inv, dz) != z) continue;
                    if (out) out[count] = i;
                    ++count;
                }
            }
    return count;
}

/* counts has n + 1 entries; counts[n] = 0 so that its exclusive scan ends with the total. */
__kernel void deps_count(__global const SdfEdit* edits, __global const SdfBounds* boxes, uint n, GRID_PARAMS,
                         __global const uint* starts, __global const uint* items, __global uint* counts) {
    const uint j = get_global_id(0);
    if (j > n) return;
    counts[j] = j < n ? visit_dependencies(j, edits, boxes, ox, oy, oz, inv, dx, dy, dz, starts, items, 0) : 0u;
}

/* Heap sort of a[0 .. len) ascending (in place, O(len log len) in the worst case). */
/* Moves a[root] down the max-heap a[0, len) to its place. */
inline void sift_down(__global uint* a, uint root, uint len) {
    const uint v = a[root];
    for (;;) {
        uint child = 2u * root + 1u;
        if (child >= len) break;
        if (child + 1u < len && a[child + 1u] > a[child]) ++child;
        if (a[child] <= v) break;
        a[root] = a[child];
        root = child;
    }
    a[root] = v;
}

inline void sort_uints(__global uint* a, uint len) {
    uint sorted = 1;
    for (uint k = 1; k < len && sorted; ++k) sorted = a[k - 1] <= a[k];
    if (sorted) return;
    /* Build a max-heap, then repeatedly move the maximum to the end. */
    for (uint start = len / 2; start-- > 0;) sift_down(a, start, len);
    for (uint end = len; end-- > 1;) {
        const uint v = a[end];
        a[end] = a[0];
        a[0] = v;
        sift_down(a, 0, end);
    }
}

/* Sorts every cell list ascending (one work-item per cell): the cell lists, and so everything
 * after grid_fill, no longer depend on the order of the atomics, and the dependency search can stop
 * at the first edit that is not earlier. */
__kernel void grid_sort(__global const uint* starts, uint cells, __global uint* items) {
    const uint c = get_global_id(0);
    if (c >= cells) return;
    sort_uints(items + starts[c], starts[c + 1u] - starts[c]);
}

__kernel void deps_write(__global const SdfEdit* edits, __global const SdfBounds* boxes, uint n, GRID_PARAMS,
                         __global const uint* starts, __global const uint* items, __global const uint* offsets,
                         __global uint* indices) {
    const uint j = get_global_id(0);
    if (j >= n) return;
    const uint first = offsets[j];
    const uint len = offsets[j + 1u] - first;
    if (len == 0u) return;
    visit_dependencies(j, edits, boxes, ox, oy, oz, inv, dx, dy, dz, starts, items, indices + first);
    sort_uints(indices + first, len);
}
