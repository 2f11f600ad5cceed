#include "scene/level_set.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <stdexcept>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "core/errors.h"
#include "core/quote.h"

#if SDFBRICK_WITH_OPENVDB
#include <openvdb/openvdb.h>
#endif
#if SDFBRICK_WITH_NANOVDB
#include <nanovdb/util/IO.h>
#endif

namespace sdfbrick {

namespace {

bool is_nanovdb(const std::filesystem::path& path) { return path.extension() == ".nvdb"; }

// A level set as both libraries give it: its active index bounds, index -> world (world = origin +
// i axis[0] + j axis[1] + k axis[2]) and the value at any index.
struct IndexGrid {
    std::string name;
    glm::dvec3 origin{0.0};
    std::array<glm::dvec3, 3> axis{};
    glm::ivec3 lo{0}, hi{-1};
    std::function<float(const glm::ivec3&)> at;
};

// The voxel size, or a refusal when the voxel axes are not orthogonal and of one length.
double uniform_voxel(const IndexGrid& g) {
    const double s = glm::length(g.axis[0]);
    const auto off = [&](int a, int b) { return std::abs(glm::dot(g.axis[a], g.axis[b])) / (s * s); };
    const bool uniform = s > 0.0 && std::isfinite(s) && std::abs(glm::length(g.axis[1]) - s) <= 1e-6 * s &&
                         std::abs(glm::length(g.axis[2]) - s) <= 1e-6 * s && off(0, 1) <= 1e-6 && off(0, 2) <= 1e-6 &&
                         off(1, 2) <= 1e-6 && glm::dot(glm::cross(g.axis[0], g.axis[1]), g.axis[2]) > 0.0;
    if (!uniform)
        throw InputError(fmt::format("grid {}: its transform is not a uniform scale plus rotation and translation "
                                     "(voxel axes of lengths {:g}, {:g}, {:g})",
                                     quoted_input(g.name), glm::length(g.axis[0]), glm::length(g.axis[1]),
                                     glm::length(g.axis[2])));
    return s;
}

// Trilinear in index space, from the 8 voxels about u.
float index_trilinear(const IndexGrid& g, const glm::dvec3& u) {
    const glm::dvec3 b = glm::floor(u), f = u - b;
    const glm::ivec3 i(b);
    double v = 0.0;
    for (int c = 0; c < 8; ++c) {
        const glm::ivec3 o(c & 1, (c >> 1) & 1, (c >> 2) & 1);
        const double w = (o.x ? f.x : 1.0 - f.x) * (o.y ? f.y : 1.0 - f.y) * (o.z ? f.z : 1.0 - f.z);
        v += w * g.at(i + o);
    }
    return static_cast<float>(v);
}

void check_points(const IndexGrid& g, const glm::dvec3& cells) {
    const double points = (cells.x + 1) * (cells.y + 1) * (cells.z + 1);
    if (cells.x > kMaxGridCells || cells.y > kMaxGridCells || cells.z > kMaxGridCells ||
        points > static_cast<double>(kMaxLevelSetPoints))
        throw InputError(fmt::format("grid {}: its active voxels span {} x {} x {} cells; a level-set edit holds at most "
                                     "{} along an axis and {} points",
                                     quoted_input(g.name), cells.x, cells.y, cells.z, kMaxGridCells, kMaxLevelSetPoints));
}

// The dense grid over the active bounds plus one voxel: copied where the axes are the world's,
// else resampled onto world axes at the voxel size.
LevelSetGrid to_dense(const IndexGrid& g) {
    if (glm::any(glm::lessThan(g.hi, g.lo))) throw InputError(fmt::format("grid {}: no active voxel", quoted_input(g.name)));
    LevelSetGrid out;
    out.grid = g.name;
    const double voxel = uniform_voxel(g);
    const glm::ivec3 lo = g.lo - 1, hi = g.hi + 1;
    const auto world = [&](const glm::dvec3& u) { return g.origin + u.x * g.axis[0] + u.y * g.axis[1] + u.z * g.axis[2]; };
    const bool aligned = g.axis[0].y == 0.0 && g.axis[0].z == 0.0 && g.axis[1].x == 0.0 && g.axis[1].z == 0.0 &&
                         g.axis[2].x == 0.0 && g.axis[2].y == 0.0 && g.axis[0].x > 0.0;
    GridFrame& f = out.frame;
    f.cell = static_cast<float>(voxel);
    if (aligned) {
        check_points(g, glm::dvec3(hi - lo));
        f.origin = glm::dvec3(glm::vec3(world(glm::dvec3(lo))));
        f.dims = hi - lo + 1;
    } else {
        Aabb box;
        for (int c = 0; c < 8; ++c) box.grow(world(glm::dvec3(c & 1 ? hi.x : lo.x, c & 2 ? hi.y : lo.y, c & 4 ? hi.z : lo.z)));
        const glm::dvec3 cells = glm::ceil(box.extent() / voxel);
        check_points(g, cells);
        f.origin = glm::dvec3(glm::vec3(box.lo));
        f.dims = glm::ivec3(cells) + 1;
    }
    // world -> index: the axes are orthogonal of length voxel, so the inverse is the transpose / voxel^2.
    const double inv2 = 1.0 / (voxel * voxel);
    out.values.resize(f.points());
    std::size_t n = 0;
    for (int k = 0; k < f.dims.z; ++k)
        for (int j = 0; j < f.dims.y; ++j)
            for (int i = 0; i < f.dims.x; ++i) {
                if (aligned) {
                    out.values[n++] = g.at(lo + glm::ivec3(i, j, k));
                    continue;
                }
                const glm::dvec3 d = f.origin + glm::dvec3(i, j, k) * f.cell - g.origin;
                out.values[n++] = index_trilinear(g, glm::dvec3(glm::dot(d, g.axis[0]), glm::dot(d, g.axis[1]),
                                                                glm::dot(d, g.axis[2])) * inv2);
            }
    return out;
}

std::string choose_grid(const std::vector<std::string>& names, const std::string& wanted) {
    if (wanted.empty() && names.size() == 1) return names[0];
    std::vector<std::string> quoted;
    for (const std::string& n : names) quoted.push_back(quoted_input(n));
    if (wanted.empty())
        throw InputError(fmt::format("the file holds {} grids ({}): name one with \"grid\"", names.size(),
                                     fmt::join(quoted, ", ")));
    if (std::find(names.begin(), names.end(), wanted) == names.end())
        throw InputError(fmt::format("no grid named {} (the file holds {})", quoted_input(wanted),
                                     names.empty() ? std::string("none") : fmt::format("{}", fmt::join(quoted, ", "))));
    return wanted;
}

#if SDFBRICK_WITH_OPENVDB
LevelSetGrid read_openvdb(const std::filesystem::path& path, const std::string& wanted) {
    openvdb::initialize();
    openvdb::io::File file(path.string());
    file.open(false);
    std::vector<std::string> names;
    for (auto it = file.beginName(); it != file.endName(); ++it) names.push_back(it.gridName());
    const std::string name = choose_grid(names, wanted);
    const openvdb::GridBase::Ptr base = file.readGrid(name);
    if (!base->isType<openvdb::FloatGrid>())
        throw InputError(fmt::format("grid {} holds {} values; a level set holds float", quoted_input(name),
                                     escaped(base->valueType())));
    if (base->getGridClass() != openvdb::GRID_LEVEL_SET)
        throw InputError(fmt::format("grid {} is of class {}, not a level set (a fog volume or other density is not a "
                                     "distance)", quoted_input(name),
                                     escaped(openvdb::GridBase::gridClassToString(base->getGridClass()))));
    if (!base->transform().isLinear())
        throw InputError(fmt::format("grid {}: its transform is not linear (a frustum)", quoted_input(name)));
    const auto grid = openvdb::gridPtrCast<openvdb::FloatGrid>(base);
    IndexGrid g;
    g.name = name;
    const auto w = [&](double i, double j, double k) {
        const openvdb::Vec3d v = grid->transform().indexToWorld(openvdb::Vec3d(i, j, k));
        return glm::dvec3(v.x(), v.y(), v.z());
    };
    g.origin = w(0, 0, 0);
    g.axis = {w(1, 0, 0) - g.origin, w(0, 1, 0) - g.origin, w(0, 0, 1) - g.origin};
    const openvdb::CoordBBox box = grid->evalActiveVoxelBoundingBox();
    if (!box.empty()) {
        g.lo = glm::ivec3(box.min().x(), box.min().y(), box.min().z());
        g.hi = glm::ivec3(box.max().x(), box.max().y(), box.max().z());
    }
    auto accessor = grid->getConstAccessor();
    g.at = [&](const glm::ivec3& c) { return accessor.getValue(openvdb::Coord(c.x, c.y, c.z)); };
    return to_dense(g);
}
#endif

#if SDFBRICK_WITH_NANOVDB
LevelSetGrid read_nanovdb(const std::filesystem::path& path, const std::string& wanted) {
    const auto handles = nanovdb::io::readGrids(path.string());
    std::vector<std::string> names;
    for (const auto& h : handles) names.push_back(h.gridMetaData() ? h.gridMetaData()->shortGridName() : "");
    const std::string name = choose_grid(names, wanted);
    const auto& handle = handles[std::find(names.begin(), names.end(), name) - names.begin()];
    const nanovdb::GridMetaData* meta = handle.gridMetaData();
    const nanovdb::FloatGrid* grid = handle.grid<float>();
    if (!grid)
        throw InputError(fmt::format("grid {} holds {} values; a level set holds float", quoted_input(name),
                                     escaped(nanovdb::toStr(meta->gridType()))));
    if (grid->gridClass() != nanovdb::GridClass::LevelSet)
        throw InputError(fmt::format("grid {} is of class {}, not a level set (a fog volume or other density is not a "
                                     "distance)", quoted_input(name), escaped(nanovdb::toStr(grid->gridClass()))));
    IndexGrid g;
    g.name = name;
    const auto w = [&](double i, double j, double k) {
        const nanovdb::Vec3d v = grid->indexToWorld(nanovdb::Vec3d(i, j, k));
        return glm::dvec3(v[0], v[1], v[2]);
    };
    g.origin = w(0, 0, 0);
    g.axis = {w(1, 0, 0) - g.origin, w(0, 1, 0) - g.origin, w(0, 0, 1) - g.origin};
    const auto& box = grid->indexBBox();
    if (!box.empty()) {
        g.lo = glm::ivec3(box.min()[0], box.min()[1], box.min()[2]);
        g.hi = glm::ivec3(box.max()[0], box.max()[1], box.max()[2]);
    }
    auto accessor = grid->getAccessor();
    g.at = [&](const glm::ivec3& c) { return accessor.getValue(nanovdb::Coord(c.x, c.y, c.z)); };
    return to_dense(g);
}
#endif

}  // namespace

bool level_set_format_available(const std::filesystem::path& path) {
#if SDFBRICK_WITH_NANOVDB
    if (is_nanovdb(path)) return true;
#endif
#if SDFBRICK_WITH_OPENVDB
    if (!is_nanovdb(path)) return true;
#endif
    (void)path;
    return false;
}

LevelSetGrid read_level_set(const std::filesystem::path& path, const std::string& grid) {
    const std::string file = escaped(path.string(), 2 * kEchoLimit);
    if (!level_set_format_available(path))
        throw InputError(fmt::format("{}: this sdfbrick was built without {} ({}): it cannot read level sets from it",
                                     file, is_nanovdb(path) ? "NanoVDB" : "OpenVDB",
                                     is_nanovdb(path) ? "libnanovdb-dev" : "libopenvdb-dev"));
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec))  // never a FIFO or device the libraries would block on
        throw InputError(fmt::format("{}: {}", file, std::filesystem::exists(path, ec) ? "not a regular file" : "no such file"));
    try {
#if SDFBRICK_WITH_NANOVDB
        if (is_nanovdb(path)) return read_nanovdb(path, grid);
#endif
#if SDFBRICK_WITH_OPENVDB
        return read_openvdb(path, grid);
#endif
    } catch (const InputError& e) {
        throw InputError(fmt::format("{}: {}", file, e.what()));
    } catch (const std::exception& e) {  // the libraries' own errors on a file they cannot read
        throw InputError(fmt::format("{}: cannot read level sets: {}", file, escaped(e.what(), 2 * kEchoLimit)));
    }
    throw std::logic_error("read_level_set: no reader");
}

std::shared_ptr<MeshSource> make_level_set_source(LevelSetGrid grid, std::string file) {
    auto source = std::make_shared<MeshSource>();
    source->file = std::move(file);
    source->grid = std::move(grid.grid);
    source->frame = grid.frame;
    source->values = std::move(grid.values);
    return source;
}

}  // namespace sdfbrick
