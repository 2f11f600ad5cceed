#include "scene/mesh.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <numbers>
#include <tuple>
#include <utility>

#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <fmt/format.h>

#include "core/errors.h"
#include "core/files.h"

namespace sdfbrick {

Aabb TriangleMesh::bounds() const {
    Aabb b;
    for (const glm::dvec3& v : vertices) b.grow(v);
    return b;
}

namespace {

// Welds positions by exact value: index of each distinct position, in order of first use.
class Welder {
public:
    explicit Welder(TriangleMesh& mesh) : mesh_(mesh) {}
    std::uint32_t add(const glm::dvec3& p) {
        const auto [it, inserted] = index_.try_emplace(std::tuple(p.x, p.y, p.z), static_cast<std::uint32_t>(mesh_.vertices.size()));
        if (inserted) mesh_.vertices.push_back(p);
        return it->second;
    }

private:
    TriangleMesh& mesh_;
    std::map<std::tuple<double, double, double>, std::uint32_t> index_;
};

void add_mesh(const aiMesh& m, const std::filesystem::path& path, Welder& welder, TriangleMesh& out) {
    for (unsigned v = 0; v < m.mNumVertices; ++v) {
        const aiVector3D& p = m.mVertices[v];
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
            throw InputError(fmt::format("{}: vertex {} is not finite ({}, {}, {})", path.string(), v, p.x, p.y, p.z));
    }
    for (unsigned f = 0; f < m.mNumFaces; ++f) {
        const aiFace& face = m.mFaces[f];
        if (face.mNumIndices != 3) continue;  // points and lines have no surface
        std::array<std::uint32_t, 3> t{};
        for (int c = 0; c < 3; ++c) {
            const aiVector3D& p = m.mVertices[face.mIndices[c]];
            t[c] = welder.add(glm::dvec3(p.x, p.y, p.z));
        }
        if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) continue;
        if (out.triangles.size() == kMaxMeshTriangles)
            throw InputError(fmt::format("{}: more than {} triangles", path.string(), kMaxMeshTriangles));
        out.triangles.push_back(t);
    }
}

}  // namespace

TriangleMesh load_mesh(const std::filesystem::path& path) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec))
        throw InputError(fmt::format("{}: cannot read mesh: no such file", path.string()));
    if (path.extension() == ".ply" || path.extension() == ".PLY") {
        // Assimp 5.2's PLY reader does not return on a header that never ends: refuse it first.
        std::ifstream in(path, std::ios::binary);
        std::string head(65536, '\0');
        in.read(head.data(), static_cast<std::streamsize>(head.size()));
        head.resize(static_cast<std::size_t>(in.gcount()));
        if (head.find("end_header") == std::string::npos)
            throw InputError(fmt::format("{}: cannot read mesh: a PLY header without end_header", path.string()));
    }
    Assimp::Importer importer;
    // Triangulated, node transforms baked into the vertices, the data structure validated.
    const aiScene* scene = importer.ReadFile(
        path.string(), aiProcess_Triangulate | aiProcess_PreTransformVertices | aiProcess_ValidateDataStructure);
    if (!scene || (scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE) != 0) {
        std::string why = importer.GetErrorString();
        std::replace(why.begin(), why.end(), '\n', ' ');
        throw InputError(fmt::format("{}: cannot read mesh: {}", path.string(), why.empty() ? "no scene" : why));
    }
    TriangleMesh out;
    Welder welder(out);
    for (unsigned m = 0; m < scene->mNumMeshes; ++m) add_mesh(*scene->mMeshes[m], path, welder, out);
    if (out.triangles.empty()) throw InputError(fmt::format("{}: the mesh has no triangles", path.string()));
    return out;
}

MeshTopology topology(const TriangleMesh& mesh) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> uses;
    for (const auto& t : mesh.triangles)
        for (int e = 0; e < 3; ++e) {
            const std::uint32_t a = t[e], b = t[(e + 1) % 3];
            ++uses[{std::min(a, b), std::max(a, b)}];
        }
    MeshTopology out;
    out.edges = uses.size();
    for (const auto& [edge, n] : uses) {
        if (n == 1) ++out.open_edges;
        if (n > 2) ++out.non_manifold_edges;
    }
    return out;
}

