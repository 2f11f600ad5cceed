#include "tune/t4.h"

#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "core/errors.h"
#include "core/quote.h"

namespace sdfbrick::tune {

namespace {

nlohmann::json t4_result(const nlohmann::json& configuration, const nlohmann::json& ms, const std::string& kernel,
                         const std::string& device, const std::string& timestamp) {
    const bool ran = ms.is_number();
    nlohmann::json r = {{"timestamp", timestamp},
                        {"configuration", configuration},
                        {"objectives", {"time"}},
                        {"times", {{"runtimes", ran ? nlohmann::json::array({ms}) : nlohmann::json::array()}}},
                        {"invalidity", ran ? "correct" : "runtime"},
                        {"correctness", ran ? 1 : 0},
                        {"measurements", nlohmann::json::array()},
                        {"kernel", kernel},
                        {"device", device}};
    if (ran) r["measurements"].push_back({{"name", "time"}, {"value", ms}, {"unit", "ms"}});
    return r;
}

// The time of a result: its "time" measurement in ms (or s), else its first runtime; nullopt if none.
std::optional<double> result_ms(const nlohmann::json& r) {
    if (const auto m = r.find("measurements"); m != r.end() && m->is_array())
        for (const auto& x : *m)
            if (x.is_object() && x.value("name", "") == "time" && x.contains("value") && x["value"].is_number()) {
                const std::string unit = x.value("unit", "ms");
                return x["value"].get<double>() * (unit == "s" ? 1000.0 : unit == "us" ? 1e-3 : 1.0);
            }
    if (const auto t = r.find("times"); t != r.end() && t->is_object())
        if (const auto rt = t->find("runtimes"); rt != t->end() && rt->is_array() && !rt->empty() && (*rt)[0].is_number())
            return (*rt)[0].get<double>();
    return std::nullopt;
}

// The configuration as the kernel's parameters, or nullopt when it names others or non-integers.
std::optional<Config> kernel_config(const nlohmann::json& c, const TunedKernel& kernel) {
    if (!c.is_object()) return std::nullopt;
    Config out;
    std::size_t read = 0;
    for (const TunedParam& p : kernel.params) {
        const auto it = c.find(p.name);
        if (it == c.end() && !p.extension.empty()) continue;  // written before the parameter existed
        if (it == c.end() || !it->is_number_integer()) return std::nullopt;
        ++read;
        const auto v = it->get<std::int64_t>();
        if (v < std::numeric_limits<int>::min() || v > std::numeric_limits<int>::max()) return std::nullopt;
        out[p.name] = static_cast<int>(v);
    }
    if (read != c.size()) return std::nullopt;  // a parameter the kernel does not have
    return kernel.completed(out);
}

}  // namespace

nlohmann::json t4_results(const nlohmann::json& devices, const std::string& timestamp) {
    nlohmann::json results = nlohmann::json::array();
    for (const nlohmann::json& d : devices) {
        const std::string device = d.contains("device") ? d["device"].value("name", "") : "";
        for (const auto& [kernel, rec] : d.items()) {
            if (!rec.is_object() || !rec.contains("evaluated_configurations")) continue;
            for (const nlohmann::json& e : rec["evaluated_configurations"])
                results.push_back(t4_result(e.at("params"), e.at("ms"), kernel, device, timestamp));
        }
    }
    return {{"schema_version", kT4SchemaVersion}, {"results", results}};
}

std::optional<T4Best> best_t4_result(const nlohmann::json& doc, const TunedKernel& kernel, const ocl::DeviceInfo& device,
                                     const std::string& where) {
    if (!doc.is_object() || !doc.contains("results") || !doc["results"].is_array())
        throw InputError(fmt::format("{}: not T4 tuning results (expected an object with a \"results\" array)", where));
    if (const auto v = doc.find("schema_version"); v != doc.end() && (!v->is_string() || v->get<std::string>().rfind("1.", 0) != 0))
        throw InputError(fmt::format("{}: /schema_version: T4 results {} are not read (1.x.y are)", where, escaped(v->dump())));
    std::optional<T4Best> best;
    const nlohmann::json& results = doc["results"];
    for (std::size_t i = 0; i < results.size(); ++i) {
        const nlohmann::json& r = results[i];
        if (!r.is_object()) throw InputError(fmt::format("{}: /results/{}: expected a result object", where, i));
        if (r.value("invalidity", "correct") != "correct") continue;
        if (r.contains("kernel") && r["kernel"] != kernel.name) continue;
        const std::optional<Config> c = kernel_config(r.value("configuration", nlohmann::json()), kernel);
        const std::optional<double> ms = result_ms(r);
        if (!c || !ms || !std::isfinite(*ms) || *ms <= 0.0 || !kernel.refuses(*c, &device).empty()) continue;
        if (!best || *ms < best->ms) best = T4Best{*c, *ms, i};
    }
    return best;
}

Entry t4_entry(const T4Best& best, const TunedKernel& kernel, const ocl::DeviceInfo& device, const std::string& where,
               const std::string& imported_at) {
    const nlohmann::json record = {{"time_ms", best.ms}, {"source", "T4"},           {"file", where},
                                   {"result", best.index}, {"tuned_at", imported_at}, {"platform", device.platform_name}};
    return {device.name, device.driver_version, device.vendor, kernel.name, best.params, record};
}

}  // namespace sdfbrick::tune
