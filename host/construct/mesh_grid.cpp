#include "construct/mesh_grid.h"

#include <algorithm>
#include <cstring>
#include <cmath>
#include <map>
#include <numeric>
#include <stdexcept>

#include <fmt/format.h>

#include "cl/buffer.h"
#include "cl/launch.h"
#include "core/errors.h"

namespace sdfbrick::construct {

namespace {

constexpr int kKernelStack = 64;  // MESH_STACK of mesh_sdf.cl

glm::dvec3 corner(const TriangleMesh& m, std::size_t t, int c) { return m.vertices[m.triangles[t][c]]; }

// Interior angle of triangle t at corner c.
double angle_at(const TriangleMesh& m, std::size_t t, int c) {
    const glm::dvec3 a = corner(m, t, c), b = corner(m, t, (c + 1) % 3), d = corner(m, t, (c + 2) % 3);
    const glm::dvec3 u = glm::normalize(b - a), v = glm::normalize(d - a);
    return std::acos(std::clamp(glm::dot(u, v), -1.0, 1.0));
}

// Pseudo-normals: the face normals; per edge the sum of its faces' normals; per vertex the sum of
// its faces' normals weighted by the angle at the vertex. Unnormalised sums point the same way.
void pseudo_normals(const TriangleMesh& m, MeshBvh& out) {
    const std::size_t n = m.triangles.size();
    std::vector<glm::dvec3> face(n), vertex(m.vertices.size(), glm::dvec3(0.0));
    std::map<std::pair<std::uint32_t, std::uint32_t>, glm::dvec3> edge;
    for (std::size_t t = 0; t < n; ++t) {
        face[t] = glm::normalize(glm::cross(corner(m, t, 1) - corner(m, t, 0), corner(m, t, 2) - corner(m, t, 0)));
        for (int c = 0; c < 3; ++c) {
            vertex[m.triangles[t][c]] += angle_at(m, t, c) * face[t];
            const std::uint32_t a = m.triangles[t][c], b = m.triangles[t][(c + 1) % 3];
            edge[{std::min(a, b), std::max(a, b)}] += face[t];
        }
    }
    out.normals.resize(21 * n);
    for (std::size_t t = 0; t < n; ++t) {
        glm::dvec3 rows[7];
        rows[0] = face[t];
        for (int c = 0; c < 3; ++c) {
            const std::uint32_t a = m.triangles[t][c], b = m.triangles[t][(c + 1) % 3];
            rows[1 + c] = edge[{std::min(a, b), std::max(a, b)}];
            rows[4 + c] = vertex[m.triangles[t][c]];
        }
        for (int r = 0; r < 7; ++r)
            for (int x = 0; x < 3; ++x) out.normals[21 * t + 3 * r + x] = static_cast<float>(rows[r][x]);
    }
}

struct Builder {
    const TriangleMesh& mesh;
    std::vector<Aabb> boxes;          // per triangle, float-rounded outward
    std::vector<glm::dvec3> centres;  // per triangle
    std::vector<SdfBvhNode>& nodes;
    int depth = 0;

    Aabb box_of(std::span<const std::uint32_t> tris) const {
        Aabb b;
        for (std::uint32_t t : tris) b.grow(boxes[t]);
        return b;
    }

