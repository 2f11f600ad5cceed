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

// Measures configurations of one kernel: each through the runner on every scene, with the kernel's
// objective as the time on a scene.
class Measurer {
public:
    Measurer(const TunedKernel& kernel, pipeline::Lane& runner, std::span<const TuneScene> scenes,
             const construct::BuildSettings& base, const TuneSpec& spec)
        : kernel_(kernel), runner_(runner), scenes_(scenes), base_(base), spec_(spec) {
        trace_.width = spec.width;
        trace_.height = spec.height;
        trace_.method = spec.method;
        if (kernel.work != pipeline::Work::trace) return;
        pipeline::RunSpec build;
        build.work = pipeline::Work::bvh;
        build.build = base;
        for (const TuneScene& s : scenes) built_.push_back(runner.run(s.scene, build));
    }

    // The configuration's time on each scene; all +infinity when it cannot run on one.
    std::vector<double> operator()(const Config& c) {
        std::vector<double> ms(scenes_.size(), kNotRunnable);
        if (!kernel_.refuses(c, &runner_.device().info()).empty()) return ms;
        construct::BuildSettings s = base_;
        render::TraceSettings t = trace_;
        kernel_.apply(c, s, t);
        pipeline::RunSpec run_spec{kernel_.work, s, t, spec_.warmup, spec_.repeat};
        run_spec.trace_digests = false;  // a configuration's cost is its time: nothing is read back
        run_spec.image = false;
        try {
            for (std::size_t i = 0; i < scenes_.size(); ++i) {
                const Scene& scene = scenes_[i].scene;
                const pipeline::Run run =
                    built_.empty() ? runner_.run(scene, run_spec) : runner_.trace(scene, built_[i].bricks, run_spec);
                ms[i] = measure::stages_stats(run.captures, kernel_.objective).min;
            }
        } catch (const InputError&) {  // e.g. more work-items than the compiled kernel allows here
            std::fill(ms.begin(), ms.end(), kNotRunnable);
        }
        return ms;
    }

private:
    const TunedKernel& kernel_;
    pipeline::Lane& runner_;
    std::span<const TuneScene> scenes_;
    const construct::BuildSettings& base_;
    const TuneSpec& spec_;
    render::TraceSettings trace_;
    std::vector<pipeline::Run> built_;  // per scene, the bricks a Work::trace kernel is measured over
};

// The geometric mean of a configuration's times (+infinity when one is).
double cost_of(const std::vector<double>& ms) {
    double log_sum = 0.0;
    for (const double m : ms) {
        if (!std::isfinite(m)) return kNotRunnable;
        log_sum += std::log(m);
    }
    return ms.size() == 1 ? ms[0] : std::exp(log_sum / static_cast<double>(ms.size()));
}

}  // namespace

bool TuneResult::found() const { return std::isfinite(result.best_cost); }

TuneResult tune_kernel(const TunedKernel& kernel, pipeline::Lane& runner, std::span<const TuneScene> scenes,
                       const construct::BuildSettings& base, const TuneSpec& spec, const TuneProgress& progress) {
    if (scenes.empty()) throw InputError("tune needs at least one scene");
    TuneResult t;
    t.kernel = &kernel;
    t.settings = base;
    t.spec = spec;
    for (const TuneScene& s : scenes) t.files.push_back(s.file);
    const Space space = kernel.space(&runner.device().info());
    t.space = space.size();
    t.strategy = strategy_from_string(spec.strategy, space, spec.budget);
    t.fallback = kernel.default_config();
    Measurer measure(kernel, runner, scenes, base, spec);
    t.result = search(space, t.strategy, spec.budget, spec.seed, [&](const Config& c) {
        t.scene_ms.push_back(measure(c));  // search measures each configuration once, in evaluated's order
        const double cost = cost_of(t.scene_ms.back());
        if (progress) progress(t.scene_ms.size(), c, cost, t.scene_ms.back());
        return cost;
    });
    const auto it = std::find_if(t.result.evaluated.begin(), t.result.evaluated.end(),
                                 [&](const auto& e) { return e.first == t.fallback; });
    t.fallback_cost = it != t.result.evaluated.end() ? it->second : cost_of(measure(t.fallback));
    return t;
}

