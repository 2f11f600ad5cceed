// What `sdfbrick scene info` reports about a scene: edits per geometry, primitive and operation
// histograms, bounds. JSON first; the text form is made from the JSON.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "scene/scene.h"

namespace sdfbrick {

// The scene as evaluated at its own time (animation applied).
nlohmann::json scene_summary(const Scene& scene);
std::string scene_summary_text(const nlohmann::json& summary);

nlohmann::json to_json(const Aabb& b);

}  // namespace sdfbrick
