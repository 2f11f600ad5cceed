#include "scene/mesh.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <chrono>
#include <csignal>
#include <fstream>
#include <optional>
#include <sstream>
#include <string_view>
#include <map>
#include <numbers>
#include <tuple>
#include <utility>

#include <fcntl.h>
#include <poll.h>
#include <sys/wait.h>
#include <unistd.h>

#include <assimp/IOStream.hpp>
#include <assimp/IOSystem.hpp>
#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <fmt/format.h>

#include "core/errors.h"
#include "core/files.h"
#include "core/quote.h"
#include "scene/mesh_orient.h"

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

// Adds a mesh's polygons as triangles (fans: a polygon of n corners gives n - 2) with its vertices
// placed by the node transform `to_scene` (applied in double precision; the identity keeps them
// exact). Corners are checked against the vertex count: nothing from the file is trusted.
void add_mesh(const aiMesh& m, const glm::dmat4& to_scene, bool identity, const std::filesystem::path& path,
              Welder& welder, TriangleMesh& out) {
    std::vector<glm::dvec3> placed(m.mNumVertices);
    for (unsigned v = 0; v < m.mNumVertices; ++v) {
        const aiVector3D& p = m.mVertices[v];
        placed[v] = identity ? glm::dvec3(p.x, p.y, p.z) : glm::dvec3(to_scene * glm::dvec4(p.x, p.y, p.z, 1.0));
        if (!std::isfinite(placed[v].x) || !std::isfinite(placed[v].y) || !std::isfinite(placed[v].z))
            throw InputError(fmt::format("{}: vertex {} is not finite ({}, {}, {})", path.string(), v, p.x, p.y, p.z));
    }
    for (unsigned f = 0; f < m.mNumFaces; ++f) {
        const aiFace& face = m.mFaces[f];
        for (unsigned c = 0; c < face.mNumIndices; ++c)
            if (face.mIndices[c] >= m.mNumVertices)
                throw InputError(fmt::format("{}: face {} names vertex {} of {}", path.string(), f, face.mIndices[c], m.mNumVertices));
        for (unsigned c = 2; c < face.mNumIndices; ++c) {  // points and lines have no surface
            const std::array<std::uint32_t, 3> t = {welder.add(placed[face.mIndices[0]]), welder.add(placed[face.mIndices[c - 1]]),
                                                    welder.add(placed[face.mIndices[c]])};
            if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) continue;
            if (out.triangles.size() == kMaxMeshTriangles)
                throw InputError(fmt::format("{}: more than {} triangles", path.string(), kMaxMeshTriangles));
            out.triangles.push_back(t);
        }
    }
}

// Adds the meshes of a node and its children, each placed by the product of the node transforms
// above it (a mesh that several nodes name is added once per node, as instances are).
void add_node(const aiScene& scene, const aiNode& node, const glm::dmat4& parent, int depth,
              const std::filesystem::path& path, Welder& welder, TriangleMesh& out) {
    if (depth > 256) throw InputError(fmt::format("{}: nodes nested more than 256 deep", path.string()));
    const aiMatrix4x4& t = node.mTransformation;
    glm::dmat4 local(1.0);
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) local[c][r] = t[r][c];  // aiMatrix4x4 is row-major, glm column-major
    const glm::dmat4 to_scene = parent * local;
    const bool identity = to_scene == glm::dmat4(1.0);
    for (unsigned i = 0; i < node.mNumMeshes; ++i) {
        if (node.mMeshes[i] >= scene.mNumMeshes)
            throw InputError(fmt::format("{}: a node names mesh {} of {}", path.string(), node.mMeshes[i], scene.mNumMeshes));
        add_mesh(*scene.mMeshes[node.mMeshes[i]], to_scene, identity, path, welder, out);
    }
    for (unsigned c = 0; c < node.mNumChildren; ++c)
        if (node.mChildren[c]) add_node(scene, *node.mChildren[c], to_scene, depth + 1, path, welder, out);
}

// Bytes one value of a PLY scalar type takes in a binary file; 0 for an unknown type.
std::size_t ply_type_bytes(std::string_view type) {
    static const std::map<std::string_view, std::size_t> sizes = {
        {"char", 1}, {"uchar", 1}, {"int8", 1}, {"uint8", 1}, {"short", 2}, {"ushort", 2}, {"int16", 2},
        {"uint16", 2}, {"int", 4}, {"uint", 4}, {"int32", 4}, {"uint32", 4}, {"float", 4}, {"float32", 4},
        {"double", 8}, {"float64", 8}};
    const auto it = sizes.find(type);
    return it == sizes.end() ? 0 : it->second;
}

