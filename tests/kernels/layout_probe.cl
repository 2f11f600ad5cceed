/* layout_probe.cl: reports sizeof and field offsets of the shared structs as the device compiler
 * lays them out, for tests/kernels/test_layout.cpp to compare with the host's. The offsets are measured on
 * a real object in global memory (no offsetof in OpenCL C 1.2). Order of the entries: see the test. */
#include "sdf_types.h"

#define SDF_OFF(obj, field) ((uint)((__global const char*)&(obj)->field - (__global const char*)(obj)))

__kernel void layout_probe(__global const SdfEdit* edit, __global const SdfBounds* bounds,
                           __global const SdfBrick* brick, __global const SdfCamera* camera,
                           __global const SdfBvhNode* node, __global const SdfBvhWideNode* wide,
                           __global const SdfInstance* instance,
                           __global const SdfBrickGeometry* geometry, __global const SdfShading* shading,
                           __global const SdfMeshGrid* mesh,
                           __global const SdfPrepared* prepared, __global uint* out) {
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
    out[n++] = (uint)sizeof(SdfCamera);
    out[n++] = SDF_OFF(camera, forward);
    out[n++] = SDF_OFF(camera, right);
    out[n++] = SDF_OFF(camera, up);
    out[n++] = SDF_OFF(camera, width);
    out[n++] = SDF_OFF(camera, height);
    out[n++] = (uint)sizeof(SdfBvhNode);
    out[n++] = SDF_OFF(node, hi0);
    out[n++] = SDF_OFF(node, lo1);
    out[n++] = SDF_OFF(node, hi1);
    out[n++] = SDF_OFF(node, child);
    out[n++] = (uint)sizeof(SdfBvhWideNode);
    out[n++] = SDF_OFF(wide, lo_y);
    out[n++] = SDF_OFF(wide, hi_x);
    out[n++] = SDF_OFF(wide, child);
    out[n++] = (uint)sizeof(SdfInstance);
    out[n++] = SDF_OFF(instance, translation);
    out[n++] = SDF_OFF(instance, scale);
    out[n++] = SDF_OFF(instance, geometry);
    out[n++] = (uint)sizeof(SdfBrickGeometry);
    out[n++] = SDF_OFF(geometry, inv_voxel);
    out[n++] = SDF_OFF(geometry, dequant);
    out[n++] = SDF_OFF(geometry, root);
    out[n++] = SDF_OFF(geometry, brick_offset);
    out[n++] = (uint)sizeof(SdfShading);
    out[n++] = SDF_OFF(shading, light_color);
    out[n++] = SDF_OFF(shading, shadow_spread);
    out[n++] = SDF_OFF(shading, ao_radius);
    out[n++] = SDF_OFF(shading, ray_offset);
    out[n++] = SDF_OFF(shading, shadow_rays);
    out[n++] = SDF_OFF(shading, ao_rays);
    out[n++] = (uint)sizeof(SdfMeshGrid);
    out[n++] = SDF_OFF(mesh, cell);
    out[n++] = SDF_OFF(mesh, inv_cell);
    out[n++] = SDF_OFF(mesh, dims);
    out[n++] = SDF_OFF(mesh, offset);
    out[n++] = SDF_OFF(mesh, tiles);
    out[n++] = SDF_OFF(mesh, coarse);
    out[n++] = SDF_OFF(mesh, centres);
    out[n++] = (uint)sizeof(SdfPrepared);
    out[n++] = SDF_OFF(prepared, inv_scale);
    out[n++] = SDF_OFF(prepared, q);
    out[n++] = SDF_OFF(prepared, prm);
    out[n++] = SDF_OFF(prepared, out_scale);
    out[n++] = SDF_OFF(prepared, blend);
    out[n++] = SDF_OFF(prepared, blend_q);
    out[n++] = SDF_OFF(prepared, kind);
    out[n++] = 0xC0FFEEu; /* end marker: the host checks it to know the list was not cut short */
}
