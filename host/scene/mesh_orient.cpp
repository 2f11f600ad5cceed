#include "scene/mesh_orient.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "core/errors.h"

namespace sdfbrick {

namespace {

using Tri = std::array<std::uint32_t, 3>;
constexpr std::uint32_t kNone = 0xffffffffu;

// For every triangle and each of its edges (corner e to e + 1), the other triangle on that edge.
std::vector<Tri> edge_neighbours(const TriangleMesh& m) {
    struct Half {
        std::uint64_t key;
        std::uint32_t tri;
        std::uint32_t edge;
    };
    std::vector<Half> halves;
    halves.reserve(3 * m.triangles.size());
    for (std::uint32_t t = 0; t < m.triangles.size(); ++t)
        for (std::uint32_t e = 0; e < 3; ++e) {
            const std::uint32_t a = m.triangles[t][e], b = m.triangles[t][(e + 1) % 3];
            halves.push_back({std::uint64_t{std::min(a, b)} << 32 | std::max(a, b), t, e});
        }
    std::sort(halves.begin(), halves.end(), [](const Half& x, const Half& y) {
        return x.key != y.key ? x.key < y.key : x.tri < y.tri;
    });
    std::vector<Tri> out(m.triangles.size(), Tri{kNone, kNone, kNone});
    for (std::size_t i = 0; i + 1 < halves.size(); i += 2) {
        if (halves[i].key != halves[i + 1].key || (i + 2 < halves.size() && halves[i + 2].key == halves[i].key))
            throw std::invalid_argument("orient: the mesh is not closed and manifold");
        out[halves[i].tri][halves[i].edge] = halves[i + 1].tri;
        out[halves[i + 1].tri][halves[i + 1].edge] = halves[i].tri;
    }
    return out;
}

// Whether triangle u runs t's edge e (corner e to e + 1) the same way as t does (then one of the
// two must turn for the pair to agree).
bool runs_alike(const Tri& t, std::uint32_t e, const Tri& u) {
    const std::uint32_t a = t[e], b = t[(e + 1) % 3];
    for (int k = 0; k < 3; ++k)
        if (u[k] == a && u[(k + 1) % 3] == b) return true;
    return false;
}

struct Components {
    std::vector<std::uint32_t> of;          // component of each triangle
    std::vector<std::uint8_t> turn;         // whether the triangle turns to agree with its component's first
    std::vector<std::uint32_t> first;       // first triangle of each component
};

// Spreads the first triangle's winding over each component by shared edges.
Components consistent_components(const TriangleMesh& m) {
    const std::vector<Tri> nb = edge_neighbours(m);
    const std::size_t n = m.triangles.size();
    Components c{std::vector<std::uint32_t>(n, kNone), std::vector<std::uint8_t>(n, 0), {}};
    std::vector<std::uint32_t> queue;
    for (std::uint32_t seed = 0; seed < n; ++seed) {
        if (c.of[seed] != kNone) continue;
        const auto id = static_cast<std::uint32_t>(c.first.size());
        c.first.push_back(seed);
        c.of[seed] = id;
        queue.assign(1, seed);
        while (!queue.empty()) {
            const std::uint32_t t = queue.back();
            queue.pop_back();
            for (std::uint32_t e = 0; e < 3; ++e) {
                const std::uint32_t u = nb[t][e];
                const auto want = static_cast<std::uint8_t>(c.turn[t] ^ runs_alike(m.triangles[t], e, m.triangles[u]));
                if (c.of[u] == kNone) {
                    c.of[u] = id;
                    c.turn[u] = want;
                    queue.push_back(u);
                } else if (c.turn[u] != want) {
                    throw InputError(fmt::format("the mesh cannot be oriented: triangle {} cannot agree with all its "
                                                 "neighbours (a one-sided surface has no inside)", u));
                }
            }
        }
    }
    return c;
}

// The triangle as its component winds it.
Tri wound(const TriangleMesh& m, const Components& c, std::uint32_t t) {
    const Tri& x = m.triangles[t];
    return c.turn[t] ? Tri{x[0], x[2], x[1]} : x;
}

struct ComponentShape {
    double volume = 0.0;  // signed, as the component's first triangle winds it
    Aabb box;
    std::vector<std::uint32_t> triangles;
};

std::vector<ComponentShape> shapes(const TriangleMesh& m, const Components& c) {
    std::vector<ComponentShape> s(c.first.size());
    for (std::uint32_t t = 0; t < m.triangles.size(); ++t) s[c.of[t]].triangles.push_back(t);
    for (std::size_t k = 0; k < s.size(); ++k) {
        const glm::dvec3 o = m.vertices[m.triangles[c.first[k]][0]];  // near the component: less cancellation
        for (std::uint32_t t : s[k].triangles) {
            const Tri w = wound(m, c, t);
            const glm::dvec3 a = m.vertices[w[0]] - o, b = m.vertices[w[1]] - o, d = m.vertices[w[2]] - o;
            s[k].volume += glm::dot(a, glm::cross(b, d)) / 6.0;
            for (std::uint32_t v : w) s[k].box.grow(m.vertices[v]);
        }
        if (!(std::abs(s[k].volume) > 0.0) || !std::isfinite(s[k].volume))
            throw InputError(fmt::format("the mesh's part from triangle {} ({} triangles) encloses no volume: its inside "
                                         "is not defined", c.first[k], s[k].triangles.size()));
    }
    return s;
}

// |winding number| of a component about p, above 1/2: p lies inside it.
bool encloses(const TriangleMesh& m, const ComponentShape& s, const glm::dvec3& p) {
    double sum = 0.0;  // solid angles (Van Oosterom and Strackee 1983)
    for (std::uint32_t t : s.triangles) {
        const Tri& x = m.triangles[t];  // the sign of each term may be off; consistently so within s
        const glm::dvec3 a = m.vertices[x[0]] - p, b = m.vertices[x[1]] - p, d = m.vertices[x[2]] - p;
        const double la = glm::length(a), lb = glm::length(b), ld = glm::length(d);
        const double num = glm::dot(a, glm::cross(b, d));
        const double den = la * lb * ld + glm::dot(a, b) * ld + glm::dot(b, d) * la + glm::dot(d, a) * lb;
        sum += 2.0 * std::atan2(num, den);
    }
    return std::abs(sum) > 2.0 * std::numbers::pi;
}

bool box_within(const Aabb& inner, const Aabb& outer) {
    return glm::all(glm::greaterThanEqual(inner.lo, outer.lo)) && glm::all(glm::lessThanEqual(inner.hi, outer.hi));
}

}  // namespace

std::string MeshOrientation::describe() const {
    std::vector<std::string> parts;
    if (turned_components > 0)
        parts.push_back(fmt::format("{} of {} parts turned to face {}", turned_components, components,
                                    cavities > 0 ? "outward (cavities inward)" : "outward"));
    if (against_neighbours > 0)
        parts.push_back(fmt::format("{} triangles turned to agree with their neighbours", against_neighbours));
    if (parts.empty()) return "";
    return fmt::format("triangles wound inward or inconsistently were turned ({}; {} triangles in all)",
                       fmt::join(parts, ", "), turned_triangles);
}

MeshOrientation orient(TriangleMesh& m) {
    const Components c = consistent_components(m);
    const std::vector<ComponentShape> s = shapes(m, c);
    MeshOrientation out;
    out.components = s.size();
    std::vector<std::uint8_t> whole(s.size(), 0);  // the component's winding (as its first triangle) turns
    for (std::size_t k = 0; k < s.size(); ++k) {
        // Nesting: bounds tested first, so that the winding number runs only over candidates.
        const glm::dvec3 p = m.vertices[m.triangles[c.first[k]][0]];
        std::size_t depth = 0;
        for (std::size_t j = 0; j < s.size(); ++j)
            if (j != k && box_within(s[k].box, s[j].box) && encloses(m, s[j], p)) ++depth;
        const bool cavity = depth % 2 == 1;
        out.cavities += cavity;
        whole[k] = (s[k].volume < 0.0) != cavity;
    }
    std::vector<std::size_t> turned(s.size(), 0);
    for (std::uint32_t t = 0; t < m.triangles.size(); ++t) {
        if ((c.turn[t] ^ whole[c.of[t]]) == 0) continue;
        std::swap(m.triangles[t][1], m.triangles[t][2]);
        ++turned[c.of[t]];
        ++out.turned_triangles;
    }
    for (std::size_t k = 0; k < s.size(); ++k) {
        const std::size_t kept = s[k].triangles.size() - turned[k];  // a mixed part: the fewer ones disagreed
        if (turned[k] > kept) ++out.turned_components;
        out.against_neighbours += std::min(turned[k], kept);
    }
    return out;
}

void reverse_winding(TriangleMesh& mesh) {
    for (auto& t : mesh.triangles) std::swap(t[1], t[2]);
}

}  // namespace sdfbrick
