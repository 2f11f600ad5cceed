/* sdf_types.h: the plain structs shared by the host (C++) and the kernels (OpenCL C 1.2).
 *
 * Rules that keep the two sides identical (tests/kernels/test_layout.cpp checks sizes and every offset on
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
 *   MESH       a closed triangle mesh         params = {hx, hy, hz, mesh index m}
 *              sampled from its distance grid (SdfMeshGrid m of the mesh pool); h = half extents of a
 *              box about the local origin that holds the grid (the edit's bounds), m an exact integer
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
#define SDF_PRIM_MESH 9u
#define SDF_PRIM_COUNT 10u

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

/* An edit in the form the folds read (sdf_edit.h: sdf_prepare writes it, kernel side): translation,
 * 1 / scale, rotation, parameters, scale / L, blend k, 0.25 / k (0 when hard), and the primitive |
 * op << 8 | a rotation flag. Same size as SdfEdit. */
typedef struct SdfPrepared {
    sdf_f32 t[3];
    sdf_f32 inv_scale;
    sdf_f32 q[4];
    sdf_f32 prm[4];
    sdf_f32 out_scale;
    sdf_f32 blend;
    sdf_f32 blend_q;
    sdf_u32 kind;
} SdfPrepared;

/* The signed distance grid of a mesh edit. Every kernel that evaluates edits takes the mesh pool, one
 * float array: the headers of the scene's meshes first (SdfMeshGrid, 12 floats each, indexed by the
 * mesh index of SdfEdit.params[3]), then their values. Grid point (i, j, k) lies at
 * origin + (i, j, k) * cell in the mesh's local frame.
 * Dense (tiles == 0): its value at pool[offset + i + dims[0] (j + dims[1] k)].
 * Sparse (tiles != 0): the cells are grouped in tiles of 8^3 (T = ceil((dims - 1) / 8) per axis).
 * pool[tiles + tx + Tx (ty + Ty tz)] holds, as uint bits, the pool offset of the tile's 9^3 points
 * (8 t + l, l in 0..8, i fastest), or SDF_MESH_NO_TILE for a tile far from the surface. Such a tile
 * reads the exact distances at its 8 corners (points 8 t, (T + 1) per axis, at pool[coarse + tx +
 * (Tx + 1) (ty + (Ty + 1) tz)]) and at its centre (point 8 t + 4, at pool[centres + tx + Tx (ty + Ty tz)])
 * and gives the largest of |d_q| - |p - q| over those 9 points q, signed as the centre: a lower bound
 * of the distance's magnitude, 1-Lipschitz within the tile.
 * A scene without meshes passes a pool of one unread float. */
#define SDF_MESH_NO_TILE 0xffffffffu
typedef struct SdfMeshGrid {
    sdf_f32 origin[3];
    sdf_f32 cell;
    sdf_f32 inv_cell;
    sdf_u32 dims[3];   /* points per axis, each >= 2 */
    sdf_u32 offset;    /* dense: first value, in floats from the pool's start */
    sdf_u32 tiles;     /* sparse: the tile table's first entry; 0 for a dense grid */
    sdf_u32 coarse;    /* sparse: the tile corners' first value */
    sdf_u32 centres;   /* sparse: the tile centres' first value */
} SdfMeshGrid;

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

/* A pinhole camera: the ray through pixel (x, y) (x right, y down, centres at +0.5) has direction
 * normalize(forward + u * right + v * up), u = 2 (x + 0.5) / width - 1, v = 1 - 2 (y + 0.5) / height;
 * right and up are pre-scaled by tan(fov / 2) (right also by width / height). kernels/sdf_camera.h
 * evaluates it; host/scene/to_device.h (make_camera) fills it from the scene's camera. */
typedef struct SdfCamera {
    sdf_f32 eye[3];
    sdf_f32 forward[3];
    sdf_f32 right[3];
    sdf_f32 up[3];
    sdf_u32 width;
    sdf_u32 height;
} SdfCamera;

/* A binary BVH node that holds both children's boxes (one node fetch tests both).
 * child[i] >= 0: internal node index; child[i] < 0: leaf number ~child[i] (a brick, an instance or an
 * edit, depending on the tree). Every node has two children (a tree of one leaf repeats it), except
 * in trees that are only searched by point containment, where a missing child has an empty box. */
