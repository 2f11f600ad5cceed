// The CPU alternative to a brick build: a direct analytic fill of each geometry's narrow band into an
// OpenVDB float tree, on all of this machine's threads (TBB), with the voxel and band a brick build at
// the same brick size stores (voxel = brick size / 6, values clamped to +-4 voxels, int8 bricks being
// the comparison). Distances come from the double-precision host reference (reference_field.h), the
// same formulas the kernels follow.
//
//   build/release/bench/vdb_fill scenes/cubes.json [--brick-size 0.0625] [--band-voxels 4] [--threads N]
//
// Work is culled the way a careful CPU implementation would, with the field's 1-Lipschitz bound:
// blocks of 64^3 voxels keep the edits that can reach them (value at the centre within the block's
// half diagonal, the band and twice the blend; intersections always) and are dropped when the field at
// the centre is farther than that from zero; each 8^3 leaf of a kept block does the same with its own
// list, then every voxel of a kept leaf is evaluated and stored (active inside the band). Finally the
// inactive space is signed by a flood fill, as a level set needs. Prints the phases' wall time, the
// process's CPU time, and the leaves and active voxels. The whole process's time is what compares
// with `sdfbrick build` (docs/performance.md).
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <openvdb/openvdb.h>
#include <openvdb/tools/SignedFloodFill.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include "reference/reference_field.h"
#include "scene/scene_json.h"

