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

// Names: spheres, drops, cubes, rain, fractal, board, thin, and the stability atlas's hard cases
// "stability/NAME" (docs/stability.md); generated_scene_names() lists them all. Unknown name ->
// InputError.
Scene generate_scene(std::string_view name, std::uint64_t seed = kDefaultSceneSeed);
std::span<const std::string_view> generated_scene_names();


}  // namespace sdfbrick