typedef struct SdfBvhNode {
    sdf_f32 lo0[3];
    sdf_f32 hi0[3];
    sdf_f32 lo1[3];
    sdf_f32 hi1[3];
    sdf_i32 child[2];
    sdf_u32 pad[2];
} SdfBvhNode;

/* A node of the 4-wide BVH that the brick tracer walks, made from the binary tree by bvh_widen
 * (kernels/bvh_build.cl): each binary node at even depth gives one wide node, whose slots are its
 * children, each internal child replaced by its own two children. Boxes are stored by axis (slot k:
 * lo_x[k] ..), so one slab test covers the four slots. child[k] >= 0: wide node child[k];
 * child[k] < 0 and != SDF_WIDE_EMPTY: leaf ~child[k]; SDF_WIDE_EMPTY: an unused slot. */
typedef struct SdfBvhWideNode {
    sdf_f32 lo_x[4];
    sdf_f32 lo_y[4];
    sdf_f32 lo_z[4];
    sdf_f32 hi_x[4];
    sdf_f32 hi_y[4];
    sdf_f32 hi_z[4];
    sdf_i32 child[4];
    sdf_u32 pad[4];
} SdfBvhWideNode;

#define SDF_WIDE_EMPTY (-2147483647 - 1)

/* One object instance: world -> geometry frame is p_g = M (p_w - translation), M = R^T / scale given
 * by its rows; a world direction maps by M alone, so a ray parameter t is the same in both frames.
 * A geometry-frame normal n maps to the world as normalize(M^T n). */
typedef struct SdfInstance {
    sdf_f32 world_to_geometry[9];
    sdf_f32 translation[3];
    sdf_f32 scale;
    sdf_u32 geometry; /* index into the scene's geometries */
    sdf_u32 pad[2];
} SdfInstance;

/* One geometry's bricks as the brick tracer reads them (all geometries share the combined node, brick
 * and pool arrays). The samples of brick b of this geometry are pool[(brick_offset + b) * S^3 ...],
 * sample (i, j, k) at brick_min + (ijk - apron + 0.5) * voxel; value * dequant = distance. */
typedef struct SdfBrickGeometry {
    sdf_f32 voxel;
    sdf_f32 inv_voxel;
    sdf_f32 dequant;
    sdf_u32 root;         /* root node in the combined node array, SDF_NO_NODE when there is no brick */
    sdf_u32 brick_offset; /* first brick of this geometry in the combined arrays */
    sdf_u32 pad[3];
} SdfBrickGeometry;

/* Sphere tracing's hit test: the field at or below this many voxels is a hit. Every tracing method
 * needs the trilinear field at or below it for a hit (the others at or below 0), so a brick whose
 * samples all lie above SDF_HIT_MARGIN times it (stored units; the margin covers rounding) holds no
 * hit, and the BVH leaves it out. */
#define SDF_SPHERE_EPS 0.01f
#define SDF_HIT_MARGIN 2.0f

/* Shaded mode (kernels/shade.cl): Blinn-Phong lit by a directional light, with soft shadows and ambient
 * occlusion from secondary rays through the same BVH. */
typedef struct SdfShading {
    sdf_f32 light_dir[3];   /* unit, towards the light */
    sdf_f32 light_color[3]; /* colour * intensity */
    sdf_f32 shadow_spread;  /* tangent of the light's angular radius: the penumbra's width */
    sdf_f32 ao_radius;      /* occluders within this world distance darken the ambient term */
    sdf_f32 ray_offset;     /* secondary rays start this far off the surface, along the normal */
    sdf_u32 shadow_rays;
    sdf_u32 ao_rays;
    sdf_u32 pad;
} SdfShading;

/* Per-pixel output of the tracers (two arrays of width * height):
 *   hit: float4 (nx, ny, nz, depth): world unit normal and the distance along the unit ray from the
 *        eye; depth < 0 (SDF_MISS) on a miss, where the normal is 0.
 *   aux: uint2, meaning per tracer (brick tracer: brick id and step counts; reference: iterations and
 *        flags). */
#define SDF_MISS (-1.0f)
#define SDF_NO_NODE 0xFFFFFFFFu
#define SDF_NO_BRICK 0xFFFFFFFFu
#define SDF_REF_UNCONVERGED 1u /* reference aux.y flag: the iteration limit was reached */
#define SDF_TRACE_CAPPED 0x80000000u /* brick tracer aux.y flag: a loop bound ended a brick's search */

#endif /* SDFBRICK_SDF_TYPES_H */
