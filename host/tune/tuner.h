// The tuner: searches one declared kernel's configurations on one device, measuring each through the
// run loop (pipeline::Lane) over one or more scenes: a build per configuration and scene for
// brick_evaluate, trace passes over bricks built once per scene for trace_primary. A configuration's
// time on a scene is the device time of the kernel's objective stages, minimum over the captures; its
// cost is the geometric mean of its times over the scenes (with one scene, that time), so that each
// scene weighs the same whatever its size; a configuration the device cannot take on some scene costs
// +infinity ("not runnable"). docs/tuning.md.
#pragma once

#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "pipeline/run.h"
#include "render/methods.h"
#include "scene/scene.h"
#include "tune/kernels.h"
#include "tune/search.h"
#include "tune/tuning_db.h"

namespace sdfbrick::tune {

struct TuneSpec {
    std::string strategy = "auto";  // strategy_from_string
    std::size_t budget = 40;        // most configurations measured (random, anneal)
    std::uint64_t seed = 1;
    int warmup = 1, repeat = 3;  // per configuration
    int width = 1280, height = 720;  // the traced image (Work::trace kernels)
    render::Method method = render::Method::sphere;  // its in-brick search
};

// A scene the tuner measures over, and the file it came from (the entry's record names it).
struct TuneScene {
    Scene scene;
    std::string file;
};

struct TuneResult {
    const TunedKernel* kernel = nullptr;
    SearchResult result;  // every configuration measured, in order; the best
    std::vector<std::vector<double>> scene_ms;  // per configuration of result.evaluated: its time per scene
    Config fallback;      // the kernel's default configuration
    double fallback_cost = 0.0;
    std::vector<std::string> files;  // the scenes' files, in order
    Strategy strategy = Strategy::full;
    std::size_t space = 0;  // configurations in the device's space
    construct::BuildSettings settings;  // the base settings measured with
    TuneSpec spec;
    bool found() const;  // some configuration ran
};

// Called after each configuration is measured: its 1-based number, the configuration, its cost
// (+infinity when not runnable) and its time per scene.
using TuneProgress = std::function<void(std::size_t, const Config&, double, std::span<const double>)>;

// The line `sdfbrick tune` prints for a measured configuration (with several scenes, each one's time
// after the cost).
std::string measured_line(std::size_t n, const Config& c, double cost, std::span<const double> scene_ms);

// Tunes kernel on runner's device over scenes (at least one). base gives every other setting (for a
// Work::trace kernel, the bricks are built once per scene with it). Throws InputError for a bad
// strategy, no scene, or settings the device refuses outside the tuned parameters.
TuneResult tune_kernel(const TunedKernel& kernel, pipeline::Lane& runner, std::span<const TuneScene> scenes,
                       const construct::BuildSettings& base, const TuneSpec& spec, const TuneProgress& progress = {});

// The database entry of a result (found() only): the best configuration, its cost, the default's,
// and how, where (its scene, or with several, its scenes) and when it was measured.
Entry make_entry(const TuneResult& r, const ocl::DeviceInfo& device, const std::string& tuned_at);

// Tunes kernels (in the tuner's order, tuned_kernels()) on runner's device over scenes, as `sdfbrick
// tune` does: a Work::trace kernel is measured over bricks built with the winners of the kernels
// before it. Each winner goes into db (make_entry with tuned_at). Gives the device's report:
// {"device", and per kernel found its entry's record with "params" and "evaluated_configurations"
// (each {"params", "ms"}, ms null when not runnable, and with several scenes "scene_ms", the time per
// scene)}. say: every line of text as soon as it is known (the device, each kernel's heading and
// result); measured: every configuration as it is measured. Either may be empty.
nlohmann::json tune_device(pipeline::Lane& runner, std::span<const TuneScene> scenes,
                           const std::vector<const TunedKernel*>& kernels, const construct::BuildSettings& base,
                           const TuneSpec& spec, TuningDb& db, const std::string& tuned_at,
                           const std::function<void(const std::string&)>& say, const TuneProgress& measured = {});

}  // namespace sdfbrick::tune
