// The tuning database: tuned launch parameters per device (name and driver) and kernel, written by
// `sdfbrick tune`, read by every later run. Look-up falls back device -> vendor -> built-in
// default, and says which one it used.
//
// File: $SDFBRICK_TUNING_DB, else $XDG_CONFIG_HOME/sdfbrick/tuning.json, else
// $HOME/.config/sdfbrick/tuning.json ("off" disables it). Format (docs/tuning.md):
//   {"format": "sdfbrick tuning 1", "entries": [{"device": ..., "driver": ..., "vendor": ...,
//    "kernel": "brick_evaluate", "params": {"chunk": 64, "group": 128}, "time_ms": ..., "tuned_at": ...,
//    "scene": ..., "settings": {...}, "strategy": ..., "evaluated": N, "space": N}]}
#pragma once

#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace sdfbrick::tune {

inline constexpr const char* kTuningDbEnv = "SDFBRICK_TUNING_DB";

struct Entry {
    std::string device, driver, vendor;
    std::string kernel;
    std::map<std::string, int> params;
    nlohmann::json record;  // everything else written by tune (time, scene, settings, strategy, ...)
};

enum class Source { device, vendor, fallback };  // fallback: the built-in default
std::string_view to_string(Source s);            // "device", "vendor", "default"

struct Lookup {
    std::map<std::string, int> params;  // empty for the built-in default
    Source source = Source::fallback;
    const Entry* entry = nullptr;
};

class TuningDb {
public:
    // The database file now in effect, or std::nullopt when it is off.
    static std::optional<std::filesystem::path> default_path();
    // Reads path; a missing file gives an empty database. Throws InputError for a file that is not a
    // tuning database (naming the file and the problem).
    static TuningDb load(const std::filesystem::path& path);

    // The entry for (device, driver, kernel), else the most recently tuned entry of the vendor for
    // the kernel, else the default.
    Lookup find(const std::string& device, const std::string& driver, const std::string& vendor,
                const std::string& kernel) const;
    // Adds or replaces the entry of (device, driver, kernel).
    void put(Entry e);
    const std::vector<Entry>& entries() const { return entries_; }

    nlohmann::json to_json() const;
    void save(const std::filesystem::path& path) const;  // atomically

private:
    std::vector<Entry> entries_;  // in the order tuned (later = more recent)
};

}  // namespace sdfbrick::tune
