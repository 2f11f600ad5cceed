#include "tune/apply.h"

#include <algorithm>
#include <set>

#include <fmt/format.h>

namespace sdfbrick::tune {

namespace {

// The parameters of kernel k (by their names in its declaration) the user gave.
std::set<std::string> given_params(const Given& g, const TunedKernel& k) {
    std::set<std::string> s;
    if (k.name == std::string(kEvaluateKernel)) {
        if (g.chunk) s.insert("chunk");
        if (g.group) s.insert("group");
        if (g.eval_registers) s.insert("registers");
    } else {
        if (g.trace_group) s.insert({"group_x", "group_y"});
        if (g.trace_registers) s.insert("registers");
    }
    return s;
}

nlohmann::json describe_entry(const Entry& e) {
    const nlohmann::json& r = e.record;
    nlohmann::json j = {{"device", e.device}, {"driver", e.driver},
                        {"tuned_at", r.is_object() ? r.value("tuned_at", "") : ""}};
    if (r.is_object() && r.contains("measured")) j["measured"] = r["measured"];
    return j;
}

struct KernelApplied {
    nlohmann::json record;
    std::string text;
};

// One kernel: the looked-up values of the parameters not given, if the device can take them.
KernelApplied apply_kernel(const TunedKernel& k, const TuningDb* db, const ocl::DeviceInfo& device,
                           const std::set<std::string>& given, construct::BuildSettings& s, render::TraceSettings& t) {
    const Lookup l = db ? db->find(device.name, device.driver_version, device.vendor, k.name) : Lookup{};
    const Config current = k.read(s, t);
    Config want = current;
    // A parameter the device does not take keeps its one value there.
    for (const TunedParam& p : k.params)
        if (const auto it = l.params.find(p.name);
            it != l.params.end() && !given.contains(p.name) && p.applies_to(device))
            want[p.name] = it->second;
    std::string note;
    if (want != current) {
        if (const std::string why = k.refuses(want, &device); why.empty())
            k.apply(want, s, t);
        else
            note = fmt::format(" (tuned values not applied: {})", why);
    }
    const bool all_given = std::all_of(k.params.begin(), k.params.end(), [&](const TunedParam& p) {
        return given.contains(p.name) || !p.applies_to(device);
    });
    const std::string source = all_given ? "command line" : std::string(to_string(l.source));
    const Config used = k.read(s, t);
    std::string ignored;  // a setting this device ignores, given anyway
    for (const TunedParam& p : k.params)
        if (!p.applies_to(device) && used.at(p.name) != p.values.front())
            ignored += fmt::format(" ({} {} has no effect: {} lacks {})", p.name, used.at(p.name), device.name,
                                   p.extension);
    KernelApplied out{{{"source", source}, {"params", used}},
                      fmt::format("{} {} ({}){}{}", k.name, k.describe(used), source, note, ignored)};
    if (!all_given) out.record["layer"] = layer_of(l.source);
    if (l.entry && !all_given) out.record["entry"] = describe_entry(*l.entry);
    if (!note.empty()) out.record["not_applied"] = note;
    if (!ignored.empty()) out.record["ignored"] = ignored;
    return out;
}

}  // namespace

Applied apply_tuning(const TuningDb* db, const ocl::DeviceInfo& device, const Given& given,
                     construct::BuildSettings& settings, render::TraceSettings* trace) {
    Applied out;
    render::TraceSettings unused;
    for (const TunedKernel* k : tuned_kernels()) {
        if (k->work == pipeline::Work::trace && !trace) continue;
        const KernelApplied a =
            apply_kernel(*k, db, device, given_params(given, *k), settings, trace ? *trace : unused);
        out.record[k->name] = a.record;
        out.text += (out.text.empty() ? "tuning: " : "; ") + a.text;
    }
    if (!db) out.text += " [tuning database off]";
    return out;
}

Resolved resolve_settings(const construct::BuildSettings& given_settings, const render::TraceSettings* trace,
                          const TuningDb* db, const ocl::DeviceInfo& device, const Given& given) {
    Resolved r{given_settings, trace ? *trace : render::TraceSettings{}, {}};
    r.tuning = apply_tuning(db, device, given, r.build, trace ? &r.trace : nullptr);
    r.build.validate(device);
    return r;
}

pipeline::SettingsFor settings_for(const construct::BuildSettings& given_settings,
                                   std::optional<render::TraceSettings> trace, const TuningDb* db, const Given& given) {
    return [=](const ocl::DeviceInfo& device) {
        Resolved r = resolve_settings(given_settings, trace ? &*trace : nullptr, db, device, given);
        return pipeline::LaneSettings{r.build, r.trace, std::move(r.tuning.record), std::move(r.tuning.text)};
    };
}

}  // namespace sdfbrick::tune
