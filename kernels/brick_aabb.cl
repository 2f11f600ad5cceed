/* brick_aabb.cl: stage "aabb". The box of each leaf brick (geometry frame) for the BVH; a leaf of a
 * coarser level than the finest (adaptive builds) has a cell of leaf * B^(finest - level) = leaf * 2^shift;
 * the shift is written for the tracer too. */
#include "sdf_types.h"

__kernel void brick_aabb(__global const SdfBrick* bricks, uint count,
                         float origin_x, float origin_y, float origin_z, float finest_leaf, uint finest, uint log2b,
                         __global SdfBounds* boxes, __global uint* shifts) {
    const uint i = get_global_id(0);
    if (i >= count) return;
    const SdfBrick b = bricks[i];
    const uint shift = (finest - b.level) * log2b;
    const float leaf = ldexp(finest_leaf, (int)shift);
    shifts[i] = shift;
    const float o[3] = {origin_x, origin_y, origin_z};
    SdfBounds box;
    for (int a = 0; a < 3; ++a) {
        box.lo[a] = o[a] + (float)b.coord[a] * leaf;
        box.hi[a] = o[a] + (float)(b.coord[a] + 1) * leaf;
    }
    boxes[i] = box;
}