namespace {

using namespace sdfbrick;
using Leaf = openvdb::FloatTree::LeafNodeType;
constexpr int kBlockLeaves = 8;                    // leaves per block side
constexpr int kBlockVoxels = kBlockLeaves * Leaf::DIM;

struct Settings {
    std::string scene;
    double brick_size = 0.0625;
    double band_voxels = 4.0;
    int threads = 0;  // 0: TBB's default (every hardware thread)
};

double seconds_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

double cpu_seconds() {
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    return static_cast<double>(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
           1e-6 * static_cast<double>(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

// The edits of `parent` (indices into g.edits, in edit order) that can change the field where it is
// within the band, in a cube around `centre` whose corners are `half_diagonal` from it.
std::vector<std::uint32_t> reaching(const Geometry& g, const std::vector<std::uint32_t>& parent,
                                    const glm::dvec3& centre, double half_diagonal, double band) {
    std::vector<std::uint32_t> out;
    for (const std::uint32_t i : parent) {
        const Edit& e = g.edits[i];
        if (e.op == Op::Intersect ||
            reference::edit_value(e, centre) <= half_diagonal + band + 2.0 * e.blend)
            out.push_back(i);
    }
    return out;
}

// Whether the field can be within the band somewhere in the cube (1-Lipschitz bound).
bool near_surface(const Geometry& g, const std::vector<std::uint32_t>& list, const glm::dvec3& centre,
                  double half_diagonal, double band) {
    return !list.empty() && std::abs(reference::evaluate(g, list, centre)) <= half_diagonal + band;
}

// The leaf at `origin` (index space), or null when none of its voxels is within the band.
Leaf* fill_leaf(const Geometry& g, const std::vector<std::uint32_t>& list, const openvdb::Coord& origin,
                double voxel, double band) {
    auto leaf = std::make_unique<Leaf>(origin, static_cast<float>(band), false);
    bool any = false;
    for (openvdb::Index n = 0; n < Leaf::SIZE; ++n) {
        const openvdb::Coord c = origin + Leaf::offsetToLocalCoord(n);
        const double d = reference::evaluate(g, list, glm::dvec3(c.x(), c.y(), c.z()) * voxel);
        const float v = static_cast<float>(std::clamp(d, -band, band));
        if (std::abs(d) < band) {
            leaf->setValueOn(n, v);
            any = true;
        } else {
            leaf->setValueOff(n, v);
        }
    }
    return any ? leaf.release() : nullptr;
}

// The leaves of one block (64^3 voxels at `origin`), appended to `out`.
void fill_block(const Geometry& g, const std::vector<std::uint32_t>& all, const openvdb::Coord& origin,
                double voxel, double band, std::vector<Leaf*>& out) {
    const auto centre_of = [&](const openvdb::Coord& lo, int side) {
        return (glm::dvec3(lo.x(), lo.y(), lo.z()) + 0.5 * (side - 1)) * voxel;
    };
    const double block_half = std::sqrt(3.0) * 0.5 * (kBlockVoxels - 1) * voxel;
    const glm::dvec3 bc = centre_of(origin, kBlockVoxels);
    const std::vector<std::uint32_t> list = reaching(g, all, bc, block_half, band);
    if (!near_surface(g, list, bc, block_half, band)) return;
    const double leaf_half = std::sqrt(3.0) * 0.5 * (Leaf::DIM - 1) * voxel;
    for (int z = 0; z < kBlockLeaves; ++z)
        for (int y = 0; y < kBlockLeaves; ++y)
            for (int x = 0; x < kBlockLeaves; ++x) {
                const openvdb::Coord lo = origin.offsetBy(x * int(Leaf::DIM), y * int(Leaf::DIM), z * int(Leaf::DIM));
                const glm::dvec3 lc = centre_of(lo, Leaf::DIM);
                const std::vector<std::uint32_t> leaf_list = reaching(g, list, lc, leaf_half, band);
                if (!near_surface(g, leaf_list, lc, leaf_half, band)) continue;
                if (Leaf* leaf = fill_leaf(g, leaf_list, lo, voxel, band)) out.push_back(leaf);
            }
}

struct GeometryFill {
    openvdb::FloatGrid::Ptr grid;
    double fill_s = 0.0, flood_s = 0.0;
};

GeometryFill fill_geometry(const Geometry& g, double voxel, double band) {
    GeometryFill r;
    r.grid = openvdb::FloatGrid::create(static_cast<float>(band));
    r.grid->setTransform(openvdb::math::Transform::createLinearTransform(voxel));
    r.grid->setGridClass(openvdb::GRID_LEVEL_SET);
    const Aabb box = bounds(g).inflated(band);
    if (box.empty()) return r;
    const auto t0 = std::chrono::steady_clock::now();
    const auto block_of = [&](double w) { return static_cast<int>(std::floor(w / voxel / kBlockVoxels)); };
    const glm::ivec3 lo(block_of(box.lo.x), block_of(box.lo.y), block_of(box.lo.z));
    const glm::ivec3 n = glm::ivec3(block_of(box.hi.x), block_of(box.hi.y), block_of(box.hi.z)) - lo + 1;
    std::vector<std::uint32_t> all(g.edits.size());
    for (std::uint32_t i = 0; i < all.size(); ++i) all[i] = i;
    std::vector<std::vector<Leaf*>> leaves(static_cast<std::size_t>(n.x) * n.y * n.z);
    tbb::parallel_for(std::size_t{0}, leaves.size(), [&](std::size_t b) {
        const int x = static_cast<int>(b % n.x), y = static_cast<int>(b / n.x % n.y), z = static_cast<int>(b / n.x / n.y);
        const openvdb::Coord origin = openvdb::Coord((lo.x + x) * kBlockVoxels, (lo.y + y) * kBlockVoxels, (lo.z + z) * kBlockVoxels);
        fill_block(g, all, origin, voxel, band, leaves[b]);
    });
    for (auto& block : leaves)
        for (Leaf* leaf : block) r.grid->tree().addLeaf(leaf);
    r.fill_s = seconds_since(t0);
    const auto t1 = std::chrono::steady_clock::now();
    openvdb::tools::signedFloodFill(r.grid->tree());
    r.flood_s = seconds_since(t1);
    return r;
}

Settings parse(int argc, char** argv) {
    Settings s;
    for (int i = 1; i < argc; ++i) {
        const std::string_view a = argv[i];
        const auto value = [&]() -> const char* {
            if (i + 1 >= argc) throw std::invalid_argument(std::string(a) + " needs a value");
            return argv[++i];
        };
        if (a == "--brick-size") s.brick_size = std::stod(value());
        else if (a == "--band-voxels") s.band_voxels = std::stod(value());
        else if (a == "--threads") s.threads = std::stoi(value());
        else if (!a.empty() && a[0] != '-' && s.scene.empty()) s.scene = a;
        else throw std::invalid_argument("unknown argument " + std::string(a));
    }
    if (s.scene.empty()) throw std::invalid_argument("usage: vdb_fill SCENE [--brick-size B] [--band-voxels N] [--threads N]");
    if (!(s.brick_size > 0.0) || !(s.band_voxels > 0.0)) throw std::invalid_argument("sizes must be positive");
    return s;
}

int run(const Settings& s) {
    const auto t0 = std::chrono::steady_clock::now();
    std::unique_ptr<tbb::global_control> threads;
    if (s.threads > 0)
        threads = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, s.threads);
    openvdb::initialize();
    const Scene loaded = load_scene(s.scene);
    const Scene scene = scene_at(loaded, loaded.time);
    const double voxel = s.brick_size / 6.0, band = s.band_voxels * voxel;
    std::printf("vdb_fill %s: voxel %.6g, band +-%.6g, %zu geometries\n", s.scene.c_str(), voxel, band,
                scene.geometries.size());
    for (const Geometry& g : scene.geometries) {
        const GeometryFill f = fill_geometry(g, voxel, band);
        std::printf("  geometry %s: %zu edits, %llu leaves, %llu active voxels; fill %.1f ms, flood fill %.1f ms\n",
                    g.name.c_str(), g.edits.size(), static_cast<unsigned long long>(f.grid->tree().leafCount()),
                    static_cast<unsigned long long>(f.grid->tree().activeVoxelCount()), 1e3 * f.fill_s,
                    1e3 * f.flood_s);
    }
    std::printf("  wall %.1f ms from main, cpu %.1f ms of the process so far\n", 1e3 * seconds_since(t0),
                1e3 * cpu_seconds());
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    try {
        return run(parse(argc, argv));
    } catch (const std::exception& e) {
        std::fprintf(stderr, "vdb_fill: %s\n", e.what());
        return 2;
    }
}
