/* sdf_types.h: the plain structs shared by the host (C++) and the kernels (OpenCL C 1.2).
 *
 * Rules that keep the two sides identical (tests/test_layout.cpp checks sizes and every offset on
 * the host and on the device):
 *   - only 4-byte scalars (float, uint, int) and arrays of them; no vector types (float3 is 16
 *     bytes in OpenCL C and 12 in C++), no pointers, no bool, no size_t;
 *   - every struct is a multiple of 4 bytes with no implicit padding.
 * Enumerations are plain #defines so that both languages read the same values.
 */
#ifndef SDFBRICK_SDF_TYPES_H
#define SDFBRICK_SDF_TYPES_H

#ifdef __OPENCL_C_VERSION__
typedef uint sdf_u32;
typedef int sdf_i32;
typedef float sdf_f32;
#else
#include <cstdint>
typedef std::uint32_t sdf_u32;
typedef std::int32_t sdf_i32;
typedef float sdf_f32;
#endif

/* Primitive kinds (SdfEdit.primitive). Parameters in SdfEdit.params, in the primitive's local frame:
 *   SPHERE     radius                         params = {r, -, -, -}
 *   BOX        half extents                   params = {bx, by, bz, -}
 *   ROUND_BOX  outer half extents, rounding   params = {bx, by, bz, r},  r <= min(b)
 *   TORUS      in the xz plane, around +y     params = {R (major), r (minor), -, -}
 *   CAPSULE    segment along y                params = {h (half length of the segment), r, -, -}
 *   CYLINDER   capped, along y                params = {h (half height), r, -, -}
 *   CONE       capped, along y, bottom at -h  params = {h (half height), r_bottom, r_top, -}
 *   ELLIPSOID  semi-axes                      params = {rx, ry, rz, -}     (a 1-Lipschitz bound)
 *   MENGER     Menger sponge in a cube        params = {half size s, iterations n (1..6), -, -}
 */
#define SDF_PRIM_SPHERE 0u
#define SDF_PRIM_BOX 1u
#define SDF_PRIM_ROUND_BOX 2u
#define SDF_PRIM_TORUS 3u
#define SDF_PRIM_CAPSULE 4u
#define SDF_PRIM_CYLINDER 5u
#define SDF_PRIM_CONE 6u
#define SDF_PRIM_ELLIPSOID 7u
#define SDF_PRIM_MENGER 8u
#define SDF_PRIM_COUNT 9u

/* Combine rules (SdfEdit.op). An edit is smooth iff SdfEdit.blend > 0. */
#define SDF_OP_ADD 0u
#define SDF_OP_SUBTRACT 1u
#define SDF_OP_INTERSECT 2u
#define SDF_OP_COUNT 3u

/* Value of an empty field (no edit yet): finite so that no inf - inf = NaN can arise. */
#define SDF_FAR 1.0e20f

/* Most edits one geometry may hold. */
#define SDF_MAX_EDITS 65536u

/* Rigid transform with uniform scale: x_parent = rotate(rotation, x_local * scale) + translation.
 * rotation is a unit quaternion (x, y, z, w). */
typedef struct SdfTransform {
    sdf_f32 translation[3];
    sdf_f32 scale;
    sdf_f32 rotation[4];
} SdfTransform;

/* One edit: a primitive placed in the geometry's frame, combined with the field built so far.
 * Its value at p is  primitive(local(p)) * scale * inv_lipschitz. */
typedef struct SdfEdit {
    SdfTransform transform;
    sdf_f32 params[4];
    sdf_f32 blend;          /* smooth blend radius k in geometry units; 0 = hard */
    sdf_f32 inv_lipschitz;  /* 1 / L, L >= 1 the primitive's Lipschitz bound */
    sdf_u32 primitive;      /* SDF_PRIM_* */
    sdf_u32 op;             /* SDF_OP_* */
} SdfEdit;

/* Axis-aligned bounds. */
typedef struct SdfBounds {
    sdf_f32 lo[3];
    sdf_f32 hi[3];
} SdfBounds;

/* One brick of the sparse hierarchy (construction fills these).
 * coord is the brick's integer position on its level's lattice (in bricks from the domain origin);
 * its edits are edit_indices[edit_offset .. edit_offset + edit_count). child_mask is the 64-bit set of
 * kept children (bit = Morton index inside the parent; branching 2 uses the low 8 bits). */
typedef struct SdfBrick {
    sdf_i32 coord[3];
    sdf_u32 level;
    sdf_u32 edit_offset;
    sdf_u32 edit_count;
    sdf_u32 child_mask[2];
} SdfBrick;

#endif /* SDFBRICK_SDF_TYPES_H */
