// Applying the tuning database to a run: the parameters of each tuned kernel (tune/kernels.h) that a
// user did not give on the command line (or in a sweep grid) take the database's values for the device
// (TuningDb::find: the user's file, then the compiled-in layer), else the built-in defaults. Every
// report says which values were used and where they came from.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "construct/brick_builder.h"
#include "cl/device.h"
#include "render/brick_tracer.h"
#include "tune/kernels.h"
#include "tune/tuning_db.h"

namespace sdfbrick::tune {

struct Given {  // parameters the user set explicitly: never overridden
    bool chunk = false, group = false, trace_group = false;
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

}  // namespace sdfbrick::tune
