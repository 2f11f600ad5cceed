// Triangle meshes from files (OBJ, PLY and the other formats Assimp reads): positions welded by
// exact value, every mesh of the file with its node transforms baked, and the checks a distance
// field needs (finite coordinates, a size limit, closedness); closed meshes generated for tests and
// benchmarks, and OBJ / PLY writers.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "scene/scene.h"

namespace sdfbrick {

// Most triangles one mesh may hold.
inline constexpr std::size_t kMaxMeshTriangles = std::size_t{1} << 24;
// Longest a mesh file may take to read, by default.
inline constexpr int kMeshReadSeconds = 60;

struct TriangleMesh {
    std::vector<glm::dvec3> vertices;
    std::vector<std::array<std::uint32_t, 3>> triangles;  // counter-clockwise seen from outside

    Aabb bounds() const;
};

// Reads a mesh file (through Assimp, in a child process: a reader that crashes, aborts or takes more
// than `seconds` on a malformed file is a refusal, not the program's end). Throws InputError
// naming the file for a missing, unreadable, empty or malformed file, a non-finite vertex (naming
// it), or more than kMaxMeshTriangles triangles. Polygons become triangle fans; degenerate triangles
// (two equal corners) are dropped.
TriangleMesh load_mesh(const std::filesystem::path& path, int seconds = kMeshReadSeconds);

struct MeshTopology {
    std::size_t edges = 0;
    std::size_t open_edges = 0;         // used by one triangle
    std::size_t non_manifold_edges = 0; // used by more than two triangles
    bool closed() const { return open_edges == 0 && non_manifold_edges == 0; }
};
MeshTopology topology(const TriangleMesh& mesh);

// ---- the mesh edit ----

// The grid a mesh edit samples: points origin + (i, j, k) * cell (i fastest) covering the mesh's
// bounds grown by `padding` cells on every side; origin and cell are the floats the kernels read.
// Compute a frame once and pass it on (MeshGridBuilder::build): the points per axis come from the
// cell before rounding, so a frame made again from the rounded cell may differ by one.
struct GridFrame {
    glm::dvec3 origin{0.0};
    double cell = 0.0;
    glm::ivec3 dims{0};  // points per axis
    glm::dvec3 hi() const { return origin + glm::dvec3(dims - 1) * cell; }
    std::size_t points() const {
        return static_cast<std::size_t>(dims.x) * static_cast<std::size_t>(dims.y) * static_cast<std::size_t>(dims.z);
    }
};
inline constexpr int kMaxGridCells = 4096;  // along one axis
// Throws InputError for more than kMaxGridCells cells along an axis, SettingError("cell") for a cell
// that is not positive and finite.
GridFrame grid_frame(const TriangleMesh& mesh, double cell, int padding);

inline constexpr int kDefaultMeshResolution = 64;  // cells along the longest side of the mesh's bounds
inline constexpr int kMaxMeshResolution = 1024;
inline constexpr int kMeshPadding = 2;              // cells around the mesh's bounds
inline constexpr int kMaxSparseMeshResolution = 2048;
inline constexpr double kMeshBandCells = 4.0;        // a sparse grid is exact at least this far from the surface

// A mesh as a scene uses it: its triangles, and the grid its edits sample. Shared by every edit (and
// every copy of the scene) that names the same file at the same resolution. A level set read from a
// VDB file (scene/level_set.h) is a source without triangles whose values are the file's.
struct MeshSource {
    std::string file;  // as the scene names it
    std::string grid;  // a level set's grid name in the file
    TriangleMesh mesh;  // empty for a level set
    bool level_set() const { return mesh.triangles.empty(); }
    int resolution = kDefaultMeshResolution;
    GridFrame frame;
    // Sparse (the default for meshes): only tiles of cells near the surface hold values, exact within
    // `band` of it (construct/mesh_grid.h, SparseMeshGrid); dense: every point of the frame.
    bool sparse = false;
    double band = 0.0;  // mesh units: kMeshBandCells cells, or more where a smooth blend reaches further
    // The grid's values (dense: frame.points() floats; sparse: SparseMeshGrid::values), converted on the
    // device on first use (construct/mesh_pool.h) and kept for every later build of the loaded scene.
    std::vector<float> values;
    std::mutex mutex;  // guards values
    // One line when the file's winding was turned to face outward (scene/mesh_orient.h), else empty.
    std::string warning;
};

// A scene's mesh: oriented (scene/mesh_orient.h: consistently, outward, cavities inward), with the
// grid frame of `resolution` cells along the longest side. Throws InputError naming `file` when the
// mesh is not closed (open or non-manifold edges: the inside, and so the sign of the distance, is not
// defined), cannot be oriented, encloses no volume, or for too large a resolution.
std::shared_ptr<MeshSource> make_mesh_source(TriangleMesh mesh, std::string file, int resolution, bool sparse = true);
// A mesh edit of the scene's mesh number `index`: params = the half extents of a box about the
// mesh's local origin that holds its grid, and the index (kernels/sdf_types.h, SDF_PRIM_MESH).
Edit make_mesh_edit(std::shared_ptr<MeshSource> source, std::uint32_t index);

// ---- generated meshes (tests, benchmarks) and writers ----

// A sphere of radius r about the origin: an icosahedron subdivided `levels` times, vertices on the
// sphere (20 * 4^levels triangles).
TriangleMesh icosphere(double r, int levels);
// A torus about +y (major radius R, minor r): `u` segments around the axis, `v` around the tube
// (2 u v triangles).
TriangleMesh torus_mesh(double R, double r, int u, int v);
// A box of half extents (a, a, h) with a square hole of half width b < a through it along z (genus 1).
TriangleMesh box_with_hole(double a, double b, double h);

// Throw InputError naming the file when it cannot be written; the file appears whole or not at all.
void write_obj(const TriangleMesh& mesh, const std::filesystem::path& path);
void write_ply(const TriangleMesh& mesh, const std::filesystem::path& path);  // ASCII PLY

}  // namespace sdfbrick
