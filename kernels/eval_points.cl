/* eval_points.cl: the field of one geometry at a batch of points (geometry frame).
 * points holds x, y, z per point (tightly packed floats). One work-item per point; edits are read
 * in order straight from global memory (construction stages their chunks through __local memory). */
#include "sdf_edit.h"

__kernel void eval_points(__global const SdfEdit* edits, uint edit_count, __global const float* meshes,
                          __global const float* points, uint point_count,
                          __global float* out) {
    const uint i = get_global_id(0);
    if (i >= point_count) return;
    const float3 p = (float3)(points[3 * i], points[3 * i + 1], points[3 * i + 2]);
    float field = SDF_FAR;
    for (uint j = 0; j < edit_count; ++j) {
        const SdfPrepared e = sdf_prepare(edits[j]);
        field = sdf_apply_edit(&e, meshes, field, p);
    }
    out[i] = field;
}
