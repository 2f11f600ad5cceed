// BVH build and brick ray tracing (host/bvh/, host/render/brick_tracer.h): the five shipped scenes x
// leaf brick sizes 0.5, 0.25, 0.125, 0.0625, normals mode at 3840 x 2160 with the default in-brick
// method and normals. Manual time = device time from OpenCL profiling events: the BVH build (every
// bvh kernel) and the primary trace kernel. Counters: bricks, BVH nodes, rays/s, node visits and
// in-brick steps per ray. The bricks of one scene and size are built once and shared by its two
// benchmarks. Device: $SDFBRICK_DEVICE (default: first GPU, else device 0); e.g.
//   SDFBRICK_DEVICE=cpu build/release/bench/bench_trace --benchmark_filter='trace/spheres'
#include <memory>
#include <string>

#include <benchmark/benchmark.h>
#include <fmt/format.h>

#include "bench_support.h"
#include "render/brick_tracer.h"
#include "render/pictures.h"
#include "scene/scene_json.h"

namespace sdfbrick {
namespace {

constexpr int kWidth = 3840, kHeight = 2160;

struct Engine {
    construct::BrickBuilder bricks{bench::device()};
    bvh::BvhBuilder bvh{bench::device()};
    render::BrickTracer tracer{bench::device()};
};

Engine& engine() {
    static Engine e;
    return e;
}

// The scene and its bricks at one size; one at a time (the pools of the smallest size are large).
struct Prepared {
    std::string key;
    Scene scene;
    std::unique_ptr<render::SceneBricks> bricks;
};

Prepared& prepare(const std::string& name, double leaf) {
    static Prepared p;
    const std::string key = fmt::format("{}/{}", name, leaf);
    if (p.key != key) {
        p.bricks.reset();
        const Scene file = load_scene(std::string(SDFBRICK_SOURCE_DIR) + "/scenes/" + name + ".json");
        p.scene = scene_at(file, file.time);
        construct::BuildSettings s;
        s.leaf_size = leaf;
        measure::Scheduler scheduler(bench::device());
        p.bricks = std::make_unique<render::SceneBricks>(
            render::build_scene_bricks(engine().bricks, engine().bvh, p.scene, s, scheduler));
        p.key = key;
    }
    return p;
}

void bench_bvh(benchmark::State& state, const std::string& name, double leaf) {
    Prepared& p = prepare(name, leaf);
    for (auto _ : state) {
        measure::Scheduler scheduler(bench::device());
        const bvh::SceneBvh b = engine().bvh.build(p.scene, p.bricks->builds, p.bricks->settings, scheduler);
        state.SetIterationTime(b.device_ms * 1e-3);
    }
    state.counters["bricks"] = static_cast<double>(p.bricks->bricks);
    state.counters["nodes"] = static_cast<double>(p.bricks->bvh.node_count);
    state.counters["bricks/s"] =
        benchmark::Counter(static_cast<double>(p.bricks->bricks), benchmark::Counter::kIsIterationInvariantRate);
    state.SetLabel(bench::device().info().name);
}

void bench_trace(benchmark::State& state, const std::string& name, double leaf) {
    Prepared& p = prepare(name, leaf);
    render::TraceSettings t;
    t.width = kWidth;
    t.height = kHeight;
    const SdfCamera camera = make_camera(p.scene.camera, kWidth, kHeight);
    render::TraceResult last;
    for (auto _ : state) {
        measure::Scheduler scheduler(bench::device());
        last = engine().tracer.render(p.scene, *p.bricks, camera, t, scheduler);
        state.SetIterationTime(last.trace_ms * 1e-3);
    }
    const render::WorkCounts work = render::work_counts(last.buffer);
    state.counters["bricks"] = static_cast<double>(p.bricks->bricks);
    state.counters["rays/s"] =
        benchmark::Counter(static_cast<double>(kWidth) * kHeight, benchmark::Counter::kIsIterationInvariantRate);
    state.counters["visits/ray"] = work.node_visits;
    state.counters["steps/ray"] = work.brick_steps;
    state.SetLabel(fmt::format("{} {} {}", bench::device().info().name, render::to_string(t.method),
                               render::to_string(t.normals)));
}

}  // namespace
}  // namespace sdfbrick

int main(int argc, char** argv) {
    using namespace sdfbrick;
    benchmark::Initialize(&argc, argv);
    bench::add_device_context();
    for (const char* name : {"spheres", "drops", "cubes", "rain", "fractal"})
        for (double leaf : {0.5, 0.25, 0.125, 0.0625}) {
            benchmark::RegisterBenchmark(fmt::format("bvh/{}/{}", name, leaf).c_str(), bench_bvh, std::string(name), leaf)
                ->UseManualTime()
                ->Unit(benchmark::kMillisecond);
            benchmark::RegisterBenchmark(fmt::format("trace/{}/{}", name, leaf).c_str(), bench_trace, std::string(name), leaf)
                ->UseManualTime()
                ->Iterations(10)
                ->Unit(benchmark::kMillisecond);
        }
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
}