Entry make_entry(const TuneResult& r, const ocl::DeviceInfo& device, const std::string& tuned_at) {
    const bool several = r.files.size() > 1;
    nlohmann::json rec = {{"time_ms", r.result.best_cost},
                          {"default_params", r.fallback},
                          {"default_ms", r.fallback_cost},
                          {"objective", r.kernel->objective_text + ", min over repeats" +
                                            (several ? ", geometric mean over the scenes" : "")},
                          {"brick_size", r.settings.leaf_size},
                          {"strategy", to_string(r.strategy)},
                          {"evaluated", r.result.evaluated.size()},
                          {"space", r.space},
                          {"repeat", r.spec.repeat},
                          {"tuned_at", tuned_at},
                          {"platform", device.platform_name}};
    if (several)
        rec["scenes"] = r.files;
    else
        rec["scene"] = r.files.at(0);
    if (r.kernel->work == pipeline::Work::trace) {
        rec["image"] = {r.spec.width, r.spec.height};
        rec["method"] = render::to_string(r.spec.method);
    }
    return {device.name, device.driver_version, device.vendor, r.kernel->name, r.result.best, rec};
}

namespace {

// Puts a kernel's winner into db and the report, and says the summary line.
void record(TuningDb& db, const ocl::DeviceInfo& d, const TuneResult& t, const std::string& tuned_at, const std::function<void(const std::string&)>& say, nlohmann::json& report) {
    const std::string& kernel = t.kernel->name;
    if (!t.found()) {
        if (say) say(fmt::format("  {}: no configuration ran; nothing written\n", kernel));
        return;
    }
    Entry entry = make_entry(t, d, tuned_at);
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
    const auto ms_json = [](double ms) { return std::isfinite(ms) ? nlohmann::json(ms) : nlohmann::json(nullptr); };
    for (std::size_t i = 0; i < t.result.evaluated.size(); ++i) {
        const auto& [c, ms] = t.result.evaluated[i];
        nlohmann::json e = {{"params", c}, {"ms", ms_json(ms)}};
        if (t.files.size() > 1) {
            e["scene_ms"] = nlohmann::json::array();
            for (const double m : t.scene_ms[i]) e["scene_ms"].push_back(ms_json(m));
        }
        evaluated.push_back(e);
    }
    rec["params"] = t.result.best;
    rec["evaluated_configurations"] = evaluated;
    report[kernel] = rec;
}

}  // namespace

std::string measured_line(std::size_t n, const Config& c, double cost, std::span<const double> scene_ms) {
    std::string params;
    for (const auto& [k, v] : c) params += fmt::format(" {} {}", k, v);
    if (!std::isfinite(cost)) return fmt::format("    {:>3}.{:<24} not runnable\n", n, params);
    std::string per_scene;
    if (scene_ms.size() > 1)
        for (const double m : scene_ms) per_scene += fmt::format("{}{:.4f}", per_scene.empty() ? " (" : ", ", m);
    return fmt::format("    {:>3}.{:<24} {:.4f} ms{}\n", n, params, cost, per_scene.empty() ? "" : per_scene + ")");
}

nlohmann::json tune_device(pipeline::Lane& runner, std::span<const TuneScene> scenes,
                           const std::vector<const TunedKernel*>& kernels, const construct::BuildSettings& base,
                           const TuneSpec& spec, TuningDb& db, const std::string& tuned_at,
                           const std::function<void(const std::string&)>& say, const TuneProgress& measured) {
    const ocl::DeviceInfo& info = runner.device().info();
    if (say) say(fmt::format("device {} [{}], driver {}\n", info.index, info.name, info.driver_version));
    nlohmann::json report = {{"device", info.to_json()}};
    construct::BuildSettings settings = base;
    const std::string over = scenes.size() > 1 ? fmt::format(", geometric mean over {} scenes", scenes.size()) : "";
    for (const TunedKernel* k : kernels) {
        if (say) {
            const Space space = k->space(&info);
            const std::size_t planned =
                search_limit(space, strategy_from_string(spec.strategy, space, spec.budget), spec.budget);
            const std::string what =
                k->work == pipeline::Work::trace
                    ? fmt::format("{}x{} {}, ", spec.width, spec.height, render::to_string(spec.method))
                    : "";
            say(fmt::format("  {} ({}{}{}), {} configurations:\n", k->name, what, k->objective_text, over, planned));
        }
        const TuneResult t = tune_kernel(*k, runner, scenes, settings, spec, measured);
        record(db, info, t, tuned_at, say, report);
        render::TraceSettings unused;
        if (t.found() && k->work != pipeline::Work::trace) k->apply(t.result.best, settings, unused);
    }
    return report;
}

}  // namespace sdfbrick::tune
