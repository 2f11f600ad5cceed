// Deterministic scene generator: `sdfbrick scene generate NAME --seed N`. The same name and seed
// give the same scene, byte for byte, on every machine (own RNG, values rounded to 4 decimals).
// The shipped scenes/*.json and scenes/stability/*.json were written by it with the default seed.
#pragma once

#include <cstdint>
#include <span>
#include <string_view>

#include "core/rng.h"
#include "scene/scene.h"

namespace sdfbrick {

inline constexpr std::uint64_t kDefaultSceneSeed = 1;

// Names: generated_scene_names(), the atlas's hard cases among them as "stability/NAME"
// (docs/stability.md). Unknown name -> InputError.
Scene generate_scene(std::string_view name, std::uint64_t seed = kDefaultSceneSeed);
std::span<const std::string_view> generated_scene_names();


}  // namespace sdfbrick
