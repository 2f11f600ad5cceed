// Mesh to signed distance grid: the device conversion (construct/mesh_grid.h, kernels/mesh_sdf.cl)
// against triangle count and grid size, beside OpenVDB's meshToVolume on the same mesh and voxel
// size on this machine's CPU (all its threads, through TBB). Cases include the sizes of Table 1 of
// source 001 (a 2,464-triangle mesh to a 128x74x89 grid, a 100,000-triangle mesh to 42x31x22),
// with generated tori of those triangle counts stretched to the grid's proportions.
//
//   SDFBRICK_DEVICE=cpu build/release/bench/bench_mesh --benchmark_format=json > mesh.json
//
// Device time is the kernel's (profiling events); host_ms (counter) is the rest of the call: the
// triangle tree, the pseudo-normals, the uploads and the read-back. The label carries a digest of
// the grid's values, equal across devices iff the grids are bit-identical. OpenVDB's time is wall time, narrow band (3 voxels) and full grid.
// BM_MeshGridSparse converts the same cases to the sparse grid mesh edits use by default; the two
// finest cases (512^3 cells) run sparse and OpenVDB's narrow band only.
#include <chrono>
#include <span>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "bench_support.h"
#include "construct/mesh_grid.h"
#include "core/hash.h"
#include "measure/scheduler.h"
#include "scene/mesh.h"

#if SDFBRICK_WITH_OPENVDB
#include <openvdb/openvdb.h>
#include <openvdb/tools/MeshToVolume.h>
#endif

