// Triangle meshes from files (OBJ, PLY and the other formats Assimp reads): positions welded by
// exact value, every mesh of the file with its node transforms baked, and the checks a distance
// field needs (finite coordinates, a size limit, closedness); closed meshes generated for tests and
// benchmarks, and OBJ / PLY writers.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <vector>

#include <glm/glm.hpp>

#include "scene/scene.h"

namespace sdfbrick {

// Most triangles one mesh may hold.
inline constexpr std::size_t kMaxMeshTriangles = std::size_t{1} << 24;

struct TriangleMesh {
    std::vector<glm::dvec3> vertices;
    std::vector<std::array<std::uint32_t, 3>> triangles;  // counter-clockwise seen from outside

    Aabb bounds() const;
};

// Reads a mesh file. Throws InputError naming the file for a missing, unreadable, empty or malformed
// file, a non-finite vertex (naming it), or more than kMaxMeshTriangles triangles. Degenerate
// triangles (two equal corners) are dropped.
TriangleMesh load_mesh(const std::filesystem::path& path);

struct MeshTopology {
    std::size_t edges = 0;
    std::size_t open_edges = 0;         // used by one triangle
    std::size_t non_manifold_edges = 0; // used by more than two triangles
    bool closed() const { return open_edges == 0 && non_manifold_edges == 0; }
};
MeshTopology topology(const TriangleMesh& mesh);

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
