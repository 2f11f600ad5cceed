#include "tune/tuner.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include <fmt/format.h>

#include "core/errors.h"
#include "measure/statistics.h"

namespace sdfbrick::tune {

namespace {

constexpr double kNotRunnable = std::numeric_limits<double>::infinity();

// Measures configurations of one kernel: each through the runner, with the kernel's objective as cost.
class Measurer {
public:
    Measurer(const TunedKernel& kernel, pipeline::Lane& runner, const Scene& scene,
             const construct::BuildSettings& base, const TuneSpec& spec)
        : kernel_(kernel), runner_(runner), scene_(scene), base_(base), spec_(spec) {
        trace_.width = spec.width;
        trace_.height = spec.height;
        trace_.method = spec.method;
        if (kernel.work != pipeline::Work::trace) return;
        pipeline::RunSpec build;
        build.work = pipeline::Work::bvh;
        build.build = base;
        built_ = runner.run(scene, build);
    }

    double operator()(const Config& c) {
        if (!kernel_.refuses(c, &runner_.device().info()).empty()) return kNotRunnable;
        construct::BuildSettings s = base_;
        render::TraceSettings t = trace_;
        kernel_.apply(c, s, t);
        pipeline::RunSpec run_spec{kernel_.work, s, t, spec_.warmup, spec_.repeat};
        run_spec.trace_digests = false;  // a configuration's cost is its time: nothing is read back
        run_spec.image = false;
        try {
            const pipeline::Run run =
                built_ ? runner_.trace(scene_, built_->bricks, run_spec) : runner_.run(scene_, run_spec);
            return measure::stages_stats(run.captures, kernel_.objective).min;
        } catch (const InputError&) {  // e.g. more work-items than the compiled kernel allows here
            return kNotRunnable;
        }
    }

private:
    const TunedKernel& kernel_;
    pipeline::Lane& runner_;
    const Scene& scene_;
    const construct::BuildSettings& base_;
    const TuneSpec& spec_;
    render::TraceSettings trace_;
    std::optional<pipeline::Run> built_;  // the bricks a Work::trace kernel is measured over
};

}  // namespace

bool TuneResult::found() const { return std::isfinite(result.best_cost); }

TuneResult tune_kernel(const TunedKernel& kernel, pipeline::Lane& runner, const Scene& scene,
                       const construct::BuildSettings& base, const TuneSpec& spec, const TuneProgress& progress) {
    TuneResult t;
    t.kernel = &kernel;
    t.settings = base;
    t.spec = spec;
    const Space space = kernel.space(&runner.device().info());
    t.space = space.size();
    t.strategy = strategy_from_string(spec.strategy, space, spec.budget);
    t.fallback = kernel.default_config();
    Measurer measure(kernel, runner, scene, base, spec);
    std::size_t done = 0;
    t.result = search(space, t.strategy, spec.budget, spec.seed, [&](const Config& c) {
        const double ms = measure(c);
        if (progress) progress(++done, c, ms);
        return ms;
    });
    const auto it = std::find_if(t.result.evaluated.begin(), t.result.evaluated.end(),
                                 [&](const auto& e) { return e.first == t.fallback; });
    t.fallback_cost = it != t.result.evaluated.end() ? it->second : measure(t.fallback);
    return t;
}

Entry make_entry(const TuneResult& r, const ocl::DeviceInfo& device, const std::string& scene_file,
                 const std::string& tuned_at) {
    nlohmann::json rec = {{"time_ms", r.result.best_cost},
                          {"default_params", r.fallback},
                          {"default_ms", r.fallback_cost},
                          {"objective", r.kernel->objective_text + ", min over repeats"},
                          {"scene", scene_file},
                          {"brick_size", r.settings.leaf_size},
                          {"strategy", to_string(r.strategy)},
                          {"evaluated", r.result.evaluated.size()},
                          {"space", r.space},
                          {"repeat", r.spec.repeat},
                          {"tuned_at", tuned_at},
                          {"platform", device.platform_name}};
    if (r.kernel->work == pipeline::Work::trace) {
        rec["image"] = {r.spec.width, r.spec.height};
        rec["method"] = render::to_string(r.spec.method);
    }
    return {device.name, device.driver_version, device.vendor, r.kernel->name, r.result.best, rec};
}

namespace {

// Puts a kernel's winner into db and the report, and says the summary line.
void record(TuningDb& db, const ocl::DeviceInfo& d, const TuneResult& t, const std::string& scene_file,
            const std::string& tuned_at, const std::function<void(const std::string&)>& say, nlohmann::json& report) {
    const std::string& kernel = t.kernel->name;
    if (!t.found()) {
        if (say) say(fmt::format("  {}: no configuration ran; nothing written\n", kernel));
        return;
    }
    Entry entry = make_entry(t, d, scene_file, tuned_at);
    nlohmann::json rec = entry.record;
    db.put(std::move(entry));
    std::string params;
    for (const auto& [k, v] : t.result.best) params += fmt::format("{}{} {}", params.empty() ? "" : ", ", k, v);
    if (say)
        say(fmt::format("  {}: best {} at {:.4f} ms; default {:.4f} ms ({:+.1f}%); {} of {} configurations ({})\n",
                        kernel, params, t.result.best_cost, t.fallback_cost,
                        100.0 * (t.result.best_cost - t.fallback_cost) / t.fallback_cost, t.result.evaluated.size(),
                        t.space, to_string(t.strategy)));
    nlohmann::json evaluated = nlohmann::json::array();
    for (const auto& [c, ms] : t.result.evaluated)
        evaluated.push_back({{"params", c}, {"ms", std::isfinite(ms) ? nlohmann::json(ms) : nlohmann::json(nullptr)}});
    rec["params"] = t.result.best;
    rec["evaluated_configurations"] = evaluated;
    report[kernel] = rec;
}

}  // namespace

nlohmann::json tune_device(pipeline::Lane& runner, const Scene& scene, const std::string& scene_file,
                           const std::vector<const TunedKernel*>& kernels, const construct::BuildSettings& base,
                           const TuneSpec& spec, TuningDb& db, const std::string& tuned_at,
                           const std::function<void(const std::string&)>& say, const TuneProgress& measured) {
    const ocl::DeviceInfo& info = runner.device().info();
    if (say) say(fmt::format("device {} [{}], driver {}\n", info.index, info.name, info.driver_version));
    nlohmann::json report = {{"device", info.to_json()}};
    construct::BuildSettings settings = base;
    for (const TunedKernel* k : kernels) {
        if (say) {
            if (k->work == pipeline::Work::trace)
                say(fmt::format("  {} ({}x{} {}, {}):\n", k->name, spec.width, spec.height, render::to_string(spec.method),
                                k->objective_text));
            else
                say(fmt::format("  {} ({}):\n", k->name, k->objective_text));
        }
        const TuneResult t = tune_kernel(*k, runner, scene, settings, spec, measured);
        record(db, info, t, scene_file, tuned_at, say, report);
        render::TraceSettings unused;
        if (t.found() && k->work != pipeline::Work::trace) k->apply(t.result.best, settings, unused);
    }
    return report;
}

}  // namespace sdfbrick::tune
