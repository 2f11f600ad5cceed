#include "tune/kernels.h"

#include <algorithm>
#include <array>
#include <limits>

#include <fmt/format.h>

#include "core/errors.h"

namespace sdfbrick::tune {

namespace {

// " registers N" for a configuration with a register cap, "" without one.
std::string registers_text(const Config& c) {
    const int r = c.contains("registers") ? c.at("registers") : 0;
    return r > 0 ? fmt::format(" registers {}", r) : "";
}

// A device without limits: BuildSettings::validate against it checks only what holds on every device.
ocl::DeviceInfo unbounded_device() {
    ocl::DeviceInfo d;
    d.name = "any device";
    d.max_work_group_size = std::numeric_limits<std::size_t>::max();
    d.local_mem_bytes = std::numeric_limits<std::uint64_t>::max();
    return d;
}

std::string validate_build(const Config& c, const ocl::DeviceInfo& device) {
    construct::BuildSettings s;
    render::TraceSettings unused;
    evaluate_kernel().apply(c, s, unused);
    try {
        s.validate(device);
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

// brick_evaluate: each work-group evaluates one brick, staging `chunk` edits at a time in __local
// memory (brick_count stages the same chunk) with their skip records, and 64 uints of bookkeeping.
// registers: the cap on registers per work-item (0: none), on NVIDIA's compiler only; on an H100 a
// cap of 64 took drops' evaluation from 3.00 to 2.93 ms and rubble's from 12.66 to 12.15, with the
// same bits (docs/performance.md).
TunedKernel make_evaluate() {
    TunedKernel k;
    k.name = kEvaluateKernel;
    k.option = "evaluate";
    k.params = {{"chunk", 16, 256, false, {}, ""},
                {"group", 8, 1024, true, {}, ""},
                {"registers", 0, 0, false, {0, 64, 56, 48}, "cl_nv_compiler_options"}};
    k.objective = {measure::Stage::count, measure::Stage::evaluate};
    k.objective_text = "count + evaluate stages";
    k.work = pipeline::Work::construct;
    k.work_items = [](const Config& c) { return static_cast<std::size_t>(c.at("group")); };
    k.local_mem_bytes = [](const Config& c) {
        return construct::BuildSettings::evaluation_local_bytes(c.at("chunk"));
    };
    k.check = [](const Config& c) { return validate_build(c, unbounded_device()); };
    k.check_device = [](const Config& c, const ocl::DeviceInfo& d) { return validate_build(c, d); };
    k.read = [](const construct::BuildSettings& s, const render::TraceSettings&) {
        return Config{{"chunk", s.chunk}, {"group", s.eval_group}, {"registers", s.eval_registers}};
    };
    k.apply = [](const Config& c, construct::BuildSettings& s, render::TraceSettings&) {
        s.chunk = c.at("chunk");
        s.eval_group = c.at("group");
        s.eval_registers = c.contains("registers") ? c.at("registers") : 0;
    };
    k.describe = [](const Config& c) {
        return fmt::format("chunk {} group {}{}", c.at("chunk"), c.at("group"), registers_text(c));
    };
    return k;
}

// trace_primary: one ray per work-item, group_x x group_y pixels per work-group; no __local memory.
// Fewer than 16 work-items leave most of a SIMD unit idle on every device measured. registers: the
// cap on registers per work-item of the trace and shade kernels (0: none), on NVIDIA's compiler only.
// On the H200 a cap of 64 took drops' 4K hybrid trace from 4.17 to 3.57 ms and the analytic one from
// 5.03 to 4.17 (occupancy 25% -> 50%), with the same images (docs/performance.md).
TunedKernel make_trace() {
    TunedKernel k;
    k.name = kTraceKernel;
    k.option = "trace";
    k.params = {{"group_x", 4, 64, false, {}, ""},
                {"group_y", 1, 32, false, {}, ""},
                {"registers", 0, 0, false, {0, 64, 96}, "cl_nv_compiler_options"}};
    k.objective = {measure::Stage::trace};
    k.objective_text = "trace stage";
    k.work = pipeline::Work::trace;
    k.work_items = [](const Config& c) { return static_cast<std::size_t>(c.at("group_x")) * c.at("group_y"); };
    k.min_work_items = 16;
    k.local_mem_bytes = [](const Config&) { return std::uint64_t{0}; };
    k.read = [](const construct::BuildSettings&, const render::TraceSettings& t) {
        return Config{{"group_x", t.group_x}, {"group_y", t.group_y}, {"registers", t.max_registers}};
    };
    k.apply = [](const Config& c, construct::BuildSettings&, render::TraceSettings& t) {
        t.group_x = c.at("group_x");
        t.group_y = c.at("group_y");
        t.max_registers = c.contains("registers") ? c.at("registers") : 0;
    };
    k.describe = [](const Config& c) {
        return fmt::format("{}x{}{}", c.at("group_x"), c.at("group_y"), registers_text(c));
    };
    return k;
}

}  // namespace

std::vector<int> TunedParam::candidates(const ocl::DeviceInfo* device) const {
    std::vector<int> v = values;
    for (long long x = lo; values.empty() && x <= hi; x *= 2) {
        if (device_capped && device && static_cast<std::size_t>(x) > device->max_work_group_size) break;
        v.push_back(static_cast<int>(x));
    }
    if (device && !applies_to(*device)) v.resize(1);
    return v;
}

Space TunedKernel::space(const ocl::DeviceInfo* device) const {
    Space s;
    for (const TunedParam& p : params) s.dims.emplace_back(p.name, p.candidates(device));
    return s;
}

Config TunedKernel::completed(Config c) const {
    for (const TunedParam& p : params)
        if (!p.extension.empty()) c.try_emplace(p.name, p.values.front());
    return c;
}

bool TunedKernel::in_space(const Config& given) const {
    const Config c = completed(given);
    if (c.size() != params.size()) return false;
    return std::all_of(params.begin(), params.end(), [&](const TunedParam& p) {
        const auto it = c.find(p.name);
        const std::vector<int> values = p.candidates(nullptr);
        return it != c.end() && std::find(values.begin(), values.end(), it->second) != values.end();
    });
}

Config TunedKernel::default_config() const { return read(construct::BuildSettings{}, render::TraceSettings{}); }

std::string TunedKernel::refuses(const Config& given, const ocl::DeviceInfo* device) const {
    const Config c = completed(given);
    for (const TunedParam& p : params)
        if (!c.contains(p.name)) return fmt::format("{} needs a value of {}", name, p.name);
    const std::size_t items = work_items(c);
    if (items < min_work_items)
        return fmt::format("{} {} is {} work-items; {} needs at least {}", name, describe(c), items, name, min_work_items);
    if (check)
        if (std::string why = check(c); !why.empty()) return why;
    if (!device) return "";
    if (items > device->max_work_group_size)
        return fmt::format("{} {} is {} work-items; {} allows {} per work-group", name, describe(c), items, device->name,
                           device->max_work_group_size);
    if (const std::uint64_t local = local_mem_bytes(c); local > device->local_mem_bytes)
        return fmt::format("{} {} needs {} bytes of local memory; {} has {}", name, describe(c), local, device->name,
                           device->local_mem_bytes);
    return check_device ? check_device(c, *device) : "";
}

const TunedKernel& evaluate_kernel() {
    static const TunedKernel k = make_evaluate();
    return k;
}

const TunedKernel& trace_kernel() {
    static const TunedKernel k = make_trace();
    return k;
}

std::span<const TunedKernel* const> tuned_kernels() {
    static const std::array<const TunedKernel*, 2> all = {&evaluate_kernel(), &trace_kernel()};
    return all;
}

const TunedKernel* find_kernel(std::string_view name_or_option) {
    for (const TunedKernel* k : tuned_kernels())
        if (k->name == name_or_option || k->option == name_or_option) return k;
    return nullptr;
}

}  // namespace sdfbrick::tune
