#include "core/rng.h"

#include <cmath>

namespace sdfbrick {

std::uint64_t Rng::next() {
    std::uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

double Rng::uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }

double Rng::uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }

glm::dvec3 Rng::in_box(const glm::dvec3& lo, const glm::dvec3& hi) {
    // One draw per statement: argument evaluation order is unspecified.
    const double x = uniform(lo.x, hi.x);
    const double y = uniform(lo.y, hi.y);
    const double z = uniform(lo.z, hi.z);
    return {x, y, z};
}

glm::dvec3 Rng::unit_vector() {
    for (;;) {
        const glm::dvec3 v = in_box(glm::dvec3(-1.0), glm::dvec3(1.0));
        const double l2 = v.x * v.x + v.y * v.y + v.z * v.z;
        if (l2 > 1e-6 && l2 <= 1.0) return v / std::sqrt(l2);
    }
}

glm::dquat Rng::rotation() {
    const double u1 = uniform();
    const double u2 = uniform() * 2.0 * M_PI;
    const double u3 = uniform() * 2.0 * M_PI;
    const double a = std::sqrt(1.0 - u1), b = std::sqrt(u1);
    return glm::dquat(b * std::cos(u3), a * std::sin(u2), a * std::cos(u2), b * std::sin(u3));
}

}  // namespace sdfbrick
