/* edit_bounds.cl: per edit, the axis-aligned boxes (geometry frame) of its solid {value <= 0} and of
 * its influence region {value <= blend}, where value = primitive(local(p)) * scale * inv_lipschitz
 * (sdf_edit.h). host/construct/edit_deps.cpp drives it; host/scene/scene.cpp holds the same formulas
 * in double precision (local_level_bounds, Transform::apply), and tests/construct/test_edit_deps.cpp
 * checks that every box here contains the host's.
 *
 * Conservative: each box is grown by EDIT_BOUNDS_PAD of the magnitude of its inputs (|translation|
 * plus the scaled local half extents summed over the axes) on every side. That covers the rounding of
 * the parameters to float (2^-24 relative), of the quaternion (not exactly unit in float) and of the
 * few operations below, with a wide margin; summing the three local half extents matters for long
 * thin primitives, where a rotation error of a long axis lands on a short world axis.
 *
 * An unknown primitive evaluates to SDF_FAR everywhere (no solid, no influence): its boxes are empty
 * (lo = +inf, hi = -inf). Inputs whose size or position overflows float (or is NaN) get the whole
 * space, [-inf, +inf] on every axis; negative sizes (invalid parameters) give an empty box. */
#include "sdf_types.h"

#define EDIT_BOUNDS_PAD 1.0e-5f

/* Half extents, in the primitive's frame, of the box holding {x : primitive(x) <= c}, c >= 0. */
inline float3 edit_local_half_extents(uint kind, const float p[4], float c) {
    switch (kind) {
        case SDF_PRIM_SPHERE: return (float3)(p[0] + c);
        case SDF_PRIM_BOX:
        case SDF_PRIM_ROUND_BOX: return (float3)(p[0] + c, p[1] + c, p[2] + c);
        case SDF_PRIM_TORUS: return (float3)(p[0] + p[1] + c, p[1] + c, p[0] + p[1] + c);
        case SDF_PRIM_CAPSULE: return (float3)(p[1] + c, p[0] + p[1] + c, p[1] + c);
        case SDF_PRIM_CYLINDER: return (float3)(p[1] + c, p[0] + c, p[1] + c);
        case SDF_PRIM_CONE: {
            const float r = fmax(p[1], p[2]);
            return (float3)(r + c, p[0] + c, r + c);
        }
        case SDF_PRIM_ELLIPSOID: {
            /* (|x/r| - 1) min(r) <= c  <=>  x in the ellipsoid of semi-axes r (1 + c / min(r)). */
            const float m = fmin(fmin(p[0], p[1]), p[2]);
            const float g = 1.0f + c / m;
            return (float3)(p[0] * g, p[1] * g, p[2] * g);
        }
        case SDF_PRIM_MENGER: return (float3)(p[0] + c); /* the sponge lies inside its cube */
        case SDF_PRIM_MESH:
            /* p[0..2] holds the grid box; outside that box the value is the distance to it plus a
             * boundary value >= 0 (a distance at least the grid's padding). */
            return (float3)(p[0] + c, p[1] + c, p[2] + c);
        default: return (float3)(-1.0f);                 /* marks "empty" */
    }
}

/* Box of {p : value(p) <= c} in the geometry frame. */
inline SdfBounds edit_level_box(const SdfEdit* e, float c) {
    SdfBounds b;
    const float s = e->transform.scale;
    /* value <= c  <=>  primitive(local) <= c L / s */
    const float local_c = fmax(c, 0.0f) / (s * e->inv_lipschitz);
    const float3 h = edit_local_half_extents(e->primitive, e->params, local_c);
    if (e->primitive >= SDF_PRIM_COUNT) {
        for (int a = 0; a < 3; ++a) {
            b.lo[a] = INFINITY;
            b.hi[a] = -INFINITY;
        }
        return b;
    }
    const float hs[3] = {h.x * s, h.y * s, h.z * s};
    /* Rotation matrix of the unit quaternion (x, y, z, w): local -> geometry frame. */
    const float x = e->transform.rotation[0], y = e->transform.rotation[1];
    const float z = e->transform.rotation[2], w = e->transform.rotation[3];
    const float xx = x * x, yy = y * y, zz = z * z;
    const float xy = x * y, xz = x * z, yz = y * z, wx = w * x, wy = w * y, wz = w * z;
    const float r[3][3] = {{1.0f - 2.0f * (yy + zz), 2.0f * (xy - wz), 2.0f * (xz + wy)},
                           {2.0f * (xy + wz), 1.0f - 2.0f * (xx + zz), 2.0f * (yz - wx)},
                           {2.0f * (xz - wy), 2.0f * (yz + wx), 1.0f - 2.0f * (xx + yy)}};
    const float size = hs[0] + hs[1] + hs[2];
    for (int a = 0; a < 3; ++a) {
        const float half_w = fabs(r[a][0]) * hs[0] + fabs(r[a][1]) * hs[1] + fabs(r[a][2]) * hs[2];
        const float t = e->transform.translation[a];
        const float grown = half_w + EDIT_BOUNDS_PAD * (fabs(t) + size);
        b.lo[a] = t - grown;
        b.hi[a] = t + grown;
    }
    int finite = 1;
    for (int a = 0; a < 3; ++a) finite &= fabs(b.lo[a]) <= FLT_MAX && fabs(b.hi[a]) <= FLT_MAX;
    if (!finite) {
        /* Overflow, inf or NaN in the inputs: the whole space (conservative; never NaN). */
        for (int a = 0; a < 3; ++a) {
            b.lo[a] = -INFINITY;
            b.hi[a] = INFINITY;
        }
    }
    return b;
}

__kernel void edit_bounds(__global const SdfEdit* edits, uint n, __global SdfBounds* bounds,
                          __global SdfBounds* influence) {
    const uint i = get_global_id(0);
    if (i >= n) return;
    const SdfEdit e = edits[i];
    bounds[i] = edit_level_box(&e, 0.0f);
    influence[i] = edit_level_box(&e, e.blend);
}
