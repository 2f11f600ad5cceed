// Point sampling of a brick set: the distance and gradient that the bricks give at world points,
// beside the double-precision reference field (reference/reference_field.h) at the same points.
// What a user needs to check bricks against another tool, or to use them for collision queries.
#pragma once

#include <cstddef>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "exchange/host_bricks.h"
#include "scene/scene.h"

namespace sdfbrick::exchange {

// Points from a file: CSV (extension .csv: one "x,y,z" a line, blank lines and one header line
// allowed) or else binary float32 x y z triples (little-endian, 12 bytes a point). Throws InputError
// naming the file and the line or point for an empty, unreadable or malformed file or a coordinate
// that is not finite.
std::vector<glm::dvec3> read_points(const std::filesystem::path& path);

struct PointSample {
    glm::dvec3 point{0.0};
    // The brick set's world distance: the least over the objects whose leaf bricks hold the point
    // (an object without a brick there lies beyond its band); nullopt when no object's bricks do.
    std::optional<double> distance;
    glm::dvec3 gradient{0.0};  // world gradient of the brick field of that object (0 without a distance)
    int object = -1;           // the object that gave the distance
    bool saturated = false;    // the distance is the object's band: the true one may be larger in magnitude
    double reference = 0.0;    // the reference field at the point (world units)
};

// bricks[g]: geometry g's brick set; scene at the time the bricks were built.
std::vector<PointSample> sample_points(const Scene& scene, std::span<const HostBricks> bricks,
                                       std::span<const glm::dvec3> points);

// CSV with the header x,y,z,distance,gx,gy,gz,object,saturated,reference; a point outside every
// brick has empty distance and gradient cells and object -1.
std::string samples_csv(std::span<const PointSample> samples);

}  // namespace sdfbrick::exchange
