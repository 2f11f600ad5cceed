// Field evaluation throughput (kernels/eval_points.cl): every shipped scene, 2^18 random points in
// its bounds, all edits at every point (no culling: that is construction's job). Manual time from
// OpenCL profiling events (kernel start -> end). Counters: points/s and edit evaluations/s.
// Device: --device-style spec in $SDFBRICK_DEVICE (default: first GPU, else device 0).
//   SDFBRICK_DEVICE=cpu build/release/bench/bench_eval --benchmark_out=eval.json
#include <cstdlib>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "bench_support.h"

#include "reference/field_eval.h"
#include "reference/reference_field.h"
#include "scene/scene_json.h"
#include "scene/to_device.h"

namespace sdfbrick {
namespace {

void bench_eval(benchmark::State& state, const std::string& scene_name) {
    ocl::Device& device = bench::device();
    static reference::FieldEvaluator evaluator(device);
    const Scene s = load_scene(std::string(SDFBRICK_SOURCE_DIR) + "/scenes/" + scene_name + ".json");
    const Geometry g = geometry_at(s.geometries[0], s.time);
    const std::vector<SdfEdit> edits = to_device(g);
    std::vector<float> xyz;
    for (const glm::dvec3& p : reference::random_points(g, static_cast<std::size_t>(state.range(0)), 1))
        for (int i = 0; i < 3; ++i) xyz.push_back(static_cast<float>(p[i]));
    const double points = static_cast<double>(xyz.size() / 3);
    for (auto _ : state) {
        const reference::FieldEvalResult r = evaluator.evaluate(edits, xyz);
        state.SetIterationTime(r.device_ms * 1e-3);
    }
    state.counters["points/s"] = benchmark::Counter(points, benchmark::Counter::kIsIterationInvariantRate);
    state.counters["edit_evals/s"] =
        benchmark::Counter(points * static_cast<double>(edits.size()), benchmark::Counter::kIsIterationInvariantRate);
    state.counters["edits"] = static_cast<double>(edits.size());
    state.SetLabel(device.info().name);
}

}  // namespace
}  // namespace sdfbrick

int main(int argc, char** argv) {
    using namespace sdfbrick;
    benchmark::Initialize(&argc, argv);
    bench::add_device_context();
    for (const char* name : {"spheres", "drops", "cubes", "rain", "fractal"})
        benchmark::RegisterBenchmark((std::string("eval/") + name).c_str(), bench_eval, std::string(name))
            ->Arg(1 << 18)
            ->UseManualTime()
            ->Unit(benchmark::kMillisecond);
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
}
