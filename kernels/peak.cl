/* peak.cl: a device's peak global-memory bandwidth and FP32 FMA throughput, measured as clpeak does
   (host/measure/peaks.cpp). */

/* Fills the bandwidth buffer, so that the copy reads initialized memory. */
__kernel void peak_fill(__global float4* out) {
    const size_t i = get_global_id(0);
    out[i] = (float4)((float)(i & 1023));
}

/* Global-memory bandwidth: each work-item reads one float4 and writes it (32 bytes moved). */
__kernel void peak_copy(__global const float4* in, __global float4* out) {
    const size_t i = get_global_id(0);
    out[i] = in[i];
}

/* FP32 FMA throughput: 8 independent chains of explicit fma() on PEAK_WIDTH-wide vectors (4 or 16,
   a -D option) in registers, 16 steps per iteration: 8 x 16 x PEAK_WIDTH FMA lanes = 256 x PEAK_WIDTH
   FLOP per iteration and work-item. GPUs run vectors lane by lane; CPU devices fill their SIMD units
   only with the wide variant. With a slightly below 1 and b small, every chain converges to
   b / (1 - a): no overflow, no denormals. The lanes start at different values, so the compiler cannot
   reduce a vector to one lane, and the sum is stored, so nothing is optimized away. */
#ifndef PEAK_WIDTH
#define PEAK_WIDTH 4
#endif
#define PEAK_CAT(a, b) PEAK_CAT_(a, b)
#define PEAK_CAT_(a, b) a##b
typedef PEAK_CAT(float, PEAK_WIDTH) peak_float;

__constant float kPeakLanes[16] = {0.0f,   0.011f, 0.022f, 0.033f, 0.044f, 0.055f, 0.066f, 0.077f,
                                   0.088f, 0.099f, 0.111f, 0.122f, 0.133f, 0.144f, 0.155f, 0.166f};

#define PEAK_STEP            \
    x0 = fma(x0, va, vb);    \
    x1 = fma(x1, va, vb);    \
    x2 = fma(x2, va, vb);    \
    x3 = fma(x3, va, vb);    \
    x4 = fma(x4, va, vb);    \
    x5 = fma(x5, va, vb);    \
    x6 = fma(x6, va, vb);    \
    x7 = fma(x7, va, vb);
#define PEAK_STEP4 PEAK_STEP PEAK_STEP PEAK_STEP PEAK_STEP

__kernel void peak_fma(__global peak_float* out, float a, float b, uint iterations) {
    const float s = (float)(get_global_id(0) & 255) * (1.0f / 256.0f);
    const peak_float va = (peak_float)(a);
    const peak_float vb = (peak_float)(b);
    peak_float x0 = PEAK_CAT(vload, PEAK_WIDTH)(0, kPeakLanes) + s;
    peak_float x1 = x0 + 0.01f;
    peak_float x2 = x0 + 0.02f;
    peak_float x3 = x0 + 0.03f;
    peak_float x4 = x0 + 0.04f;
    peak_float x5 = x0 + 0.05f;
    peak_float x6 = x0 + 0.06f;
    peak_float x7 = x0 + 0.07f;
    for (uint i = 0; i < iterations; ++i) {
        PEAK_STEP4 PEAK_STEP4 PEAK_STEP4 PEAK_STEP4
    }
    out[get_global_id(0)] = ((x0 + x1) + (x2 + x3)) + ((x4 + x5) + (x6 + x7));
}
