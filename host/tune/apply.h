// Applying the tuning database to a run: the parameters of each tuned kernel (tune/kernels.h) that a
// user did not give on the command line (or in a sweep grid) take the database's values for the device
// (TuningDb::find: the user's file, then the compiled-in layer), else the built-in defaults. Every
// report says which values were used and where they came from.
#pragma once

#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "construct/brick_builder.h"
#include "cl/device.h"
#include "pipeline/executor.h"
#include "render/brick_tracer.h"
#include "tune/kernels.h"
#include "tune/tuning_db.h"

namespace sdfbrick::tune {

struct Given {  // parameters the user set explicitly: never overridden
    bool chunk = false, group = false, eval_registers = false, trace_group = false, trace_registers = false;
};

struct Applied {
    // per kernel: {"source", "layer", "params", "entry", "not_applied"}
    nlohmann::json record = nlohmann::json::object();
    std::string text;  // one line for text reports
};

// db may be null (tuning off: both layers ignored). trace may be null (construction only). Values the
// device cannot take (TunedKernel::refuses: a work-group larger than it allows, a chunk that does not
// fit its local memory) are not applied; the record says so.
Applied apply_tuning(const TuningDb* db, const ocl::DeviceInfo& device, const Given& given,
                     construct::BuildSettings& settings, render::TraceSettings* trace);

// One device's settings, resolved in one place: the settings as given (flags or sweep keys), the
// tuning database's values for the parameters not given, then validation for that device (throws
// SettingError naming the setting). Every verb, the sweep and the stability atlas resolve their
// settings through it, once per device.
struct Resolved {
    construct::BuildSettings build;
    render::TraceSettings trace;
    Applied tuning;
};
// trace: null for construction-only work (its trace settings are then the defaults, untuned).
Resolved resolve_settings(const construct::BuildSettings& given_settings, const render::TraceSettings* trace,
                          const TuningDb* db, const ocl::DeviceInfo& device, const Given& given);

// The executor's settings function: resolve_settings on each lane's device (db must outlive it).
// trace: empty for construction-only work.
pipeline::SettingsFor settings_for(const construct::BuildSettings& given_settings,
                                   std::optional<render::TraceSettings> trace, const TuningDb* db, const Given& given);

}  // namespace sdfbrick::tune