namespace sdfbrick::bench {
namespace {

struct Case {
    std::string name;
    TriangleMesh mesh;
    double cell = 0.0;
    int padding = 0;
};

// m stretched so that its bounds span dims - 1 cells of side 1 on each axis.
TriangleMesh fit_to(TriangleMesh m, glm::ivec3 dims) {
    const Aabb b = m.bounds();
    for (glm::dvec3& v : m.vertices) v = (v - b.lo) / b.extent() * (glm::dvec3(dims) - 1.0);
    return m;
}

const std::vector<Case>& cases() {
    static const std::vector<Case> all = [] {
        std::vector<Case> c;
        for (int level : {3, 5, 6})
            for (int res : {64, 128}) {
                TriangleMesh m = icosphere(0.5, level);
                const double cell = construct::cell_for_resolution(m, res);
                c.push_back({fmt::format("sphere {} tris, {}^3 cells", m.triangles.size(), res), std::move(m), cell, 2});
            }
        c.push_back({"Table 1 teapot size: 2464 tris to 128x74x89", fit_to(torus_mesh(0.4, 0.15, 44, 28), {128, 74, 89}), 1.0, 0});
        c.push_back({"Table 1 dragon size: 100000 tris to 42x31x22", fit_to(torus_mesh(0.4, 0.15, 250, 200), {42, 31, 22}), 1.0, 0});
        for (int res : {256, 512}) {  // fine grids: sparse and OpenVDB's narrow band only
            TriangleMesh m = icosphere(0.5, 5);
            const double cell = construct::cell_for_resolution(m, res);
            c.push_back({fmt::format("sphere {} tris, {}^3 cells", m.triangles.size(), res), std::move(m), cell, 2});
        }
        return c;
    }();
    return all;
}

void BM_MeshGridDevice(benchmark::State& state) {
    const Case& c = cases()[static_cast<std::size_t>(state.range(0))];
    construct::MeshGridBuilder builder(device());
    construct::MeshGrid grid;
    double host_ms = 0.0;
    for (auto _ : state) {
        measure::Scheduler scheduler(device());
        const auto start = std::chrono::steady_clock::now();
        grid = builder.build(c.mesh, {c.cell, c.padding}, scheduler);
        const double wall = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
        const double kernel = scheduler.resolve().front().device_ms;
        state.SetIterationTime(kernel * 1e-3);
        host_ms = wall - kernel;
    }
    // The digest of the values: equal across devices iff the grids are bit-identical.
    state.SetLabel(fmt::format("{} ({}x{}x{}), digest {}", c.name, grid.dims.x, grid.dims.y, grid.dims.z,
                               Fnv1a64().add_values(std::span<const float>(grid.values)).hex()));
    state.counters["triangles"] = static_cast<double>(c.mesh.triangles.size());
    state.counters["points"] = static_cast<double>(grid.values.size());
    state.counters["host_ms"] = host_ms;
}

// The sparse grid (the default of mesh edits): tile corners and centres, then the tiles within the
// band (kMeshBandCells) of the surface; device time is the three kernels'.
void BM_MeshGridSparse(benchmark::State& state) {
    const Case& c = cases()[static_cast<std::size_t>(state.range(0))];
    construct::MeshGridBuilder builder(device());
    const GridFrame frame = grid_frame(c.mesh, c.cell, c.padding);
    construct::SparseMeshGrid grid;
    double host_ms = 0.0;
    for (auto _ : state) {
        measure::Scheduler scheduler(device());
        const auto start = std::chrono::steady_clock::now();
        grid = builder.build_sparse(c.mesh, frame, kMeshBandCells * frame.cell, scheduler);
        const double wall = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
        double kernels = 0.0;
        for (const auto& launch : scheduler.resolve()) kernels += launch.device_ms;
        state.SetIterationTime(kernels * 1e-3);
        host_ms = wall - kernels;
    }
    state.SetLabel(fmt::format("{} ({}x{}x{}), digest {}", c.name, frame.dims.x, frame.dims.y, frame.dims.z,
                               Fnv1a64().add_values(std::span<const float>(grid.values)).hex()));
    state.counters["triangles"] = static_cast<double>(c.mesh.triangles.size());
    state.counters["points"] = static_cast<double>(frame.points());
    state.counters["values"] = static_cast<double>(grid.values.size());
    state.counters["tiles_kept"] = static_cast<double>(grid.active);
    state.counters["tiles"] = static_cast<double>(grid.table_size());
    state.counters["host_ms"] = host_ms;
}

#if SDFBRICK_WITH_OPENVDB
void BM_OpenVdbMeshToVolume(benchmark::State& state) {
    const Case& c = cases()[static_cast<std::size_t>(state.range(0))];
    const bool full = state.range(1) != 0;
    openvdb::initialize();
    std::vector<openvdb::Vec3s> points;
    std::vector<openvdb::Vec3I> triangles;
    for (const glm::dvec3& v : c.mesh.vertices)
        points.emplace_back(static_cast<float>(v.x), static_cast<float>(v.y), static_cast<float>(v.z));
    for (const auto& t : c.mesh.triangles) triangles.emplace_back(t[0], t[1], t[2]);
    const auto xform = openvdb::math::Transform::createLinearTransform(c.cell);
    const glm::dvec3 e = c.mesh.bounds().extent() / c.cell;
    const float band = full ? static_cast<float>(std::max({e.x, e.y, e.z}) + 2 * c.padding + 1) : 3.0f;
    std::vector<openvdb::Vec4I> quads;
    openvdb::Index64 voxels = 0;
    for (auto _ : state) {
        auto grid = openvdb::tools::meshToSignedDistanceField<openvdb::FloatGrid>(*xform, points, triangles, quads, band, band);
        voxels = grid->activeVoxelCount();
        benchmark::DoNotOptimize(grid);
    }
    state.SetLabel(fmt::format("{}, {}", c.name, full ? "full grid" : "narrow band 3 voxels"));
    state.counters["triangles"] = static_cast<double>(c.mesh.triangles.size());
    state.counters["active_voxels"] = static_cast<double>(voxels);
}
BENCHMARK(BM_OpenVdbMeshToVolume)
    ->ArgsProduct({benchmark::CreateDenseRange(0, 7, 1), {0, 1}})
    ->Args({8, 0})
    ->Args({9, 0})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
#endif

BENCHMARK(BM_MeshGridDevice)->DenseRange(0, 7)->Unit(benchmark::kMillisecond)->UseManualTime();
BENCHMARK(BM_MeshGridSparse)->DenseRange(0, 9)->Unit(benchmark::kMillisecond)->UseManualTime();

}  // namespace
}  // namespace sdfbrick::bench

int main(int argc, char** argv) {
    benchmark::Initialize(&argc, argv);
    sdfbrick::bench::add_device_context();
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
}