namespace {

using Tri = std::array<std::uint32_t, 3>;

// Turns every triangle to face away from `inside(centroid)`.
template <class Inside>
void orient_outward(TriangleMesh& m, Inside inside) {
    for (Tri& t : m.triangles) {
        const glm::dvec3 a = m.vertices[t[0]], b = m.vertices[t[1]], c = m.vertices[t[2]];
        const glm::dvec3 centroid = (a + b + c) / 3.0;
        if (glm::dot(glm::cross(b - a, c - a), centroid - inside(centroid)) < 0.0) std::swap(t[1], t[2]);
    }
}

}  // namespace

TriangleMesh icosphere(double r, int levels) {
    const double g = (1.0 + std::sqrt(5.0)) / 2.0;
    TriangleMesh m;
    for (const glm::dvec3& v : {glm::dvec3(-1, g, 0), glm::dvec3(1, g, 0), glm::dvec3(-1, -g, 0), glm::dvec3(1, -g, 0),
                                glm::dvec3(0, -1, g), glm::dvec3(0, 1, g), glm::dvec3(0, -1, -g), glm::dvec3(0, 1, -g),
                                glm::dvec3(g, 0, -1), glm::dvec3(g, 0, 1), glm::dvec3(-g, 0, -1), glm::dvec3(-g, 0, 1)})
        m.vertices.push_back(r * glm::normalize(v));
    m.triangles = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                   {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
                   {3, 8, 9},  {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
    for (int level = 0; level < levels; ++level) {
        std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> middle;
        const auto mid = [&](std::uint32_t a, std::uint32_t b) {
            const auto key = std::pair(std::min(a, b), std::max(a, b));
            const auto [it, fresh] = middle.try_emplace(key, static_cast<std::uint32_t>(m.vertices.size()));
            if (fresh) m.vertices.push_back(r * glm::normalize(m.vertices[a] + m.vertices[b]));
            return it->second;
        };
        std::vector<Tri> next;
        for (const Tri& t : m.triangles) {
            const std::uint32_t ab = mid(t[0], t[1]), bc = mid(t[1], t[2]), ca = mid(t[2], t[0]);
            next.insert(next.end(), {Tri{t[0], ab, ca}, Tri{t[1], bc, ab}, Tri{t[2], ca, bc}, Tri{ab, bc, ca}});
        }
        m.triangles = std::move(next);
    }
    orient_outward(m, [](const glm::dvec3&) { return glm::dvec3(0.0); });
    return m;
}

TriangleMesh torus_mesh(double R, double r, int u, int v) {
    TriangleMesh m;
    for (int j = 0; j < v; ++j)
        for (int i = 0; i < u; ++i) {
            const double a = 2.0 * std::numbers::pi * i / u, b = 2.0 * std::numbers::pi * j / v;
            m.vertices.emplace_back((R + r * std::cos(b)) * std::cos(a), r * std::sin(b), (R + r * std::cos(b)) * std::sin(a));
        }
    const auto at = [&](int i, int j) { return static_cast<std::uint32_t>((i % u) + u * (j % v)); };
    for (int j = 0; j < v; ++j)
        for (int i = 0; i < u; ++i) {
            m.triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
            m.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
        }
    orient_outward(m, [R](const glm::dvec3& c) { return R * glm::normalize(glm::dvec3(c.x, 0.0, c.z)); });
    return m;
}

TriangleMesh box_with_hole(double a, double b, double h) {
    TriangleMesh m;
    const double xs[4] = {-a, -b, b, a};
    for (double z : {h, -h})
        for (int j = 0; j < 4; ++j)
            for (int i = 0; i < 4; ++i) m.vertices.emplace_back(xs[i], xs[j], z);
    const auto top = [](int i, int j) { return static_cast<std::uint32_t>(i + 4 * j); };
    const auto bottom = [](int i, int j) { return static_cast<std::uint32_t>(16 + i + 4 * j); };
    for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 3; ++i) {
            if (i == 1 && j == 1) continue;  // the hole
            m.triangles.push_back({top(i, j), top(i + 1, j), top(i + 1, j + 1)});
            m.triangles.push_back({top(i, j), top(i + 1, j + 1), top(i, j + 1)});
            m.triangles.push_back({bottom(i, j), bottom(i + 1, j + 1), bottom(i + 1, j)});
            m.triangles.push_back({bottom(i, j), bottom(i, j + 1), bottom(i + 1, j + 1)});
        }
    // Walls along loops with the solid on the left (seen from +z): the outer square counter-clockwise,
    // the hole clockwise.
    const int outer[][2] = {{0, 0}, {1, 0}, {2, 0}, {3, 0}, {3, 1}, {3, 2}, {3, 3},
                            {2, 3}, {1, 3}, {0, 3}, {0, 2}, {0, 1}, {0, 0}};
    const int inner[][2] = {{1, 1}, {1, 2}, {2, 2}, {2, 1}, {1, 1}};
    const auto walls = [&](const int (*loop)[2], int n) {
        for (int e = 0; e + 1 < n; ++e) {
            const auto [i0, j0] = std::pair(loop[e][0], loop[e][1]);
            const auto [i1, j1] = std::pair(loop[e + 1][0], loop[e + 1][1]);
            m.triangles.push_back({top(i0, j0), bottom(i0, j0), bottom(i1, j1)});
            m.triangles.push_back({top(i0, j0), bottom(i1, j1), top(i1, j1)});
        }
    };
    walls(outer, 13);
    walls(inner, 5);
    return m;
}

void write_obj(const TriangleMesh& mesh, const std::filesystem::path& path) {
    std::string s = "# generated by the sdfbrick tests\n";
    for (const glm::dvec3& v : mesh.vertices) s += fmt::format("v {} {} {}\n", v.x, v.y, v.z);
    for (const auto& t : mesh.triangles) s += fmt::format("f {} {} {}\n", t[0] + 1, t[1] + 1, t[2] + 1);
    write_file_atomic(path, s);
}

void write_ply(const TriangleMesh& mesh, const std::filesystem::path& path) {
    std::string s = fmt::format("ply\nformat ascii 1.0\nelement vertex {}\nproperty float x\nproperty float y\n"
                                "property float z\nelement face {}\nproperty list uchar int vertex_indices\nend_header\n",
                                mesh.vertices.size(), mesh.triangles.size());
    for (const glm::dvec3& v : mesh.vertices) s += fmt::format("{} {} {}\n", v.x, v.y, v.z);
    for (const auto& t : mesh.triangles) s += fmt::format("3 {} {} {}\n", t[0], t[1], t[2]);
    write_file_atomic(path, s);
}

GridFrame grid_frame(const TriangleMesh& mesh, double cell, int padding) {
    if (!(cell > 0.0) || !std::isfinite(cell))
        throw SettingError("cell", fmt::format("the mesh grid's cell must be positive and finite, got {}", cell));
    const Aabb box = mesh.bounds();
    const glm::dvec3 cells = glm::ceil(box.extent() / cell) + 2.0 * padding;
    if (cells.x > kMaxGridCells || cells.y > kMaxGridCells || cells.z > kMaxGridCells)
        throw InputError(fmt::format("a mesh grid of {} x {} x {} cells is more than {} along an axis: use a larger cell",
                                     cells.x, cells.y, cells.z, kMaxGridCells));
    GridFrame f;
    f.origin = glm::dvec3(glm::vec3(box.lo - padding * cell));  // the floats the kernels read
    f.cell = static_cast<float>(cell);
    f.dims = glm::ivec3(cells) + 1;
    return f;
}

std::shared_ptr<MeshSource> make_mesh_source(TriangleMesh mesh, std::string file, int resolution) {
    const MeshTopology t = topology(mesh);
    if (!t.closed())
        throw InputError(fmt::format("{}: the mesh is not closed ({} open edges, {} non-manifold edges of {}): its "
                                     "inside, and so the sign of its distance, is not defined",
                                     file, t.open_edges, t.non_manifold_edges, t.edges));
    if (resolution < 2 || resolution > kMaxMeshResolution)
        throw InputError(fmt::format("{}: resolution {} is outside 2..{}", file, resolution, kMaxMeshResolution));
    auto source = std::make_shared<MeshSource>();
    const glm::dvec3 e = mesh.bounds().extent();
    const double longest = std::max({e.x, e.y, e.z});
    if (!(longest > 0.0)) throw InputError(fmt::format("{}: the mesh has no extent", file));
    source->frame = grid_frame(mesh, longest / resolution, kMeshPadding);
    source->mesh = std::move(mesh);
    source->file = std::move(file);
    source->resolution = resolution;
    return source;
}

Edit make_mesh_edit(std::shared_ptr<MeshSource> source, std::uint32_t index) {
    Edit e;
    e.primitive = Primitive::Mesh;
    const glm::dvec3 h = glm::max(glm::abs(source->frame.origin), glm::abs(source->frame.hi()));
    e.params = {h.x, h.y, h.z, static_cast<double>(index)};
    e.mesh = std::move(source);
    return e;
}

}  // namespace sdfbrick
