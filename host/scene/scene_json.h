// The scene file: JSON <-> Scene. docs/scene-format.md is the reference for the format.
// Every error is an InputError whose one-line message names the file and the JSON path
// ("scenes/a.json: /geometries/0/edits/3/radius: must be > 0, got -1") or, for syntax errors,
// the line and column.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "scene/scene.h"

namespace sdfbrick {

inline constexpr int kSceneFormatVersion = 1;

// Every number of a scene file lies in [-kSceneNumberLimit, kSceneNumberLimit]: far below SDF_FAR
// (1e20) and float's range even after scaling, animation and squaring, so that no bound, blend
// constant or distance the kernels compute overflows.
inline constexpr double kSceneNumberLimit = 1e6;

// Mesh files that a scene names are read relative to the scene file's folder (parse_scene: `base`)
// and must lie in it (a symbolic link counts where it leads) or in a folder allow_mesh_folders
// names; any other is refused with an InputError naming the place in the scene.
Scene load_scene(const std::filesystem::path& path);
// `origin` names the source in error messages (a file name, or "<string>").
Scene parse_scene(std::string_view text, std::string_view origin, const std::filesystem::path& base = {});
// The same from parsed JSON (a document made in memory): the same checks and messages, the JSON path
// after origin.
Scene scene_from_json(const nlohmann::json& j, std::string_view origin, const std::filesystem::path& base = {});

// One edit object as a scene file's geometries hold it (not a mesh or level set), with the scene's
// checks; errors name origin and the JSON path below `path` ("log.jsonl:3: /edit/radius: ...").
Edit edit_from_json(const nlohmann::json& j, std::string_view origin, std::string_view path);

// Folders outside a scene's own folder whose mesh files every later scene read may use (replaces
// the earlier list; the CLI's --allow-outside).
void allow_mesh_folders(std::vector<std::filesystem::path> folders);

nlohmann::json scene_to_json(const Scene& s);
// Readable text: one edit per line, short arrays inline.
std::string format_scene(const Scene& s);
void save_scene(const Scene& s, const std::filesystem::path& path);

// Any JSON file (sweep files, reports), with the scene loader's error messages (file, JSON path,
// line and column).
nlohmann::json parse_json_text(std::string_view text, std::string_view origin);
nlohmann::json load_json(const std::filesystem::path& path);

// JSON text with scalar arrays and small flat objects on one line (used for scenes and reports).
std::string format_json(const nlohmann::json& j, int indent = 2);

}  // namespace sdfbrick
