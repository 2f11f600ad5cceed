#include "exchange/vdb.h"

#include <chrono>
#include <cmath>
#include <functional>
#include <map>
#include <unordered_set>
#include <utility>

#include <glm/gtc/quaternion.hpp>

#include <fmt/format.h>

#include "core/errors.h"
#include "core/files.h"

#if SDFBRICK_WITH_OPENVDB
#include <openvdb/openvdb.h>
#include <openvdb/tools/SignedFloodFill.h>
#endif
#if SDFBRICK_WITH_NANOVDB
#include <nanovdb/util/GridBuilder.h>
#include <nanovdb/util/IO.h>
#endif

namespace sdfbrick::exchange {

std::string_view to_string(VdbFormat f) { return f == VdbFormat::openvdb ? "OpenVDB" : "NanoVDB"; }

bool vdb_available(VdbFormat f) {
#if SDFBRICK_WITH_OPENVDB
    if (f == VdbFormat::openvdb) return true;
#endif
#if SDFBRICK_WITH_NANOVDB
    if (f == VdbFormat::nanovdb) return true;
#endif
    (void)f;
    return false;
}

double grid_bytes_per_brick(const construct::BrickLayout& layout, VdbFormat f) {
    const double voxels = std::pow(static_cast<double>(layout.interior()), 3.0);
    return voxels * (f == VdbFormat::openvdb ? 12.0 : 24.0);
}

void require_vdb(VdbFormat f) {
    if (vdb_available(f)) return;
    const bool open = f == VdbFormat::openvdb;
    throw InputError(fmt::format("this sdfbrick was built without {} ({}): install it and configure with {}=ON to "
                                 "write {} files",
                                 to_string(f), open ? "libopenvdb-dev" : "libnanovdb-dev",
                                 open ? "-DSDFBRICK_WITH_OPENVDB" : "-DSDFBRICK_WITH_NANOVDB", open ? ".vdb" : ".nvdb"));
}

namespace {

// A finest-level brick: its interior samples, and its apron samples on voxels that no leaf's cell
// holds (the first brick that has one), each voxel once.
void finest_brick_voxels(const HostBricks& bricks, std::size_t b, float s,
                         std::unordered_set<glm::ivec3, CoordHash>& apron_taken,
                         const std::function<void(const VdbVoxel&)>& visit) {
    const int n = bricks.samples(), a = bricks.apron(), interior = bricks.interior();
    const glm::ivec3 first = bricks.coord(b) * interior - a;
    for (int k = 0; k < n; ++k)
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                const VdbVoxel v{first + glm::ivec3(i, j, k), bricks.sample(b, i, j, k) * s};
                const bool owned =
                    i >= a && i < a + interior && j >= a && j < a + interior && k >= a && k < a + interior;
                if (owned) {
                    visit(v);
                    continue;
                }
                const glm::dvec3 cell = glm::floor(glm::dvec3(v.ijk) / static_cast<double>(interior));
                if (!bricks.covering(glm::ivec3(cell)) && apron_taken.insert(v.ijk).second) visit(v);
            }
}

// A coarser leaf (adaptive builds) on the finest voxel lattice: every finest voxel inside its cell
// whose trilinear value lies within the finest band. A coarse voxel whose 27 neighbouring samples
// are all at least the band deep on one side holds no such voxel (trilinear values stay within
// their corners' range) and is skipped whole.
void coarse_brick_voxels(const HostBricks& bricks, std::size_t b, float s,
                         const std::function<void(const VdbVoxel&)>& visit) {
    const int a = bricks.apron(), interior = bricks.interior(), fine = 1 << bricks.shift(b);
    const float band = static_cast<float>(bricks.band());
    const glm::ivec3 base = bricks.coord(b) * interior;  // first interior voxel, this level's lattice
    for (int k = 0; k < interior; ++k)
        for (int j = 0; j < interior; ++j)
            for (int i = 0; i < interior; ++i) {
                float lo = INFINITY, hi = -INFINITY;
                for (int n = 0; n < 27; ++n) {
                    const float v = bricks.sample(b, a + i + n % 3 - 1, a + j + n / 3 % 3 - 1, a + k + n / 9 - 1);
                    lo = std::min(lo, v);
                    hi = std::max(hi, v);
                }
                if (lo >= band || hi <= -band) continue;
                const glm::ivec3 first = (base + glm::ivec3(i, j, k)) * fine;
                for (int z = 0; z < fine; ++z)
                    for (int y = 0; y < fine; ++y)
                        for (int x = 0; x < fine; ++x) {
                            const glm::ivec3 ijk = first + glm::ivec3(x, y, z);
                            const glm::dvec3 p =
                                bricks.origin() + (glm::dvec3(ijk) + 0.5) * bricks.voxel();
                            const double d = bricks.at(b, p).distance;  // p lies in b's cell
                            if (std::abs(d) < band) visit({ijk, static_cast<float>(d) * s});
                        }
            }
}

}  // namespace