// Refuses a PLY file whose header promises more elements than its body can hold (before Assimp
// allocates for them): each element takes at least the bytes of its scalar properties and list
// counts (binary), or two characters per property (ASCII: a digit and a separator), and never less
// than one byte. Also refuses a header that never ends (Assimp 5.2 does not return on one).
void check_ply_header(std::string_view bytes, const std::filesystem::path& path) {
    const auto fail = [&](const std::string& why) { return InputError(fmt::format("{}: cannot read mesh: {}", path.string(), why)); };
    const std::size_t end = bytes.find("end_header");
    if (end == std::string_view::npos) throw fail("a PLY header without end_header");
    const std::size_t body_start = std::min(bytes.size(), bytes.find('\n', end) == std::string_view::npos ? bytes.size() : bytes.find('\n', end) + 1);
    std::istringstream header{std::string(bytes.substr(0, end))};
    bool ascii = false;
    std::vector<std::pair<std::string, double>> elements;  // name, count
    std::vector<double> least;                             // bytes each element takes at least
    for (std::string line; std::getline(header, line);) {
        std::istringstream words(line);
        std::string word, a, b;
        words >> word >> a >> b;
        if (word == "format") ascii = a == "ascii";
        else if (word == "element") {
            double count = -1;
            if (!(std::istringstream(b) >> count) || count < 0) throw fail(fmt::format("element {}: a count that is not a number", escaped(a)));
            elements.emplace_back(a, count);
            least.push_back(0);
        } else if (word == "property" && !least.empty())
            least.back() += ascii ? 2.0 : static_cast<double>(ply_type_bytes(a == "list" ? b : a));
    }
    double need = 0;
    for (std::size_t e = 0; e < elements.size(); ++e) need += elements[e].second * std::max(1.0, least[e]);
    const std::size_t body = bytes.size() - body_start;
    if (need > static_cast<double>(body)) {
        std::string counts;
        for (const auto& [name, count] : elements) counts += fmt::format("{}{} {:.0f}", counts.empty() ? "" : ", ", name, count);
        throw fail(fmt::format("the {} PLY header declares {}: at least {:.0f} bytes, but {} bytes follow it",
                               ascii ? "ASCII" : "binary", escaped(counts, 256), need, body));
    }
}

// ---- reading mesh files ----

// An Assimp stream over bytes already read (read_file: regular files only, size-capped).
class BytesStream final : public Assimp::IOStream {
public:
    explicit BytesStream(std::string bytes) : owned_(std::move(bytes)), bytes_(owned_) {}
    explicit BytesStream(std::string_view bytes) : bytes_(bytes) {}  // bytes outlive the stream
    size_t Read(void* out, size_t size, size_t count) override {
        if (size == 0) return 0;
        const size_t n = std::min(count, (bytes_.size() - pos_) / size);
        std::memcpy(out, bytes_.data() + pos_, n * size);
        pos_ += n * size;
        return n;
    }
    size_t Write(const void*, size_t, size_t) override { return 0; }
    aiReturn Seek(size_t offset, aiOrigin origin) override {
        const size_t base = origin == aiOrigin_SET ? 0 : origin == aiOrigin_CUR ? pos_ : bytes_.size();
        if (origin == aiOrigin_END ? offset > base : offset > bytes_.size() - base) return aiReturn_FAILURE;
        pos_ = origin == aiOrigin_END ? base - offset : base + offset;
        return aiReturn_SUCCESS;
    }
    size_t Tell() const override { return pos_; }
    size_t FileSize() const override { return bytes_.size(); }
    void Flush() override {}

private:
    std::string owned_;
    std::string_view bytes_;
    size_t pos_ = 0;
};

