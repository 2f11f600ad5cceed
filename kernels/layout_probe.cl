/* layout_probe.cl: reports sizeof and field offsets of the shared structs as the device compiler
 * lays them out, for tests/test_layout.cpp to compare with the host's. The offsets are measured on
 * a real object in global memory (no offsetof in OpenCL C 1.2). Order of the entries: see the test. */
#include "sdf_types.h"

#define SDF_OFF(obj, field) ((uint)((__global const char*)&(obj)->field - (__global const char*)(obj)))

__kernel void layout_probe(__global const SdfEdit* edit, __global const SdfBounds* bounds,
                           __global const SdfBrick* brick, __global uint* out) {
    if (get_global_id(0) != 0) return;
    uint n = 0;
    out[n++] = (uint)sizeof(SdfTransform);
    out[n++] = (uint)sizeof(SdfEdit);
    out[n++] = (uint)sizeof(SdfBounds);
    out[n++] = (uint)sizeof(SdfBrick);
    out[n++] = SDF_OFF(edit, transform.translation);
    out[n++] = SDF_OFF(edit, transform.scale);
    out[n++] = SDF_OFF(edit, transform.rotation);
    out[n++] = SDF_OFF(edit, params);
    out[n++] = SDF_OFF(edit, blend);
    out[n++] = SDF_OFF(edit, inv_lipschitz);
    out[n++] = SDF_OFF(edit, primitive);
    out[n++] = SDF_OFF(edit, op);
    out[n++] = SDF_OFF(bounds, lo);
    out[n++] = SDF_OFF(bounds, hi);
    out[n++] = SDF_OFF(brick, coord);
    out[n++] = SDF_OFF(brick, level);
    out[n++] = SDF_OFF(brick, edit_offset);
    out[n++] = SDF_OFF(brick, edit_count);
    out[n++] = SDF_OFF(brick, child_mask);
    out[n++] = 0xC0FFEEu; /* end marker: the host checks it to know the list was not cut short */
}