void for_each_level_set_voxel(const HostBricks& bricks, double scale, const std::function<void(const VdbVoxel&)>& visit) {
    const float s = static_cast<float>(scale);
    std::unordered_set<glm::ivec3, CoordHash> apron_taken;  // apron voxels that no brick owns, once
    for (std::size_t b = 0; b < bricks.brick_count(); ++b) {
        if (bricks.shift(b) == 0)
            finest_brick_voxels(bricks, b, s, apron_taken, visit);
        else
            coarse_brick_voxels(bricks, b, s, visit);
    }
}

IndexToWorld index_to_world(const HostBricks& bricks, const Transform& object) {
    // world = R (s p) + t with p = origin + (ijk + 0.5) voxel.
    const glm::dmat3 r = glm::mat3_cast(object.rotation);
    const double step = object.scale * bricks.voxel();
    IndexToWorld m;
    for (int axis = 0; axis < 3; ++axis) m.axis[axis] = r[axis] * step;
    m.origin = object.apply(bricks.origin() + 0.5 * bricks.voxel());
    return m;
}

namespace {

// One object's grid: what it is called and where its samples come from.
struct ObjectGrid {
    VdbGridRecord record;
    std::size_t geometry = 0;
    const Object* object = nullptr;
};

std::vector<ObjectGrid> object_grids(const Scene& scene, std::span<const HostBricks> bricks) {
    std::vector<ObjectGrid> out;
    std::map<std::string, int> uses;
    for (std::size_t o = 0; o < scene.objects.size(); ++o) {
        const Object& obj = scene.objects[o];
        const HostBricks& b = bricks[obj.geometry];
        if (b.brick_count() == 0) continue;
        ObjectGrid g;
        std::string name = obj.name.empty() ? fmt::format("object {}", o) : obj.name;
        const int seen = uses[name]++;
        g.record.name = seen == 0 ? name : fmt::format("{}#{}", name, seen);
        g.record.geometry = scene.geometries[obj.geometry].name;
        g.record.voxel_size = b.voxel() * obj.transform.scale;
        g.record.background = b.band() * obj.transform.scale;
        g.record.quantum = b.quantum() * obj.transform.scale;
        g.geometry = obj.geometry;
        g.object = &obj;
        out.push_back(std::move(g));
    }
    return out;
}

#if SDFBRICK_WITH_OPENVDB
openvdb::FloatTree::Ptr openvdb_tree(const HostBricks& b, double scale) {
    auto tree = std::make_shared<openvdb::FloatTree>(static_cast<float>(b.band() * scale));
    openvdb::tree::ValueAccessor<openvdb::FloatTree> acc(*tree);
    for_each_level_set_voxel(
        b, scale, [&](const VdbVoxel& v) { acc.setValueOn(openvdb::Coord(v.ijk.x, v.ijk.y, v.ijk.z), v.value); });
    openvdb::tools::signedFloodFill(*tree);
    return tree;
}

// OpenVDB's archive writer, given a stream of ours: io::File would open the path itself, unchecked.
class StreamArchive : public openvdb::io::Archive {
public:
    void write_to(std::ostream& os, const openvdb::GridPtrVec& grids) const { Archive::write(os, grids, /*seekable=*/true); }
};

Output openvdb_output(const Scene& scene, std::span<const HostBricks> bricks, std::vector<ObjectGrid>& grids,
                      const std::filesystem::path& path) {
    openvdb::initialize();
    openvdb::GridPtrVec out;
    std::map<std::pair<std::size_t, double>, openvdb::FloatTree::Ptr> trees;  // (geometry, scale): shared
    for (ObjectGrid& g : grids) {
        const HostBricks& b = bricks[g.geometry];
        auto& tree = trees[{g.geometry, g.object->transform.scale}];
        if (!tree) tree = openvdb_tree(b, g.object->transform.scale);
        openvdb::FloatGrid::Ptr grid = openvdb::FloatGrid::create(tree);
        const IndexToWorld m = index_to_world(b, g.object->transform);
        openvdb::math::Mat4d mat = openvdb::math::Mat4d::identity();
        for (int j = 0; j < 3; ++j)
            for (int i = 0; i < 3; ++i) mat[j][i] = m.axis[j][i];
        for (int i = 0; i < 3; ++i) mat[3][i] = m.origin[i];
        grid->setTransform(openvdb::math::Transform::createLinearTransform(mat));
        grid->setName(g.record.name);
        grid->setGridClass(openvdb::GRID_LEVEL_SET);
        grid->setSaveFloatAsHalf(false);
        grid->insertMeta("sdfbrick_scene", openvdb::StringMetadata(scene.name));
        grid->insertMeta("sdfbrick_geometry", openvdb::StringMetadata(g.record.geometry));
        grid->insertMeta("sdfbrick_quantisation_step", openvdb::DoubleMetadata(g.record.quantum));
        g.record.active_voxels = grid->activeVoxelCount();
        out.push_back(grid);
    }
    return {path, [out](std::ostream& os) { StreamArchive().write_to(os, out); }};
}
#endif

#if SDFBRICK_WITH_NANOVDB
Output nanovdb_output(std::span<const HostBricks> bricks, std::vector<ObjectGrid>& grids, const std::filesystem::path& path) {
    auto handles = std::make_shared<std::vector<nanovdb::GridHandle<nanovdb::HostBuffer>>>();
    for (ObjectGrid& g : grids) {
        const HostBricks& b = bricks[g.geometry];
        nanovdb::GridBuilder<float> builder(static_cast<float>(g.record.background), nanovdb::GridClass::LevelSet);
        auto acc = builder.getAccessor();
        for_each_level_set_voxel(b, g.object->transform.scale, [&](const VdbVoxel& v) {
            acc.setValue(nanovdb::Coord(v.ijk.x, v.ijk.y, v.ijk.z), v.value);
        });
        builder.sdfToLevelSet();
        const IndexToWorld m = index_to_world(b, g.object->transform);
        const glm::dmat3 forward(m.axis[0], m.axis[1], m.axis[2]);
        const glm::dmat3 inverse = glm::inverse(forward);
        double mat[3][3], inv[3][3];
        for (int j = 0; j < 3; ++j)
            for (int i = 0; i < 3; ++i) {
                mat[j][i] = forward[j][i];
                inv[j][i] = inverse[j][i];
            }
        nanovdb::Map map;
        map.set(mat, inv, nanovdb::Vec3d(m.origin.x, m.origin.y, m.origin.z), 1.0);
        handles->push_back(builder.getHandle(map, g.record.name));
        g.record.active_voxels = handles->back().grid<float>()->activeVoxelCount();
    }
    return {path, [handles](std::ostream& os) { nanovdb::io::writeGrids(os, *handles); }};
}
#endif

}  // namespace

