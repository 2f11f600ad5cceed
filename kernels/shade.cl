/* shade.cl: stage "shade" of the shaded mode. From the primary hits (trace.cl): Blinn-Phong with a
 * directional light, soft shadows (shadow_rays rays spread over the light's disc) and ambient occlusion
 * (ao_rays cosine-distributed rays within ao_radius), all secondary rays any-hit rays through the same
 * BVH. Sample patterns: an R2 sequence rotated per pixel by an integer hash, mapped to the disc without
 * trigonometry (only + - * / sqrt, so every device computes the same colours). */
#include "sdf_camera.h"
#include "sdf_trace.h"

inline uint sh_hash(uint v) {
    v ^= v >> 16;
    v *= 0x7feb352du;
    v ^= v >> 15;
    v *= 0x846ca68bu;
    v ^= v >> 16;
    return v;
}

inline float sh_unit(uint h) { return (float)(h >> 8) * (1.0f / 16777216.0f); } /* [0, 1), exact */
inline float sh_frac(float v) { return v - floor(v); }

/* Point k of the pixel's pattern in the unit disc (elliptical grid mapping of [-1, 1]^2). */
inline float2 sh_disc(uint k, float2 jitter) {
    const float a = 2.0f * sh_frac(jitter.x + (float)k * 0.7548776662f) - 1.0f;
    const float b = 2.0f * sh_frac(jitter.y + (float)k * 0.5698402910f) - 1.0f;
    return (float2)(a * sqrt(1.0f - 0.5f * b * b), b * sqrt(1.0f - 0.5f * a * a));
}

/* Two unit vectors completing n to an orthonormal frame (Duff et al. 2017). */
inline void sh_frame(float3 n, float3* t1, float3* t2) {
    const float sign = copysign(1.0f, n.z);
    const float a = -1.0f / (sign + n.z);
    const float b = n.x * n.y * a;
    *t1 = (float3)(1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x);
    *t2 = (float3)(b, sign + n.y * n.y * a, -n.y);
}

__kernel void shade(__global const SdfCamera* camera, __global const SdfBvhWideNode* tlas,
                    __global const SdfInstance* instances, __global const SdfBrickGeometry* geometries,
                    __global const SdfBvhWideNode* nodes, __global const sample_t* pool, __global const uint* shifts,
                    __global const SdfShading* shading,
                    __global const float4* hits, __global float4* colour) {
    const uint x = get_global_id(0), y = get_global_id(1);
    const SdfCamera cam = *camera;
    if (x >= cam.width || y >= cam.height) return;
    const size_t i = (size_t)y * cam.width + x;
    const float3 d = sdf_camera_dir(&cam, x, y);
    const float4 h = hits[i];
    const float3 sky = (float3)(0.55f, 0.63f, 0.75f);
    if (h.w < 0.0f) {
        colour[i] = (float4)(sky * (0.75f + 0.25f * fmax(d.y, 0.0f)), 1.0f);
        return;
    }
    TraceScene sc;
    sc.tlas = tlas;
    sc.instances = instances;
    sc.geometries = geometries;
    sc.nodes = nodes;
    sc.pool = pool;
    sc.shifts = shifts;
    const SdfShading sh = *shading;
    const float3 n = h.xyz;
    const float3 l = (float3)(sh.light_dir[0], sh.light_dir[1], sh.light_dir[2]);
    const float3 light = (float3)(sh.light_color[0], sh.light_color[1], sh.light_color[2]);
    const float3 origin = sdf_camera_eye(&cam) + h.w * d + sh.ray_offset * n;
    const uint seed = sh_hash(x * 0x9E3779B9u ^ sh_hash(y));
    const float2 jitter = (float2)(sh_unit(seed), sh_unit(sh_hash(seed)));

    float3 t1, t2;
    float visible = 0.0f;
    sh_frame(l, &t1, &t2);
    for (uint k = 0; k < sh.shadow_rays; ++k) {
        const float2 p = sh_disc(k, jitter);
        const float3 dir = tr_normalize(l + sh.shadow_spread * (p.x * t1 + p.y * t2));
        if (tr_dot(dir, n) > 0.0f && tr_trace(&sc, origin, dir, 0.0f, INFINITY, 1).t < 0.0f) visible += 1.0f;
    }
    const float shadow = sh.shadow_rays ? visible / (float)sh.shadow_rays : 1.0f;

    float open = 0.0f;
    sh_frame(n, &t1, &t2);
    for (uint k = 0; k < sh.ao_rays; ++k) {
        const float2 p = sh_disc(k, (float2)(jitter.y, jitter.x));
        const float z = sqrt(fmax(1.0f - p.x * p.x - p.y * p.y, 0.0f));
        const float3 dir = tr_normalize(p.x * t1 + p.y * t2 + z * n);
        if (tr_trace(&sc, origin, dir, 0.0f, sh.ao_radius, 1).t < 0.0f) open += 1.0f;
    }
    const float ao = sh.ao_rays ? open / (float)sh.ao_rays : 1.0f;

    const float ndl = fmax(tr_dot(n, l), 0.0f);
    const float ndh = fmax(tr_dot(n, tr_normalize(l - d)), 0.0f);
    float spec = ndh * ndh; /* ndh^32 by squaring */
    spec *= spec;
    spec *= spec;
    spec *= spec;
    spec *= spec;
    const float3 albedo = (float3)(0.78f, 0.76f, 0.72f);
    const float3 c = albedo * (0.35f * ao * sky + ndl * shadow * light) + 0.25f * spec * shadow * light;
    colour[i] = (float4)(sqrt(clamp(c, 0.0f, 1.0f)), 1.0f); /* display gamma ~2 */
}
