/* brick_cull.cl: stage "cull". Refines each new brick's edit list (inherited from its parent) to the
 * edits that may change the band-limited field anywhere the brick's descendants will test or sample:
 * within radius of the brick's centre (half its diagonal plus the sample apron). With dependencies
 * on, every edit that a kept smooth edit depends on (and that the parent's list holds) is kept too.
 * Lists stay unique and ascending: a bit per parent-list entry, then compaction.
 *   (brick_subdivide wrote the words of each brick's bit set; cull_words for a re-cull)  -> scan -> word offsets
 *   cull_mark:  the bit set, and where each word's entries are in the parent lists
 *   cull_dependencies (with dependencies on): the bits of the kept smooth edits' dependencies
 *   scan_popcount_blocks (scan.cl): the kept count per word (its bits), scanned -> each word's output slot
 *   cull_write: the compacted lists; the bricks' edit_offset / edit_count now name them
 * cull_mark and cull_write take `span` bits per work-item (a power of two up to 32): 1 where a level
 * has few (the top levels: few bricks, long lists), so that the device is full, up to a word where it
 * has many (then fewer work-items do more each). Where a level's bricks are new children that share
 * their parents' lists, cull_mark_siblings takes their place: one work-group per parent. */
#include "sdf_build.h"

/* Position of value in the ascending list[0, n), or n when absent. */
inline uint find_sorted(__global const uint* list, uint n, uint value) {
    uint lo = 0, hi = n;
    while (lo < hi) {
        const uint mid = lo + ((hi - lo) >> 1);
        if (list[mid] < value) lo = mid + 1u; else hi = mid;
    }
    return lo < n && list[lo] == value ? lo : n;
}

/* The entry of an exclusive scan that owns position w: the last whose offset is <= w (entries with
 * empty ranges are skipped). */
inline uint owner_of(__global const uint* offsets, uint count, uint w) {
    uint lo = 0, hi = count;
    while (hi - lo > 1u) {
        const uint mid = lo + ((hi - lo) >> 1);
        if (offsets[mid] <= w) lo = mid; else hi = mid;
    }
    return lo;
}

/* Per brick, the words of its list's bit set, where bricks are culled again from their own lists
 * (brick_subdivide writes them for new bricks). */
__kernel void cull_words(__global const SdfBrick* bricks, uint count, __global uint* words) {
    const uint i = get_global_id(0);
    if (i < count) words[i] = (bricks[i].edit_count + 31u) >> 5;
}

/* cull_mark_siblings: per parent, its work-groups (each takes share_words of its list's words; none
 * where it kept no children). groups has parent_count entries; their exclusive scan numbers the
 * work-groups, so that a parent's share of them follows its list's length. */
__kernel void sibling_groups(__global const SdfBrick* bricks, __global const uint* child_offsets,
                             __global const uint* child_counts, uint parent_count, uint share_words,
                             __global uint* groups) {
    const uint p = get_global_id(0);
    if (p >= parent_count) return;
    const uint words = child_counts[p] == 0u ? 0u : (bricks[child_offsets[p]].edit_count + 31u) >> 5;
    groups[p] = (words + share_words - 1u) / share_words;
}

/* cull_mark_siblings: stages the m entries of the list from word w0 on, each edit prepared (as
 * edit_prepare.cl left it, with its reach), with its reach limit (sdf_reach_limit). */
inline void stage_words(__global const SdfPrepared* prepared, __global const float* reaches, __global const uint* list,
                        uint w0, uint m, uint lid, uint wg, __local SdfPrepared* staged, __local float* limits,
                        float clamp_c, float radius, float magnitude) {
    for (uint j = lid; j < m; j += wg) {
        const uint k = list[(w0 << 5) + j];
        const SdfPrepared e = prepared[k];
        staged[j] = e;
        limits[j] = sdf_reach_limit(e.blend, reaches[k], clamp_c, radius, magnitude);
    }
}

#if SDF_LANES == 1 /* a program built with CPU lanes serves cull_mark_siblings alone */
/* span bits per work-item (32 / span work-items per word, side by side in one work-group of
 * get_local_size(0), a multiple of 32 / span): each sets the bits of the entries it keeps in its
 * word through a __local word (OR: the order does not matter), whose first work-item writes it. */