    // The subtree over tris (non-empty) as child reference: ~triangle for one, else a node index.
    int build(std::span<std::uint32_t> tris, int level) {
        depth = std::max(depth, level);
        if (tris.size() == 1) return ~static_cast<int>(tris[0]);
        Aabb c;
        for (std::uint32_t t : tris) c.grow(centres[t]);
        const glm::dvec3 e = c.extent();
        const int axis = e.x >= e.y && e.x >= e.z ? 0 : e.y >= e.z ? 1 : 2;
        const std::size_t half = tris.size() / 2;
        std::nth_element(tris.begin(), tris.begin() + static_cast<std::ptrdiff_t>(half), tris.end(),
                         [&](std::uint32_t a, std::uint32_t b) {
                             return centres[a][axis] < centres[b][axis] || (centres[a][axis] == centres[b][axis] && a < b);
                         });
        const int index = static_cast<int>(nodes.size());
        nodes.emplace_back();
        const std::span<std::uint32_t> halves[2] = {tris.first(half), tris.subspan(half)};
        for (int side = 0; side < 2; ++side) {
            const int child = build(halves[side], level + 1);
            const Aabb b = box_of(halves[side]);
            SdfBvhNode& node = nodes[static_cast<std::size_t>(index)];
            float* lo = side == 0 ? node.lo0 : node.lo1;
            float* hi = side == 0 ? node.hi0 : node.hi1;
            for (int x = 0; x < 3; ++x) {
                lo[x] = static_cast<float>(b.lo[x]);
                hi[x] = static_cast<float>(b.hi[x]);
            }
            node.child[side] = child;
        }
        return index;
    }
};

}  // namespace

double cell_for_resolution(const TriangleMesh& mesh, int resolution) {
    const glm::dvec3 e = mesh.bounds().extent();
    return std::max({e.x, e.y, e.z}) / resolution;
}

MeshBvh build_mesh_bvh(const TriangleMesh& mesh) {
    MeshBvh out;
    const std::size_t n = mesh.triangles.size();
    if (n == 0) throw std::invalid_argument("build_mesh_bvh: a mesh without triangles");
    Builder b{mesh, std::vector<Aabb>(n), std::vector<glm::dvec3>(n), out.nodes};
    out.corners.resize(9 * n);
    for (std::size_t t = 0; t < n; ++t) {
        for (int c = 0; c < 3; ++c) {
            const glm::vec3 v(corner(mesh, t, c));  // the floats the kernel reads; boxes hold them exactly
            b.boxes[t].grow(glm::dvec3(v));
            for (int x = 0; x < 3; ++x) out.corners[9 * t + 3 * c + x] = v[x];
        }
        b.centres[t] = b.boxes[t].centre();
    }
    std::vector<std::uint32_t> order(n);
    std::iota(order.begin(), order.end(), 0u);
    if (n == 1) {  // a root node whose two children are the one triangle
        out.nodes.emplace_back();
        SdfBvhNode& root = out.nodes[0];
        for (int x = 0; x < 3; ++x) {
            root.lo0[x] = root.lo1[x] = static_cast<float>(b.boxes[0].lo[x]);
            root.hi0[x] = root.hi1[x] = static_cast<float>(b.boxes[0].hi[x]);
        }
        root.child[0] = root.child[1] = ~0;
    } else {
        b.build(order, 0);
    }
    out.depth = b.depth;
    pseudo_normals(mesh, out);
    return out;
}

MeshGridBuilder::MeshGridBuilder(ocl::Device& device)
    : device_(device),
      program_(ocl::build_program(device, "mesh_sdf.cl")),
      kernel_(ocl::make_kernel(program_, "mesh_sdf")),
      tiles_kernel_(ocl::make_kernel(program_, "mesh_sdf_tiles")) {}

MeshGrid MeshGridBuilder::build(const TriangleMesh& mesh, const MeshGridSpec& spec, measure::Scheduler& scheduler) {
    return build(mesh, grid_frame(mesh, spec.cell, spec.padding), scheduler);
}

// The mesh's triangle tree, corners and pseudo-normals on the device.
struct MeshGridBuilder::Triangles {
    ocl::Buffer<SdfBvhNode> nodes;
    ocl::Buffer<float> corners, normals;
};

MeshGridBuilder::Triangles MeshGridBuilder::upload(const TriangleMesh& mesh) const {
    const MeshBvh bvh = build_mesh_bvh(mesh);
    if (bvh.depth >= kKernelStack)
        throw InputError(fmt::format("the mesh's triangle tree is {} levels deep; the kernel holds {}", bvh.depth, kKernelStack));
    const auto copy = [&](auto data, const char* what) {
        using T = typename decltype(data)::value_type;
        check_fits(data.size_bytes(), what);
        return ocl::Buffer<T>(device_, data, CL_MEM_READ_ONLY);
    };
    return {copy(std::span<const SdfBvhNode>(bvh.nodes), "the triangle tree nodes"),
            copy(std::span<const float>(bvh.corners), "the triangle corners"),
            copy(std::span<const float>(bvh.normals), "the pseudo-normals")};
}

void MeshGridBuilder::check_fits(std::size_t bytes, const char* what) const {
    if (bytes > device_.info().max_alloc_bytes)
        throw InputError(fmt::format("{} of the mesh need {} bytes; {} allocates at most {} bytes at once", what, bytes,
                                     device_.info().name, device_.info().max_alloc_bytes));
}

MeshGrid MeshGridBuilder::build(const TriangleMesh& mesh, const GridFrame& frame, measure::Scheduler& scheduler) {
    return build(upload(mesh), frame, scheduler);
}

MeshGrid MeshGridBuilder::build(const Triangles& tris, const GridFrame& frame, measure::Scheduler& scheduler) {
    MeshGrid grid;
    grid.origin = frame.origin;
    grid.cell = frame.cell;
    grid.dims = frame.dims;
    const std::size_t points = frame.points();
    check_fits(points * sizeof(float), "the grid's points");
    ocl::Buffer<float> out(device_, points);
    const glm::vec3 o(grid.origin);
    ocl::set_args(kernel_.get(), tris.nodes, tris.corners, tris.normals, o.x, o.y, o.z, static_cast<float>(grid.cell),
                  static_cast<cl_uint>(grid.dims.x), static_cast<cl_uint>(grid.dims.y), static_cast<cl_uint>(grid.dims.z), out);
    const std::size_t group = 64;
    scheduler.launch(measure::Stage::mesh, -1, kernel_.get(), (points + group - 1) / group * group, group);
    grid.values = out.read();
    return grid;
}

SparseMeshGrid MeshGridBuilder::build_sparse(const TriangleMesh& mesh, const GridFrame& frame, double band,
                                             measure::Scheduler& scheduler) {
    const Triangles tris = upload(mesh);
    SparseMeshGrid out;
    out.tiles = sparse_tiles(frame);
    // The exact distances at the tile corners: the points 8 t of the same grid (cell times 8 is exact
    // in float, so these are the very points of the fine grid).
    GridFrame coarse = frame;
    coarse.cell = frame.cell * kMeshTile;
    coarse.dims = out.tiles + 1;
    const MeshGrid corners = build(tris, coarse, scheduler);
    GridFrame middle = coarse;  // the tile centres, points 8 t + 4
    middle.origin = glm::dvec3(glm::vec3(frame.origin + 0.5 * coarse.cell));
    middle.dims = out.tiles;
    const MeshGrid centres = build(tris, middle, scheduler);
    // A tile whose centre lies at least half its diagonal plus `band` from the surface holds no point
    // nearer than `band`: it keeps no values (the lookup bounds the distance from its corners and
    // centre); a little more is asked for the float rounding of the centre's distance.
    const double half_diagonal = 0.5 * kMeshTile * frame.cell * std::sqrt(3.0) * (1.0 + 1e-5);
    std::vector<cl_uint> active;
    const std::size_t table = out.table_size();
    out.values.assign(table, 0.0f);
    out.values.insert(out.values.end(), corners.values.begin(), corners.values.end());
    out.values.insert(out.values.end(), centres.values.begin(), centres.values.end());
    std::size_t next = out.values.size();
    for (int z = 0, t = 0; z < out.tiles.z; ++z)
        for (int y = 0; y < out.tiles.y; ++y)
            for (int x = 0; x < out.tiles.x; ++x, ++t) {
                cl_uint entry = SDF_MESH_NO_TILE;
                if (std::abs(centres.at(x, y, z)) < half_diagonal + band) {
                    entry = static_cast<cl_uint>(next);
                    next += kMeshTilePoints;
                    active.insert(active.end(), {cl_uint(x), cl_uint(y), cl_uint(z)});
                }
                std::memcpy(&out.values[t], &entry, sizeof entry);
            }
    out.active = active.size() / 3;
    if (out.active > 0) {
        check_fits(out.active * kMeshTilePoints * sizeof(float), "the band's tiles");
        const ocl::Buffer<cl_uint> list(device_, std::span<const cl_uint>(active), CL_MEM_READ_ONLY);
        ocl::Buffer<float> values(device_, out.active * kMeshTilePoints);
        const glm::vec3 o(frame.origin);
        const auto count = static_cast<cl_uint>(out.active);
        ocl::set_args(tiles_kernel_.get(), tris.nodes, tris.corners, tris.normals, o.x, o.y, o.z,
                      static_cast<float>(frame.cell), list, count, values);
        const std::size_t group = 64, items = out.active * kMeshTilePoints;
        scheduler.launch(measure::Stage::mesh, -1, tiles_kernel_.get(), (items + group - 1) / group * group, group);
        const std::vector<float> v = values.read();
        out.values.insert(out.values.end(), v.begin(), v.end());
    }
    return out;
}

}  // namespace sdfbrick::construct
