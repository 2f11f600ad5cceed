// SplitMix64 random numbers: small, fast, and the same sequence for a seed on every platform
// (std:: distributions are implementation-defined). Used by the scene generator and the tests.
#pragma once

#include <cstdint>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

namespace sdfbrick {

class Rng {
public:
    explicit Rng(std::uint64_t seed) : state_(seed) {}
    std::uint64_t next();
    double uniform();                      // [0, 1), 53 bits
    double uniform(double lo, double hi);  // [lo, hi)
    glm::dvec3 in_box(const glm::dvec3& lo, const glm::dvec3& hi);
    glm::dvec3 unit_vector();              // uniform on the unit sphere
    glm::dquat rotation();                 // uniform unit quaternion (Shoemake)

private:
    std::uint64_t state_;
};

}  // namespace sdfbrick