__kernel void cull_mark(__global const SdfPrepared* prepared, __global const float* reaches, __global const float* meshes,
                        __global const uint* parent_indices, __global const SdfBrick* bricks, uint count, uint total_words, uint span,
                        float origin_x, float origin_y, float origin_z, float cell,
                        float radius, float clamp_c, float magnitude,
                        __global const uint* word_offsets, __global uint* bits, __global uint* sources,
                        __local uint* words) {
    const uint t = get_global_id(0), per_word = 32u / span;
    const uint w = t / per_word, part = t % per_word, slot = get_local_id(0) / per_word;
    if (part == 0u) words[slot] = 0u;
    barrier(CLK_LOCAL_MEM_FENCE);
    if (w < total_words) {
        const uint i = owner_of(word_offsets, count, w);
        const SdfBrick b = bricks[i];
        const float3 c = sdf_cell_centre((float3)(origin_x, origin_y, origin_z), cell,
                                         (int3)(b.coord[0], b.coord[1], b.coord[2]));
        __global const uint* list = parent_indices + b.edit_offset;
        const uint word_first = (w - word_offsets[i]) << 5, first = word_first + part * span;
        const uint end = min(b.edit_count, first + span);
        uint word = 0;
        for (uint j = first; j < end; ++j) {
            const uint k = list[j];
            const SdfPrepared e = prepared[k];
            const float limit = sdf_reach_limit(e.blend, reaches[k], clamp_c, radius, magnitude);
            if (sdf_within_reach((e.kind >> 8) & 0xffu, sdf_prepared_value(&e, meshes, c), limit)) word |= 1u << (j & 31u);
        }
        if (word != 0u) atomic_or(&words[slot], word);
        if (part == 0u) sources[w] = b.edit_offset + word_first;
    }
    barrier(CLK_LOCAL_MEM_FENCE);
    if (part == 0u && w < total_words) bits[w] = words[slot];
}

#endif

/* The bits of cull_mark, for new children (brick_subdivide: a parent's kept children lie together at
 * child_offsets[parent], child_counts[parent] of them, and share its list): sibling_groups' work-groups
 * per parent (group_first: their exclusive scan), each taking share_words of the list's words. The
 * share is staged through __local memory in chunks of whole words, each edit read and prepared
 * once for all the children; a work-item takes one child and one word of a chunk (children fastest,
 * so the work-items of a word read the same staged edits) and tests its 32 edits. With SDF_LANES >
 * 1 (CPU devices) a work-item takes SDF_LANES children instead (lane l: child g * SDF_LANES + l, g =
 * lid % groups, groups = ceil(children / SDF_LANES); lanes past the last child repeat it and are not
 * written) and tests the 32 edits at all their centres at once, the one-lane operations in every
 * lane. */
__kernel void cull_mark_siblings(__global const SdfPrepared* prepared, __global const float* reaches,
                                 __global const float* meshes,
                                 __global const uint* parent_indices, __global const SdfBrick* bricks,
                                 __global const uint* child_offsets, __global const uint* child_counts,
                                 float origin_x, float origin_y, float origin_z, float cell,
                                 float radius, float clamp_c, float magnitude,
                                 __global const uint* word_offsets, __global uint* bits, __global uint* sources,
                                 __local SdfPrepared* staged, __local float* limits, uint chunk_words,
                                 __global const uint* group_first, uint parent_count, uint share_words) {
    const uint parent = owner_of(group_first, parent_count, get_group_id(0));
    const uint split = get_group_id(0) - group_first[parent];
    const uint lid = get_local_id(0), wg = get_local_size(0);
    const uint kids = child_counts[parent]; /* at least 1: a parent without children has no work-group */
    const uint first = child_offsets[parent];
    const SdfBrick b0 = bricks[first];
    __global const uint* list = parent_indices + b0.edit_offset;
    const uint n = b0.edit_count;
    const uint from = split * share_words, to = min((n + 31u) >> 5, from + share_words);
    const float3 origin = (float3)(origin_x, origin_y, origin_z);
#if SDF_LANES == 1
    const uint per_chunk = clamp(wg / kids, 1u, chunk_words); /* words a chunk */
    const uint child = lid % kids, slot = lid / kids; /* the host gives at least B^3 work-items */
    const uint mine = first + child, out = word_offsets[mine];
    const SdfBrick b = bricks[mine];
    const float3 c = sdf_cell_centre(origin, cell, (int3)(b.coord[0], b.coord[1], b.coord[2]));
#else
    const uint groups = (kids + SDF_LANES - 1u) / SDF_LANES;
    const uint per_chunk = clamp(wg / groups, 1u, chunk_words); /* words a chunk */
    const uint g = lid % groups, slot = lid / groups;
    float x[SDF_LANES], y[SDF_LANES], z[SDF_LANES];
    for (uint l = 0; l < SDF_LANES; ++l) {
        const SdfBrick b = bricks[first + min(g * SDF_LANES + l, kids - 1u)];
        const float3 c = sdf_cell_centre(origin, cell, (int3)(b.coord[0], b.coord[1], b.coord[2]));
        x[l] = c.x;
        y[l] = c.y;
        z[l] = c.z;
    }
    const sdf_real px = SDF_REAL_CAT(vload, SDF_LANES)(0, x), py = SDF_REAL_CAT(vload, SDF_LANES)(0, y),
                   pz = SDF_REAL_CAT(vload, SDF_LANES)(0, z);
#endif
    for (uint w0 = from; w0 < to; w0 += per_chunk) {
        const uint m = min(min(per_chunk, to - w0) << 5, n - (w0 << 5));
        barrier(CLK_LOCAL_MEM_FENCE);
        stage_words(prepared, reaches, list, w0, m, lid, wg, staged, limits, clamp_c, radius, magnitude);
        barrier(CLK_LOCAL_MEM_FENCE);
        if (slot < per_chunk && w0 + slot < to) {
            const uint lo = slot << 5, hi = min(lo + 32u, m);
            const uint source = b0.edit_offset + ((w0 + slot) << 5);
#if SDF_LANES == 1
            uint word = 0;
            for (uint j = lo; j < hi; ++j) {
                const SdfPrepared e = staged[j];
                if (sdf_within_reach((e.kind >> 8) & 0xffu, sdf_prepared_value(&e, meshes, c), limits[j]))
                    word |= 1u << (j & 31u);
            }
            bits[out + w0 + slot] = word;
            sources[out + w0 + slot] = source;
#else
            sdf_index word = 0;
            for (uint j = lo; j < hi; ++j) {
                const SdfPrepared e = staged[j];
                const sdf_index in =
                    sdf_within_reach((e.kind >> 8) & 0xffu, sdf_edit_value(&e, meshes, px, py, pz), limits[j]);
                word |= select((sdf_index)(0), (sdf_index)(as_int(1u << (j & 31u))), in);
            }
            int w[SDF_LANES];
            SDF_REAL_CAT(vstore, SDF_LANES)(word, 0, w);
            for (uint l = 0; l < SDF_LANES && g * SDF_LANES + l < kids; ++l) {
                const uint out = word_offsets[first + g * SDF_LANES + l];
                bits[out + w0 + slot] = (uint)w[l];
                sources[out + w0 + slot] = source;
            }
#endif
        }
    }
}


