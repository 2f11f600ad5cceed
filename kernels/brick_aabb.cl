/* brick_aabb.cl: stage "aabb". The box of each leaf brick (geometry frame) for the BVH. */
#include "sdf_types.h"

__kernel void brick_aabb(__global const SdfBrick* bricks, uint count,
                         float origin_x, float origin_y, float origin_z, float leaf, __global SdfBounds* boxes) {
    const uint i = get_global_id(0);
    if (i >= count) return;
    const SdfBrick b = bricks[i];
    const float o[3] = {origin_x, origin_y, origin_z};
    SdfBounds box;
    for (int a = 0; a < 3; ++a) {
        box.lo[a] = o[a] + (float)b.coord[a] * leaf;
        box.hi[a] = o[a] + (float)(b.coord[a] + 1) * leaf;
    }
    boxes[i] = box;
}
