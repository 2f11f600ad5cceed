#include "tune/apply.h"

#include <fmt/format.h>

#include "core/errors.h"

namespace sdfbrick::tune {

namespace {

int param(const Lookup& l, const char* name, int fallback) {
    const auto it = l.params.find(name);
    return it != l.params.end() ? it->second : fallback;
}

nlohmann::json describe(const Lookup& l, const nlohmann::json& params, bool given) {
    nlohmann::json j = {{"source", given ? "command line" : std::string(to_string(l.source))}, {"params", params}};
    if (l.entry && !given)
        j["entry"] = {{"device", l.entry->device}, {"driver", l.entry->driver}, {"tuned_at", l.entry->record.is_object() ? l.entry->record.value("tuned_at", "") : ""}};
    return j;
}

}  // namespace

Applied apply_tuning(const TuningDb* db, const ocl::DeviceInfo& device, const Given& given,
                     construct::BuildSettings& settings, render::TraceSettings* trace) {
    Applied out;
    const auto find = [&](const char* kernel) {
        return db ? db->find(device.name, device.driver_version, device.vendor, kernel) : Lookup{};
    };
    const Lookup eval = find(kEvaluateKernel);
    construct::BuildSettings tuned = settings;
    if (!given.chunk) tuned.chunk = param(eval, "chunk", tuned.chunk);
    if (!given.group) tuned.eval_group = param(eval, "group", tuned.eval_group);
    std::string note;
    try {
        tuned.validate(device);
        settings = tuned;
    } catch (const InputError& e) {
        note = fmt::format(" (tuned values not applied: {})", e.what());
    }
    out.record[kEvaluateKernel] = describe(eval, {{"chunk", settings.chunk}, {"group", settings.eval_group}},
                                           given.chunk && given.group);
    if (!note.empty()) out.record[kEvaluateKernel]["not_applied"] = note;
    out.text = fmt::format("tuning: {} chunk {} group {} ({}){}", kEvaluateKernel, settings.chunk, settings.eval_group,
                           given.chunk && given.group ? "command line" : to_string(eval.source), note);
    if (trace) {
        const Lookup tr = find(kTraceKernel);
        if (!given.trace_group) {
            const int x = param(tr, "group_x", trace->group_x), y = param(tr, "group_y", trace->group_y);
            if (static_cast<std::size_t>(x) * y <= device.max_work_group_size) {
                trace->group_x = x;
                trace->group_y = y;
            }
        }
        out.record[kTraceKernel] = describe(tr, {{"group_x", trace->group_x}, {"group_y", trace->group_y}}, given.trace_group);
        out.text += fmt::format("; {} {}x{} ({})", kTraceKernel, trace->group_x, trace->group_y,
                                given.trace_group ? "command line" : to_string(tr.source));
    }
    if (!db) out.text += " [tuning database off]";
    return out;
}

}  // namespace sdfbrick::tune