/* Per brick (with dependencies on): the dependencies of every edit kept by cull_mark that is smooth
 * (and that the inherited list holds; no closure) get their bits too. */
__kernel void cull_dependencies(__global const SdfEdit* edits, __global const uint* parent_indices,
                                __global const SdfBrick* bricks, uint count, __global const uint* word_offsets,
                                __global uint* bits, __global const uint* dep_offsets,
                                __global const uint* dep_indices) {
    const uint i = get_global_id(0);
    if (i >= count) return;
    const SdfBrick b = bricks[i];
    __global const uint* list = parent_indices + b.edit_offset;
    __global uint* mask = bits + word_offsets[i];
    const uint words = (b.edit_count + 31u) >> 5;
    for (uint w = 0; w < words; ++w) {
        uint word = mask[w];
        while (word != 0u) {
            const uint j = (w << 5) + (31u - clz(word & (0u - word)));
            word &= word - 1u;
            const uint edit = list[j];
            if (!(edits[edit].blend > 0.0f)) continue;
            for (uint d = dep_offsets[edit]; d < dep_offsets[edit + 1u]; ++d) {
                const uint q = find_sorted(list, b.edit_count, dep_indices[d]);
                if (q < b.edit_count) mask[q >> 5] |= 1u << (q & 31u);
            }
        }
    }
}

/* span bits per work-item (with one, a warp writes one word's entries side by side): a kept entry
 * goes to its word's first output slot (the prefix sum of the kept counts) plus the kept entries
 * before it in the word. The first `count`
 * work-items also give their brick its new list (bricks are not read here otherwise: sources holds
 * each word's first entry in the parent lists). */
__kernel void cull_write(__global const uint* parent_indices, __global SdfBrick* bricks, uint count, uint total_words,
                         uint span, __global const uint* word_offsets, __global const uint* bits,
                         __global const uint* sources, __global const uint* word_lists, __global uint* indices) {
    const uint t = get_global_id(0);
    const uint first = t * span, end = min(first + span, total_words << 5);
    for (uint k = first; k < end;) {
        const uint w = k >> 5, all = bits[w], out = word_lists[w], source = sources[w];
        const uint lo = k & 31u, hi = min(end - (w << 5), 32u); /* this word's bits [lo, hi) */
        uint word = all & (0xffffffffu << lo) & (hi == 32u ? 0xffffffffu : (1u << hi) - 1u);
        while (word != 0u) {
            const uint bit = 31u - clz(word & (0u - word));
            word &= word - 1u;
            indices[out + popcount(all & ((1u << bit) - 1u))] = parent_indices[source + bit];
        }
        k = (w << 5) + hi;
    }
    if (t < count) {
        const uint from = word_offsets[t];
        const uint to = from + ((bricks[t].edit_count + 31u) >> 5);
        bricks[t].edit_offset = word_lists[from];
        bricks[t].edit_count = word_lists[to] - word_lists[from];
    }
}
