/* trace.cl: stage "trace". One work-item per pixel: the camera ray through the two-level BVH of bricks
 * (sdf_trace.h), the nearest hit's depth and world normal, and counters for the heat map.
 * Output (sdf_types.h): hit = (normal, depth) or (0, 0, 0, SDF_MISS); aux = (global brick index or
 * SDF_NO_BRICK, BVH nodes visited (saturated at 65535) | in-brick steps (saturated at 32767) << 16 |
 * SDF_TRACE_CAPPED when a brick's search stopped at a loop bound). */
#include "sdf_camera.h"
#include "sdf_trace.h"

__kernel void trace_primary(__global const SdfCamera* camera, __global const SdfBvhWideNode* tlas,
                            __global const SdfInstance* instances, __global const SdfBrickGeometry* geometries,
                            __global const SdfBvhWideNode* nodes, __global const sample_t* pool,
                            __global const uint* shifts, __global float4* out_hit,
                            __global uint2* out_aux) {
    const uint x = get_global_id(0), y = get_global_id(1);
    const SdfCamera cam = *camera;
    if (x >= cam.width || y >= cam.height) return;
    TraceScene sc;
    sc.tlas = tlas;
    sc.instances = instances;
    sc.geometries = geometries;
    sc.nodes = nodes;
    sc.pool = pool;
    sc.shifts = shifts;
    const float3 d = sdf_camera_dir(&cam, x, y);
    const TraceHit hit = tr_trace(&sc, sdf_camera_eye(&cam), d, 0.0f, INFINITY, 0);
    const size_t i = (size_t)y * cam.width + x;
    const uint counters = min(hit.visits, 65535u) | (min(hit.steps, 32767u) << 16) | (hit.capped ? SDF_TRACE_CAPPED : 0u);
    if (hit.t >= 0.0f) {
        const float3 n = tr_normal(&sc, &hit, d);
        out_hit[i] = (float4)(n, hit.t);
        out_aux[i] = (uint2)(hit.brick, counters);
    } else {
        out_hit[i] = (float4)(0.0f, 0.0f, 0.0f, SDF_MISS);
        out_aux[i] = (uint2)(SDF_NO_BRICK, counters);
    }
}
