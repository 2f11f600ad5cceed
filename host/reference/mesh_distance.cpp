#include "reference/mesh_distance.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace sdfbrick::reference {

namespace {

double segment_distance(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b) {
    const glm::dvec3 ab = b - a;
    const double len2 = glm::dot(ab, ab);
    const double t = len2 > 0.0 ? std::clamp(glm::dot(p - a, ab) / len2, 0.0, 1.0) : 0.0;
    return glm::length(p - (a + t * ab));
}

double triangle_distance(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
    const glm::dvec3 n = glm::cross(b - a, c - a);
    const double n2 = glm::dot(n, n);
    if (n2 > 0.0) {
        // The projection onto the plane, inside when it is on the inner side of all three edges.
        const glm::dvec3 q = p - (glm::dot(p - a, n) / n2) * n;
        const bool inside = glm::dot(glm::cross(b - a, q - a), n) >= 0.0 && glm::dot(glm::cross(c - b, q - b), n) >= 0.0 &&
                            glm::dot(glm::cross(a - c, q - c), n) >= 0.0;
        if (inside) return glm::length(p - q);
    }
    return std::min({segment_distance(p, a, b), segment_distance(p, b, c), segment_distance(p, c, a)});
}

}  // namespace

double mesh_unsigned_distance(const TriangleMesh& mesh, const glm::dvec3& p) {
    double best = std::numeric_limits<double>::infinity();
    for (const auto& t : mesh.triangles)
        best = std::min(best, triangle_distance(p, mesh.vertices[t[0]], mesh.vertices[t[1]], mesh.vertices[t[2]]));
    return best;
}

double winding_number(const TriangleMesh& mesh, const glm::dvec3& p) {
    // Solid angle of each triangle seen from p (Van Oosterom and Strackee 1983).
    double sum = 0.0;
    for (const auto& t : mesh.triangles) {
        const glm::dvec3 a = mesh.vertices[t[0]] - p, b = mesh.vertices[t[1]] - p, c = mesh.vertices[t[2]] - p;
        const double la = glm::length(a), lb = glm::length(b), lc = glm::length(c);
        const double num = glm::dot(a, glm::cross(b, c));
        const double den = la * lb * lc + glm::dot(a, b) * lc + glm::dot(b, c) * la + glm::dot(c, a) * lb;
        sum += 2.0 * std::atan2(num, den);
    }
    return sum / (4.0 * std::numbers::pi);
}

double grid_distance(const GridFrame& frame, const std::vector<float>& values, const glm::dvec3& p) {
    const glm::dvec3 top(frame.dims - 1);
    const glm::dvec3 u = (p - frame.origin) / frame.cell;
    const glm::dvec3 c = glm::clamp(u, glm::dvec3(0.0), top);
    const glm::dvec3 base = glm::min(glm::floor(c), top - 1.0), f = c - base;
    const auto at = [&](int i, int j, int k) {
        const glm::ivec3 q = glm::ivec3(base) + glm::ivec3(i, j, k);
        return static_cast<double>(values[static_cast<std::size_t>(q.x) +
                                          static_cast<std::size_t>(frame.dims.x) *
                                              (static_cast<std::size_t>(q.y) + static_cast<std::size_t>(frame.dims.y) * q.z)]);
    };
    double v = 0.0;
    for (int n = 0; n < 8; ++n) {
        const int i = n & 1, j = (n >> 1) & 1, k = (n >> 2) & 1;
        v += (i ? f.x : 1.0 - f.x) * (j ? f.y : 1.0 - f.y) * (k ? f.z : 1.0 - f.z) * at(i, j, k);
    }
    return v + glm::length(u - c) * frame.cell;
}

double mesh_signed_distance(const TriangleMesh& mesh, const glm::dvec3& p) {
    const double d = mesh_unsigned_distance(mesh, p);
    return winding_number(mesh, p) > 0.5 ? -d : d;
}

}  // namespace sdfbrick::reference
