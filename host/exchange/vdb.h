// Brick sets out to OpenVDB (.vdb) and NanoVDB (.nvdb): one narrow-band level-set FloatGrid per
// object, in world units. Each object's grid holds its geometry's leaf samples (the interior voxels
// of every brick, and apron voxels that no brick owns) times the object's scale, on the geometry's
// voxel lattice placed by the object's transform (rotation, uniform scale and translation are an
// affine index-to-world map, so nothing is resampled). Background = the stored band in world units,
// inactive voxels signed by flood fill, class level set. Objects that instance one geometry at one
// scale share one tree in the OpenVDB file (it writes the tree once).
//
// OpenVDB needs SDFBRICK_WITH_OPENVDB (libopenvdb-dev), NanoVDB SDFBRICK_WITH_NANOVDB (libnanovdb-dev);
// without one, writing that format throws InputError naming the missing package.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "core/files.h"
#include "exchange/host_bricks.h"
#include "scene/scene.h"

namespace sdfbrick::exchange {

enum class VdbFormat { openvdb, nanovdb };
std::string_view to_string(VdbFormat f);  // "OpenVDB", "NanoVDB"
bool vdb_available(VdbFormat f);           // compiled in
// Throws InputError naming the missing dependency when f is not compiled in.
void require_vdb(VdbFormat f);

// One voxel of a level-set grid: its index coordinate and world distance.
struct VdbVoxel {
    glm::ivec3 ijk{0};
    float value = 0.0f;
};

// Index -> world of an object's grid, in the row-vector convention of OpenVDB and NanoVDB:
// world = i * axis[0] + j * axis[1] + k * axis[2] + origin.
struct IndexToWorld {
    glm::dvec3 axis[3];
    glm::dvec3 origin{0.0};
};

// Visits the voxels of a geometry's brick set on its finest voxel lattice, distances times scale, in
// brick (Morton) order: every finest brick's interior samples, and its apron samples on voxels no
// leaf's cell holds (the first brick that has one), each voxel once; a coarser leaf of an adaptive
// build gives the finest voxels in its cell where its trilinear field is within the finest band.
// Streams: nothing the size of the set is held.
void for_each_level_set_voxel(const HostBricks& bricks, double scale, const std::function<void(const VdbVoxel&)>& visit);
// Voxel (i, j, k) of the geometry lattice sits at origin + (ijk + 0.5) * voxel in the geometry frame.
IndexToWorld index_to_world(const HostBricks& bricks, const Transform& object);

struct VdbGridRecord {
    std::string name;      // the object's name ("object N" when it has none; "#N" added to repeats)
    std::string geometry;  // the geometry it instances
    std::uint64_t active_voxels = 0;
    double voxel_size = 0.0;   // world units
    double background = 0.0;   // world units: the band times the object's scale
    double quantum = 0.0;      // one quantisation step in world units (0 for float samples)
};

struct VdbExport {
    VdbFormat format = VdbFormat::openvdb;
    std::filesystem::path path;
    std::vector<VdbGridRecord> grids;
    std::uint64_t file_bytes = 0;
    double ms = 0.0;  // host wall time of making the grids in memory
};

// A level-set file made in memory, ready to write: what it holds and the output that writes it
// (with other outputs of a command through one write_all).
struct VdbFile {
    VdbExport record;
    Output output;
    std::shared_ptr<std::uint64_t> bytes = std::make_shared<std::uint64_t>(0);  // set as the output is written

    // The record with the size of the file as written.
    VdbExport written() const {
        VdbExport r = record;
        r.file_bytes = *bytes;
        return r;
    }
};

// Makes one grid per object of scene (at its time); bricks[g] is geometry g's brick set. Objects
// whose geometry has no brick are left out; a scene with no brick at all is refused (InputError).
// About the host bytes the grids of format f take per leaf brick of this layout while they are made
// (each interior voxel a float in a tree with its masks and partly filled leaf nodes; NanoVDB's
// builder tree and its finished grid at once): generous, for refusing an export that cannot fit.
double grid_bytes_per_brick(const construct::BrickLayout& layout, VdbFormat f);

VdbFile make_vdb(const Scene& scene, std::span<const HostBricks> bricks, const std::filesystem::path& path,
                 VdbFormat format);

// make_vdb, then write_all of that one file.
VdbExport write_vdb(const Scene& scene, std::span<const HostBricks> bricks, const std::filesystem::path& path,
                    VdbFormat format);

}  // namespace sdfbrick::exchange
