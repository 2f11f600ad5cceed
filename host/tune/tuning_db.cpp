#include "tune/tuning_db.h"

#include <cstdlib>

#include <fmt/format.h>

#include "core/errors.h"
#include "core/files.h"

namespace sdfbrick::tune {

namespace {

constexpr const char* kFormat = "sdfbrick tuning 1";

}  // namespace

std::string_view to_string(Source s) {
    switch (s) {
        case Source::device: return "device";
        case Source::vendor: return "vendor";
        case Source::builtin_device: return "builtin device";
        case Source::builtin_vendor: return "builtin vendor";
        case Source::fallback: return "default";
    }
    return "?";
}

std::string_view layer_of(Source s) {
    switch (s) {
        case Source::device:
        case Source::vendor: return "file";
        case Source::builtin_device:
        case Source::builtin_vendor: return "builtin";
        case Source::fallback: return "default";
    }
    return "?";
}

std::optional<std::filesystem::path> TuningDb::default_path() { return config_file(kTuningDbEnv, "tuning.json"); }

TuningDb TuningDb::load(const std::filesystem::path& path, Layers layers) {
    TuningDb db(layers);
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) return db;
    const auto bad = [&](const std::string& what) {
        return InputError(fmt::format("tuning database {}: {} (fix or delete the file, or run without the tuning database)",
                                      path.string(), what));
    };
    nlohmann::json j;
    try {
        j = nlohmann::json::parse(read_file(path));
    } catch (const nlohmann::json::exception& e) {
        throw bad(fmt::format("not valid JSON ({})", e.what()));
    }
    if (!j.is_object() || j.value("format", "") != kFormat || !j.contains("entries") || !j["entries"].is_array())
        throw bad(fmt::format("not a tuning database (expected {{\"format\": \"{}\", \"entries\": [...]}})", kFormat));
    for (std::size_t i = 0; i < j["entries"].size(); ++i) {
        const nlohmann::json& e = j["entries"][i];
        try {
            Entry entry{e.at("device").get<std::string>(), e.at("driver").get<std::string>(),
                        e.at("vendor").get<std::string>(), e.at("kernel").get<std::string>(),
                        e.at("params").get<std::map<std::string, int>>(), e};
            for (const char* k : {"device", "driver", "vendor", "kernel", "params"}) entry.record.erase(k);
            db.entries_.push_back(std::move(entry));
        } catch (const nlohmann::json::exception& ex) {
            throw bad(fmt::format("entry {}: {}", i, ex.what()));
        }
    }
    return db;
}

namespace {

// The user's file: the device and driver, else the vendor's most recent entry.
Lookup find_in_file(const std::vector<Entry>& entries, const std::string& device, const std::string& driver,
                    const std::string& vendor, const std::string& kernel) {
    const Entry* by_vendor = nullptr;
    for (const Entry& e : entries) {
        if (e.kernel != kernel) continue;
        if (e.device == device && e.driver == driver) return {e.params, Source::device, &e};
        if (e.vendor == vendor) by_vendor = &e;  // the last one is the most recent
    }
    if (by_vendor) return {by_vendor->params, Source::vendor, by_vendor};
    return {};
}

// The compiled-in layer: the device name whatever the driver (its own driver's entry first), else the
// vendor's most recent entry.
Lookup find_builtin(const std::string& device, const std::string& driver, const std::string& vendor,
                    const std::string& kernel) {
    const Entry *by_name = nullptr, *by_vendor = nullptr;
    for (const Entry& e : builtin_entries()) {
        if (e.kernel != kernel) continue;
        if (e.device == device && (by_name == nullptr || by_name->driver != driver)) by_name = &e;
        if (e.vendor == vendor) by_vendor = &e;
    }
    if (by_name) return {by_name->params, Source::builtin_device, by_name};
    if (by_vendor) return {by_vendor->params, Source::builtin_vendor, by_vendor};
    return {};
}

}  // namespace

Lookup TuningDb::find(const std::string& device, const std::string& driver, const std::string& vendor,
                      const std::string& kernel) const {
    if (Lookup l = find_in_file(entries_, device, driver, vendor, kernel); l.entry) return l;
    if (builtin_) return find_builtin(device, driver, vendor, kernel);
    return {};
}

void TuningDb::put(Entry e) {
    std::erase_if(entries_, [&](const Entry& x) { return x.device == e.device && x.driver == e.driver && x.kernel == e.kernel; });
    entries_.push_back(std::move(e));
}

nlohmann::json TuningDb::to_json() const {
    nlohmann::json entries = nlohmann::json::array();
    for (const Entry& e : entries_) {
        nlohmann::json j = e.record;
        j.update({{"device", e.device}, {"driver", e.driver}, {"vendor", e.vendor}, {"kernel", e.kernel},
                  {"params", e.params}});
        entries.push_back(std::move(j));
    }
    return {{"format", kFormat}, {"entries", entries}};
}

void TuningDb::save(const std::filesystem::path& path) const {
    if (path.has_parent_path()) std::filesystem::create_directories(path.parent_path());
    write_file_atomic(path, to_json().dump(2) + "\n");
}

}  // namespace sdfbrick::tune
