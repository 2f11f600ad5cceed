// A closed triangle mesh converted on the device to a signed distance grid (kernels/mesh_sdf.cl):
// the exact distance to the mesh at every grid point, found through a BVH over the triangles (not
// brute force), signed by angle-weighted pseudo-normals. The grid is what a mesh edit samples.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "cl/device.h"
#include "cl/program.h"
#include "measure/scheduler.h"
#include "scene/mesh.h"
#include "sdf_types.h"

namespace sdfbrick::construct {

// Grid point (i, j, k) sits at origin + (i, j, k) * cell; i runs fastest in values.
struct MeshGrid {
    glm::dvec3 origin{0.0};
    double cell = 0.0;
    glm::ivec3 dims{0};
    std::vector<float> values;

    float at(int i, int j, int k) const {
        return values[static_cast<std::size_t>(i) + static_cast<std::size_t>(dims.x) *
                                                        (static_cast<std::size_t>(j) + static_cast<std::size_t>(dims.y) * k)];
    }
};

// The grid over a mesh: cells of side `cell` covering its bounds grown by `padding` cells per side.
struct MeshGridSpec {
    double cell = 0.0;
    int padding = 2;
};
// The cell that puts `resolution` cells along the longest side of the mesh's bounds.
double cell_for_resolution(const TriangleMesh& mesh, int resolution);

// The mesh's triangles as the kernel reads them: the BVH (leaves ~triangle), 9 corner floats and
// 21 pseudo-normal floats per triangle (face, edges ab bc ca, vertices a b c). Built on the host in
// double precision; the tree splits at the median by a total order (centroid, index), so it is the
// same everywhere, and its depth stays below the kernel's stack.
struct MeshBvh {
    std::vector<SdfBvhNode> nodes;
    std::vector<float> corners;
    std::vector<float> normals;
    int depth = 0;
};
MeshBvh build_mesh_bvh(const TriangleMesh& mesh);

// A sparse grid over a GridFrame (kernels/sdf_types.h, SdfMeshGrid with tiles): the cells in tiles of
// kMeshTile^3, exact values (kMeshTilePoints a tile, the same bits as the dense grid's points) in
// every tile that comes within `band` of the surface; the others are bounded from the exact
// distances at every tile's corners and centre. `values`: the tile table (uint bits: the offset of
// the tile's points in `values`, or SDF_MESH_NO_TILE), the corners ((tiles + 1)^3), the centres
// (tiles^3), the tiles' points.
inline constexpr int kMeshTile = 8;
inline constexpr std::size_t kMeshTilePoints = 9 * 9 * 9;
// The tiles per axis of a sparse grid over `frame`: ceil(cells / kMeshTile).
inline glm::ivec3 sparse_tiles(const GridFrame& frame) { return (frame.dims - 1 + kMeshTile - 1) / kMeshTile; }
struct SparseMeshGrid {
    glm::ivec3 tiles{0};  // per axis: sparse_tiles(frame)
    std::size_t active = 0;
    std::vector<float> values;
    std::size_t table_size() const { return static_cast<std::size_t>(tiles.x) * tiles.y * tiles.z; }
};

class MeshGridBuilder {
public:
    explicit MeshGridBuilder(ocl::Device& device);

    // Throws InputError when the grid or the mesh does not fit the device (naming what and how much),
    // SettingError("cell") for a cell that is not positive and finite.
    MeshGrid build(const TriangleMesh& mesh, const MeshGridSpec& spec, measure::Scheduler& scheduler);
    // The grid at the points of `frame` (scene/mesh.h, grid_frame).
    MeshGrid build(const TriangleMesh& mesh, const GridFrame& frame, measure::Scheduler& scheduler);
    // The sparse grid over `frame`, exact within `band` (mesh units) of the surface: three launches
    // (the tile corners, the tile centres, then the points of the tiles kept), recorded as stage "mesh".
    SparseMeshGrid build_sparse(const TriangleMesh& mesh, const GridFrame& frame, double band,
                                measure::Scheduler& scheduler);

private:
    struct Triangles;
    Triangles upload(const TriangleMesh& mesh) const;
    void check_fits(std::size_t bytes, const char* what) const;
    MeshGrid build(const Triangles& tris, const GridFrame& frame, measure::Scheduler& scheduler);

    ocl::Device& device_;
    ocl::Program program_;
    ocl::Kernel kernel_;
    ocl::Kernel tiles_kernel_;
};

}  // namespace sdfbrick::construct
