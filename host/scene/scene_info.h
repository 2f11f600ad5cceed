// What `sdfbrick scene info` reports about a scene: edits per geometry, primitive and operation
// histograms, bounds; with --bricks, the surface cells a host reference counts. A plain struct with
// one JSON and one text form.
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "scene/scene.h"

namespace sdfbrick {

// The surface cells of a geometry at a leaf size (filled by the caller: the count is a reference's).
struct SurfaceCells {
    double leaf_size = 0.0;
    int branching = 4;
    int levels = 0;
    std::vector<std::uint64_t> per_level;  // kept cells per level; the last is the leaves
    double seconds = 0.0;
};

struct GeometrySummary {
    std::string name;
    std::size_t edits = 0, smooth_edits = 0, animated_edits = 0;
    std::map<std::string, int> primitives, ops;  // every primitive and op, with its count (0 too)
    double max_blend = 0.0, max_lipschitz = 1.0;
    Aabb bounds;
    std::optional<SurfaceCells> surface_cells;
};

struct ObjectSummary {
    std::string name, geometry;
    double scale = 1.0;
    Aabb bounds;
};

struct SceneSummary {
    std::string file;  // where the scene was read from; "" = not said
    std::string name;
    double time = 0.0;
    std::vector<GeometrySummary> geometries;
    std::vector<ObjectSummary> objects;
    Aabb bounds;  // the world's: every object's
    glm::dvec3 eye{0.0}, target{0.0};
    double fov_deg = 0.0;
};

// The scene as evaluated at its own time (animation applied).
SceneSummary scene_summary(const Scene& scene);
// {"name", "time", "geometries", "objects", "bounds", "camera"} and "file" when set.
nlohmann::json to_json(const SceneSummary& s);
std::string to_text(const SceneSummary& s);

nlohmann::json to_json(const Aabb& b);

}  // namespace sdfbrick
