// Sparse brick construction (host/construct/brick_builder.h): the five shipped scenes x leaf brick sizes
// 0.5, 0.25, 0.125, 0.0625 x culling on/off. Manual time = the device time of the whole
// construction (every stage's kernels, from OpenCL profiling events). Counters: leaf bricks,
// bricks/s, edit evaluations/s, edits per leaf brick (mean), and each stage's share in ms.
// Device: $SDFBRICK_DEVICE (default: first GPU, else device 0). Culling off at small bricks is slow
// on a CPU: pick with --benchmark_filter, e.g.
//   SDFBRICK_DEVICE=cpu build/release/bench/bench_build --benchmark_filter='build/drops/0.125/cull'
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "bench_support.h"
#include <fmt/format.h>

#include "construct/brick_builder.h"
#include "scene/scene_json.h"

namespace sdfbrick {
namespace {

construct::BrickBuilder& builder() {
    static construct::BrickBuilder b(bench::device());
    return b;
}

void bench_build(benchmark::State& state, const std::string& scene_name, double leaf, bool cull) {
    const Scene s = load_scene(std::string(SDFBRICK_SOURCE_DIR) + "/scenes/" + scene_name + ".json");
    const Geometry g = geometry_at(s.geometries[0], s.time);
    construct::BuildSettings settings;
    settings.leaf_size = leaf;
    settings.cull = cull;
    construct::GeometryBuild last;
    std::map<std::string, double> stage_ms;
    for (auto _ : state) {
        measure::Scheduler scheduler(bench::device());
        last = builder().build(g, settings, scheduler);
        state.SetIterationTime(last.device_ms * 1e-3);
        for (const measure::Launch& l : scheduler.launches()) stage_ms[std::string(to_string(l.stage))] += l.device_ms;
    }
    const auto iterations = static_cast<double>(state.iterations());
    state.counters["bricks"] = static_cast<double>(last.leaf_count);
    state.counters["bricks/s"] = benchmark::Counter(static_cast<double>(last.leaf_count), benchmark::Counter::kIsIterationInvariantRate);
    state.counters["edit_evals/s"] =
        benchmark::Counter(static_cast<double>(last.edit_evaluations), benchmark::Counter::kIsIterationInvariantRate);
    state.counters["edits/leaf"] = last.edits_per_leaf_mean;
    for (const auto& [stage, ms] : stage_ms) state.counters[stage + "_ms"] = ms / iterations;
    state.SetLabel(bench::device().info().name);
}

}  // namespace
}  // namespace sdfbrick

int main(int argc, char** argv) {
    using namespace sdfbrick;
    benchmark::Initialize(&argc, argv);
    bench::add_device_context();
    for (const char* name : {"spheres", "drops", "cubes", "rain", "fractal"})
        for (double leaf : {0.5, 0.25, 0.125, 0.0625})
            for (bool cull : {true, false})
                benchmark::RegisterBenchmark(fmt::format("build/{}/{}/{}", name, leaf, cull ? "cull" : "nocull").c_str(),
                                             bench_build, std::string(name), leaf, cull)
                    ->UseManualTime()
                    ->Unit(benchmark::kMillisecond);
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
}
