#include "render/seams.h"

#include <cmath>

#include <glm/geometric.hpp>

namespace sdfbrick::render {

namespace {

// Cells are below 2^21 per axis on every level (the Morton keys' limit).
std::uint64_t key(const glm::ivec3& c) {
    const auto u = [](int v) { return static_cast<std::uint64_t>(v); };
    return u(c.x) | u(c.y) << 21 | u(c.z) << 42;
}

const glm::ivec3 kFaces[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};

}  // namespace

LeafCells::LeafCells(const construct::GeometryBuild& b)
    : origin_(b.origin), leaf_size_(b.leaf_size), levels_(b.levels), branching_(b.branching),
      coarsest_(b.coarsest_leaf_level), by_level_(static_cast<std::size_t>(b.levels)),
      index_(static_cast<std::size_t>(b.levels)) {
    for (const SdfBrick& r : b.leaves->read()) {
        const glm::ivec3 c(r.coord[0], r.coord[1], r.coord[2]);
        by_level_[r.level].push_back(c);
        index_[r.level].insert(key(c));
        ++leaves_;
    }
}

double LeafCells::cell(int level) const { return leaf_size_ * std::pow(double(branching_), levels_ - 1 - level); }

bool LeafCells::has(int level, const glm::ivec3& c) const {
    constexpr int kLimit = 1 << 21;
    if (c.x < 0 || c.y < 0 || c.z < 0 || c.x >= kLimit || c.y >= kLimit || c.z >= kLimit) return false;
    return index_[static_cast<std::size_t>(level)].count(key(c)) != 0;
}

std::optional<int> LeafCells::level_at(const glm::dvec3& p) const {
    for (int l = coarsest_; l < levels_; ++l) {
        if (has(l, glm::ivec3(glm::floor((p - origin_) / cell(l))))) return l;
    }
    return std::nullopt;
}

bool LeafCells::near_seam(const glm::dvec3& p, int interior) const {
    const std::optional<int> l = level_at(p);
    if (!l) return false;
    const double h = cell(*l), voxel = h / interior;
    const glm::ivec3 c(glm::floor((p - origin_) / h));
    const glm::dvec3 low = origin_ + glm::dvec3(c) * h;
    for (const glm::ivec3& f : kFaces) {
        const int axis = f.x != 0 ? 0 : (f.y != 0 ? 1 : 2);
        const double face = low[axis] + (f[axis] > 0 ? h : 0.0);
        if (std::abs(face - p[axis]) > voxel || has(*l, c + f)) continue;
        glm::dvec3 across = p;
        across[axis] = face + f[axis] * 0.5 * leaf_size_ / interior;  // half a finest voxel past the face
        const std::optional<int> other = level_at(across);
        if (other && *other != *l) return true;
    }
    return false;
}

std::size_t LeafCells::seam_leaves(int interior) const {
    std::size_t n = 0;
    for (int l = coarsest_; l < levels_; ++l) {
        const double h = cell(l);
        for (const glm::ivec3& c : by_level_[l]) {
            const glm::dvec3 centre = origin_ + (glm::dvec3(c) + 0.5) * h;
            for (const glm::ivec3& f : kFaces) {
                if (has(l, c + f)) continue;
                const glm::dvec3 across = centre + glm::dvec3(f) * (0.5 * h + 0.5 * leaf_size_ / interior);
                const std::optional<int> other = level_at(across);
                if (other && *other != l) {
                    ++n;
                    break;
                }
            }
        }
    }
    return n;
}

nlohmann::json to_json(const SeamMismatches& s) {
    return {{"at_seams", s.at_seams}, {"elsewhere", s.elsewhere}, {"seam_leaves", s.seam_leaves}};
}

SeamMismatches count_seam_mismatches(const Scene& scene, const SceneBricks& bricks, const SdfCamera& camera,
                                     const RenderBuffer& test, const RenderBuffer& reference) {
    test.check("test");
    reference.check("reference");
    const int interior = bricks.settings.layout().interior();
    std::vector<LeafCells> cells;
    SeamMismatches out;
    for (const construct::GeometryBuild& b : bricks.builds) {
        cells.emplace_back(b);
        out.seam_leaves += cells.back().seam_leaves(interior);
    }
    const glm::dvec3 eye(camera.eye[0], camera.eye[1], camera.eye[2]);
    const glm::dvec3 forward(camera.forward[0], camera.forward[1], camera.forward[2]);
    const glm::dvec3 right(camera.right[0], camera.right[1], camera.right[2]);
    const glm::dvec3 up(camera.up[0], camera.up[1], camera.up[2]);
    for (std::size_t i = 0; i < test.pixels(); ++i) {
        if (test.is_hit(i) == reference.is_hit(i) || (reference.aux[i].s[1] & SDF_REF_UNCONVERGED) != 0u) continue;
        const double x = double(i % test.width), y = double(i / test.width);
        const double u = 2.0 * (x + 0.5) / test.width - 1.0, v = 1.0 - 2.0 * (y + 0.5) / test.height;
        const double t = test.is_hit(i) ? test.hit[i].s[3] : reference.hit[i].s[3];
        const glm::dvec3 world = eye + t * glm::normalize(forward + u * right + v * up);
        bool seam = false;
        for (const Object& o : scene.objects)
            seam = seam || cells[o.geometry].near_seam(o.transform.inverse_apply(world), interior);
        ++(seam ? out.at_seams : out.elsewhere);
    }
    return out;
}

}  // namespace sdfbrick::render