VdbFile make_vdb(const Scene& scene, std::span<const HostBricks> bricks, const std::filesystem::path& path,
                 VdbFormat format) {
    require_vdb(format);
    const auto start = std::chrono::steady_clock::now();
    std::vector<ObjectGrid> grids = object_grids(scene, bricks);
    if (grids.empty())
        throw InputError(fmt::format("{}: nothing to write: no object of scene \"{}\" has a brick (no surface lies within "
                                     "its geometry's bounds at this leaf size)",
                                     path.string(), scene.name));
    VdbFile file;
    file.record.format = format;
    file.record.path = path;
#if SDFBRICK_WITH_OPENVDB
    if (format == VdbFormat::openvdb) file.output = openvdb_output(scene, bricks, grids, path);
#endif
#if SDFBRICK_WITH_NANOVDB
    if (format == VdbFormat::nanovdb) file.output = nanovdb_output(bricks, grids, path);
#endif
    // Count the bytes as they are written: the file's size, also where the path is a special file.
    file.output.write = [write = std::move(file.output.write), bytes = file.bytes](std::ostream& os) {
        const std::streampos begin = os.tellp();
        write(os);
        const std::streampos end = os.tellp();
        *bytes = begin >= 0 && end >= begin ? static_cast<std::uint64_t>(end - begin) : 0;
    };
    file.record.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    for (ObjectGrid& g : grids) file.record.grids.push_back(std::move(g.record));
    return file;
}

VdbExport write_vdb(const Scene& scene, std::span<const HostBricks> bricks, const std::filesystem::path& path,
                    VdbFormat format) {
    VdbFile file = make_vdb(scene, bricks, path, format);
    write_all({file.output});
    return file.written();
}

}  // namespace sdfbrick::exchange
