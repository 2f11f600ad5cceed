// Level sets in: a narrow-band signed distance grid from an OpenVDB (.vdb) or NanoVDB (.nvdb) file
// (Houdini, Blender, OpenVDB's tools, `sdfbrick export`) as an edit, placed and combined like any
// other. It becomes the same dense grid a mesh edit samples (scene/mesh.h, GridFrame): the grid's
// active bounds plus one voxel, each point the file's value (inactive voxels read +-background, the
// band's width, which never exceeds the true distance there). A grid whose voxel axes are rotated is
// resampled (trilinear, in index space) onto an axis-aligned grid of the same voxel size.
#pragma once

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "scene/mesh.h"

namespace sdfbrick {

// Most points a level set's dense grid may hold (4 bytes each).
inline constexpr std::size_t kMaxLevelSetPoints = std::size_t{1} << 28;

struct LevelSetGrid {
    std::string grid;  // the grid's name in the file
    GridFrame frame;
    std::vector<float> values;  // frame.points(), i fastest
};

// Whether this build reads .vdb (OpenVDB) and .nvdb (NanoVDB) files.
bool level_set_format_available(const std::filesystem::path& path);

// Reads grid `grid` of the file (the file's only grid when `grid` is empty). Throws InputError naming
// the file and the grid for: a file that cannot be read, no grid of that name (the names it holds
// listed), a grid of another value type than float, a grid that is not a level set (a fog volume:
// its class), a transform that is not a uniform scale plus rotation and translation, no active
// voxel, or a dense grid over more than kMaxLevelSetPoints points or kMaxGridCells cells along an
// axis; and for a build without the format's library (naming the package).
LevelSetGrid read_level_set(const std::filesystem::path& path, const std::string& grid);

// The scene's source for a level-set edit: values preset, no triangles (MeshSource::level_set()).
std::shared_ptr<MeshSource> make_level_set_source(LevelSetGrid grid, std::string file);

}  // namespace sdfbrick
