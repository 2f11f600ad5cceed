// The tuned kernels, each declared once (as CLBlast and Kernel Tuner declare theirs): its name, its
// parameters and their candidate values, its constraints, its local-memory cost, its objective (the
// stages whose device time is the cost), its default configuration, and how a configuration is applied
// to the build and trace settings. The tuner (tune/tuner.h), the look-up (tune/apply.h) and
// `sdfbrick tune` read these declarations; nothing else spells the parameters again. docs/tuning.md.
#pragma once

#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "cl/device.h"
#include "construct/brick_builder.h"
#include "measure/stage.h"
#include "pipeline/run.h"
#include "render/brick_tracer.h"
#include "tune/search.h"

namespace sdfbrick::tune {

// The kernels' names in the database and in reports.
inline constexpr const char* kEvaluateKernel = "brick_evaluate";  // chunk, group, registers
inline constexpr const char* kTraceKernel = "trace_primary";      // group_x, group_y, registers

// One parameter: its candidates are the powers of two lo..hi, or the listed values. With device_capped,
// the candidates stop at the device's maximum work-group size (a work-group dimension no device-free
// constraint can bound). With an extension, a device without it has one candidate, the first value
// (the setting it ignores), and a configuration read from a file without the parameter takes that value.
struct TunedParam {
    std::string name;
    int lo = 1, hi = 1;
    bool device_capped = false;
    std::vector<int> values;  // instead of lo..hi when not empty
    std::string extension;    // OpenCL extension the setting needs, "" for none
    std::vector<int> candidates(const ocl::DeviceInfo* device) const;  // device null: all of them
    // Whether device takes the parameter (has its extension); elsewhere it keeps its first value.
    bool applies_to(const ocl::DeviceInfo& device) const {
        return extension.empty() || device.has_extension(extension);
    }
};

struct TunedKernel {
    std::string name;    // kEvaluateKernel, kTraceKernel
    std::string option;  // its name for `tune --kernels`: "evaluate", "trace"
    std::vector<TunedParam> params;
    // The stages whose device time is the cost (summed per capture, minimum over the captures), and
    // in words.
    std::vector<measure::Stage> objective;
    std::string objective_text;
    // How the tuner measures it: Work::construct (a build per configuration), or Work::trace (trace
    // passes over bricks built once).
    pipeline::Work work = pipeline::Work::construct;
    // Work-items per work-group, and the fewest a configuration may have.
    std::function<std::size_t(const Config&)> work_items;
    std::size_t min_work_items = 1;
    // Bytes of __local memory a work-group stages.
    std::function<std::uint64_t(const Config&)> local_mem_bytes;
    // Further constraints, "" when met, else why not: on every device (may be null), and on this one
    // (may be null). Beyond these, a device must allow work_items per work-group and local_mem_bytes.
    std::function<std::string(const Config&)> check;
    std::function<std::string(const Config&, const ocl::DeviceInfo&)> check_device;
    // Reads a configuration from settings, and applies one to them.
    std::function<Config(const construct::BuildSettings&, const render::TraceSettings&)> read;
    std::function<void(const Config&, construct::BuildSettings&, render::TraceSettings&)> apply;
    // The configuration as reports print it: "chunk 64 group 128", "16x8".
    std::function<std::string(const Config&)> describe;

    // The search space; with a device, capped to what it allows.
    Space space(const ocl::DeviceInfo* device = nullptr) const;
    bool in_space(const Config& c) const;  // every parameter present (or completed) and among its candidates
    // c with each missing parameter that needs an extension set to its first value (TunedParam).
    Config completed(Config c) const;
    // The built-in default: the values of BuildSettings{} and TraceSettings{}.
    Config default_config() const;
    // "" when c gives every parameter and meets the constraints (with a device, also that device's
    // limits), else the first reason it is refused. Membership of the space is not required.
    std::string refuses(const Config& c, const ocl::DeviceInfo* device = nullptr) const;
};

const TunedKernel& evaluate_kernel();
const TunedKernel& trace_kernel();
// Both, in the order the tuner runs them (the trace is measured over bricks built with the evaluate
// kernel's result).
std::span<const TunedKernel* const> tuned_kernels();
// By name (kEvaluateKernel) or option ("evaluate"); null when there is none.
const TunedKernel* find_kernel(std::string_view name_or_option);

}  // namespace sdfbrick::tune