// The files a mesh loader may open: the mesh file itself (its bytes as load_mesh read them) and
// regular files inside its folder (a glTF buffer, an OBJ material library), each read whole through
// read_file and so size-capped and never blocking.
// The first refusal is kept: the loader may carry on without the file, but the mesh is refused.
class MeshFiles final : public Assimp::IOSystem {
public:
    // mesh_bytes: the mesh file's bytes, already read (and outliving this).
    MeshFiles(const std::filesystem::path& mesh, std::string_view mesh_bytes)
        : mesh_(resolved(mesh)), folder_(mesh_.parent_path()), mesh_bytes_(mesh_bytes) {}
    bool Exists(const char* file) const override {
        std::error_code ec;
        return std::filesystem::exists(file, ec);
    }
    char getOsSeparator() const override { return '/'; }
    Assimp::IOStream* Open(const char* file, const char* mode) override {
        if (std::string_view(mode).find_first_of("wa+") != std::string_view::npos) return nullptr;
        try {
            const std::filesystem::path real = inside_folder(file);
            if (real == mesh_) return new BytesStream(mesh_bytes_);
            return new BytesStream(read_file(real));
        } catch (const InputError& e) {
            if (!refusal_) refusal_ = e.what();
            return nullptr;
        }
    }
    void Close(Assimp::IOStream* stream) override { delete stream; }
    const std::optional<std::string>& refusal() const { return refusal_; }

private:
    static std::filesystem::path resolved(const std::filesystem::path& file) {
        std::error_code ec;
        return std::filesystem::weakly_canonical(std::filesystem::absolute(file, ec), ec);
    }
    std::filesystem::path inside_folder(const std::filesystem::path& file) const {
        const std::filesystem::path real = resolved(file);
        if (real.empty() || !lies_within(real, folder_))
            throw InputError(fmt::format("{}: refused: outside the mesh's folder {}", file.string(), folder_.string()));
        return real;
    }
    std::filesystem::path mesh_, folder_;
    std::string_view mesh_bytes_;
    std::optional<std::string> refusal_;
};


// Reads the mesh with Assimp in this process: the file's folder as its file system, the data
// structure validated; polygons and node transforms are handled here (add_node), not by Assimp's
// post-processing, whose assertions abort on some malformed files.
TriangleMesh read_with_assimp(const std::filesystem::path& path, std::string_view bytes) {
    Assimp::Importer importer;
    auto* files = new MeshFiles(path, bytes);
    importer.SetIOHandler(files);  // the importer owns it
    const aiScene* scene = importer.ReadFile(path.string(), aiProcess_ValidateDataStructure);
    // What the file names and Assimp's messages echo the file's bytes: escaped.
    if (files->refusal()) throw InputError(fmt::format("{}: cannot read mesh: {}", path.string(), escaped(*files->refusal(), 512)));
    if (!scene || (scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE) != 0) {
        const std::string why = importer.GetErrorString();
        throw InputError(fmt::format("{}: cannot read mesh: {}", path.string(), why.empty() ? "no scene" : escaped(why, 512)));
    }
    TriangleMesh out;
    Welder welder(out);
    if (scene->mRootNode) add_node(*scene, *scene->mRootNode, glm::dmat4(1.0), 0, path, welder, out);
    return out;
}

// The reply of the reading process: 'M', the vertex and triangle counts, the vertices (3 doubles
// each) and the triangles (3 uint32 each); or 'E' and the refusal's message.
template <class T>
void append_raw(std::string& out, const T* values, std::size_t count) {
    if (count > 0) out.append(reinterpret_cast<const char*>(values), count * sizeof(T));
}

std::string encode_reply(const std::filesystem::path& path, std::string_view bytes) {
    try {
        const TriangleMesh m = read_with_assimp(path, bytes);
        std::string out = "M";
        const std::uint64_t counts[2] = {m.vertices.size(), m.triangles.size()};
        append_raw(out, counts, 2);
        append_raw(out, m.vertices.data(), m.vertices.size());
        append_raw(out, m.triangles.data(), m.triangles.size());
        return out;
    } catch (const InputError& e) {
        return std::string("E") + e.what();
    } catch (const std::bad_alloc&) {
        return fmt::format("E{}: cannot read mesh: out of host memory", path.string());
    } catch (const std::exception& e) {
        return fmt::format("E{}: cannot read mesh: {}", path.string(), escaped(e.what(), 512));
    }
}

TriangleMesh decode_reply(const std::string& reply, const std::filesystem::path& path) {
    if (!reply.empty() && reply[0] == 'E') throw InputError(reply.substr(1));
    std::uint64_t counts[2] = {0, 0};
    const auto broken = [&] { return InputError(fmt::format("{}: cannot read mesh: a broken reply from the reader", path.string())); };
    if (reply.size() < 1 + sizeof counts || reply[0] != 'M') throw broken();
    std::memcpy(counts, reply.data() + 1, sizeof counts);
    const std::size_t at = 1 + sizeof counts;
    if (counts[0] > reply.size() / sizeof(glm::dvec3) || counts[1] > reply.size() / 12 ||
        reply.size() != at + counts[0] * sizeof(glm::dvec3) + counts[1] * 12)
        throw broken();
    TriangleMesh m;
    m.vertices.resize(counts[0]);
    m.triangles.resize(counts[1]);
    if (counts[0] > 0) std::memcpy(m.vertices.data(), reply.data() + at, counts[0] * sizeof(glm::dvec3));
    if (counts[1] > 0) std::memcpy(m.triangles.data(), reply.data() + at + counts[0] * sizeof(glm::dvec3), counts[1] * 12);
    for (const auto& t : m.triangles)
        for (const std::uint32_t i : t)
            if (i >= m.vertices.size()) throw broken();
    return m;
}

