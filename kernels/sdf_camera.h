/* sdf_camera.h: primary rays of the pinhole camera (SdfCamera in sdf_types.h), shared by the brick
 * tracer and the device reference tracer so that both see exactly the same rays. */
#ifndef SDFBRICK_SDF_CAMERA_H
#define SDFBRICK_SDF_CAMERA_H

#include "sdf_types.h"

inline float3 sdf_camera_eye(const SdfCamera* c) { return (float3)(c->eye[0], c->eye[1], c->eye[2]); }

/* Unit direction of the ray through the centre of pixel (x, y). */
inline float3 sdf_camera_dir(const SdfCamera* c, uint x, uint y) {
    const float u = (2.0f * ((float)x + 0.5f)) / (float)c->width - 1.0f;
    const float v = 1.0f - (2.0f * ((float)y + 0.5f)) / (float)c->height;
    const float3 d = (float3)(c->forward[0] + u * c->right[0] + v * c->up[0],
                              c->forward[1] + u * c->right[1] + v * c->up[1],
                              c->forward[2] + u * c->right[2] + v * c->up[2]);
    const float len = sqrt(d.x * d.x + d.y * d.y + d.z * d.z);
    return d / len;
}

#endif /* SDFBRICK_SDF_CAMERA_H */
