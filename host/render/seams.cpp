#include "render/seams.h"

#include <cmath>

#include <glm/geometric.hpp>

#include "reference/host_tracer.h"

namespace sdfbrick::render {

namespace {

// Cells are below 2^21 per axis on every level (the Morton keys' limit).
constexpr int kLimit = 1 << 21;

std::uint64_t key(const glm::ivec3& c) {
    const auto u = [](int v) { return static_cast<std::uint64_t>(v); };
    return u(c.x) | u(c.y) << 21 | u(c.z) << 42;
}

glm::ivec3 cell_of(std::uint64_t k) {
    return {int(k & (kLimit - 1)), int((k >> 21) & (kLimit - 1)), int(k >> 42)};
}

const glm::ivec3 kFaces[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};

}  // namespace

LeafCells::LeafCells(const construct::GeometryBuild& b)
    : domain_{glm::dvec3(b.origin), b.leaf_size, b.branching, b.levels}, coarsest_(b.coarsest_leaf_level),
      cells_(static_cast<std::size_t>(b.levels)) {
    for (const SdfBrick& r : b.leaves->read()) cells_[r.level].insert(key({r.coord[0], r.coord[1], r.coord[2]}));
}

std::size_t LeafCells::leaf_count() const {
    std::size_t n = 0;
    for (const auto& level : cells_) n += level.size();
    return n;
}

bool LeafCells::has(int level, const glm::ivec3& c) const {
    if (c.x < 0 || c.y < 0 || c.z < 0 || c.x >= kLimit || c.y >= kLimit || c.z >= kLimit) return false;
    return cells_[static_cast<std::size_t>(level)].count(key(c)) != 0;
}

glm::ivec3 LeafCells::cell_at(int level, const glm::dvec3& p) const {
    return glm::ivec3(glm::floor((p - domain_.origin) / domain_.cell_size(level)));
}

std::optional<int> LeafCells::level_at(const glm::dvec3& p) const {
    for (int l = coarsest_; l < domain_.levels; ++l) {
        if (has(l, cell_at(l, p))) return l;
    }
    return std::nullopt;
}

bool LeafCells::near_seam(const glm::dvec3& p, int interior) const {
    const std::optional<int> l = level_at(p);
    if (!l) return false;
    const double h = domain_.cell_size(*l), voxel = h / interior;
    const glm::ivec3 c = cell_at(*l, p);
    const glm::dvec3 low = domain_.cell_lo(*l, c);
    for (const glm::ivec3& f : kFaces) {
        const int axis = f.x != 0 ? 0 : (f.y != 0 ? 1 : 2);
        const double face = low[axis] + (f[axis] > 0 ? h : 0.0);
        if (std::abs(face - p[axis]) > voxel || has(*l, c + f)) continue;
        glm::dvec3 across = p;
        across[axis] = face + f[axis] * 0.5 * domain_.leaf_size / interior;  // half a finest voxel past the face
        const std::optional<int> other = level_at(across);
        if (other && *other != *l) return true;
    }
    return false;
}

std::size_t LeafCells::seam_leaves(int interior) const {
    std::size_t n = 0;
    for (int l = coarsest_; l < domain_.levels; ++l) {
        const double h = domain_.cell_size(l);
        for (const std::uint64_t k : cells_[static_cast<std::size_t>(l)]) {
            const glm::ivec3 c = cell_of(k);
            const glm::dvec3 centre = domain_.cell_centre(l, c);
            for (const glm::ivec3& f : kFaces) {
                if (has(l, c + f)) continue;
                const glm::dvec3 across = centre + glm::dvec3(f) * (0.5 * h + 0.5 * domain_.leaf_size / interior);
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

SeamMismatches count_seam_mismatches(const Scene& scene, const SceneBricks& bricks, const RenderBuffer& test,
                                     const RenderBuffer& reference) {
    test.check("test");
    reference.check("reference");
    const int interior = bricks.settings.layout().interior();
    std::vector<LeafCells> cells;
    SeamMismatches out;
    for (const construct::GeometryBuild& b : bricks.builds) {
        cells.emplace_back(b);
        out.seam_leaves += cells.back().seam_leaves(interior);
    }
    const reference::HostCamera camera = reference::make_host_camera(scene.camera, test.width, test.height);
    for (std::size_t i = 0; i < test.pixels(); ++i) {
        if (test.is_hit(i) == reference.is_hit(i) || (reference.aux[i].s[1] & SDF_REF_UNCONVERGED) != 0u) continue;
        const int x = static_cast<int>(i % test.width), y = static_cast<int>(i / test.width);
        const double t = test.is_hit(i) ? test.hit[i].s[3] : reference.hit[i].s[3];
        const glm::dvec3 world = camera.eye + t * camera.direction(x, y);
        bool seam = false;
        for (const Object& o : scene.objects)
            seam = seam || cells[o.geometry].near_seam(o.transform.inverse_apply(world), interior);
        ++(seam ? out.at_seams : out.elsewhere);
    }
    return out;
}

}  // namespace sdfbrick::render