// Reads everything the child writes to fd within the time limit; false on a timeout.
bool read_reply(int fd, std::string& reply, std::chrono::seconds limit) {
    const auto end = std::chrono::steady_clock::now() + limit;
    char chunk[1 << 16];
    while (true) {
        const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(end - std::chrono::steady_clock::now());
        if (left.count() <= 0) return false;
        pollfd p{fd, POLLIN, 0};
        const int ready = ::poll(&p, 1, static_cast<int>(left.count()));
        if (ready < 0 && errno == EINTR) continue;
        if (ready == 0) return false;  // the time is up
        if (ready < 0) return true;    // the pipe failed: what was read is the reply
        const ssize_t n = ::read(fd, chunk, sizeof chunk);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) return true;
        reply.append(chunk, static_cast<std::size_t>(n));
    }
}

// Assimp runs in a child process: a crash, an assertion or a hang of the reader on a malformed file
// ends the child, not the program, and becomes a refusal naming the file.
TriangleMesh read_isolated(const std::filesystem::path& path, std::string_view bytes, int seconds) {
    int fds[2];
    if (::pipe2(fds, O_CLOEXEC) != 0) return read_with_assimp(path, bytes);  // no pipe: read in this process
    const pid_t child = ::fork();
    if (child < 0) {
        ::close(fds[0]);
        ::close(fds[1]);
        return read_with_assimp(path, bytes);
    }
    if (child == 0) {
        ::close(fds[0]);
        for (const int sig : {SIGSEGV, SIGBUS, SIGILL, SIGFPE, SIGABRT}) ::signal(sig, SIG_DFL);
        const std::string reply = encode_reply(path, bytes);
        for (std::size_t done = 0; done < reply.size();) {
            const ssize_t n = ::write(fds[1], reply.data() + done, reply.size() - done);
            if (n < 0 && errno == EINTR) continue;
            if (n <= 0) ::_exit(1);
            done += static_cast<std::size_t>(n);
        }
        ::_exit(0);
    }
    ::close(fds[1]);
    std::string reply;
    const bool in_time = read_reply(fds[0], reply, std::chrono::seconds(seconds));
    ::close(fds[0]);
    if (!in_time) ::kill(child, SIGKILL);
    int status = 0;
    while (::waitpid(child, &status, 0) < 0 && errno == EINTR) {}
    if (!in_time)
        throw InputError(fmt::format("{}: cannot read mesh: the reader (Assimp) took more than {} s", path.string(), seconds));
    if (WIFSIGNALED(status))
        throw InputError(fmt::format("{}: cannot read mesh: the reader (Assimp) crashed on it ({})", path.string(),
                                     strsignal(WTERMSIG(status))));
    return decode_reply(reply, path);
}

}  // namespace

TriangleMesh load_mesh(const std::filesystem::path& path, int seconds) {
    const std::string bytes = read_file(path);
    if (bytes.starts_with("ply")) check_ply_header(bytes, path);
    TriangleMesh out = read_isolated(path, bytes, seconds);
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

std::shared_ptr<MeshSource> make_mesh_source(TriangleMesh mesh, std::string file, int resolution, bool sparse) {
    const MeshTopology t = topology(mesh);
    if (!t.closed())
        throw InputError(fmt::format("{}: the mesh is not closed ({} open edges, {} non-manifold edges of {}): its "
                                     "inside, and so the sign of its distance, is not defined",
                                     file, t.open_edges, t.non_manifold_edges, t.edges));
    const int most = sparse ? kMaxSparseMeshResolution : kMaxMeshResolution;
    if (resolution < 2 || resolution > most)
        throw InputError(fmt::format("{}: resolution {} is outside 2..{} for a {} grid", file, resolution, most,
                                     sparse ? "sparse" : "dense"));
    MeshOrientation turned;
    try {
        turned = orient(mesh);
    } catch (const InputError& e) {
        throw InputError(fmt::format("{}: {}", file, e.what()));
    }
    auto source = std::make_shared<MeshSource>();
    source->warning = turned.describe();
    const glm::dvec3 e = mesh.bounds().extent();
    const double longest = std::max({e.x, e.y, e.z});
    if (!(longest > 0.0)) throw InputError(fmt::format("{}: the mesh has no extent", file));
    source->frame = grid_frame(mesh, longest / resolution, kMeshPadding);
    source->sparse = sparse;
    source->band = kMeshBandCells * source->frame.cell;
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
