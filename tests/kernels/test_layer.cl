/* test_layer.cl: small kernels for the device layer's own tests (tests/cl/test_device_layer.cpp). */

/* out[i] = in[i] * a + b for i < n. */
__kernel void scale_add(__global const float* in, __global float* out, float a, float b, uint n) {
    const uint i = get_global_id(0);
    if (i < n) {
        out[i] = in[i] * a + b;
    }
}

/* Reverses each work-group's slice of in through __local memory (exercises LocalMemory arguments). */
__kernel void reverse_groups(__global const uint* in, __global uint* out, __local uint* scratch) {
    const uint lid = get_local_id(0);
    const uint size = get_local_size(0);
    const uint base = get_group_id(0) * size;
    scratch[lid] = in[base + lid];
    barrier(CLK_LOCAL_MEM_FENCE);
    out[base + lid] = scratch[size - 1 - lid];
}
