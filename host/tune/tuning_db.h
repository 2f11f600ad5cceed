// The tuning database: tuned launch parameters per device (name and driver) and kernel, in two layers:
// the user's file, written by `sdfbrick tune`, over a compiled-in layer of values measured on known
// devices (tune/builtin_db.cpp), so that a first run on such a device is already tuned. Every later run
// reads it. Look-up: the file's entry of the device and driver, else the file's most recent entry of
// the vendor, else the compiled-in entry of the device name (any driver), else the compiled-in entry of
// the vendor, else the built-in default; the result says which (Source).
//
// File: $SDFBRICK_TUNING_DB, else $XDG_CONFIG_HOME/sdfbrick/tuning.json, else
// $HOME/.config/sdfbrick/tuning.json ("off" turns tuning off: no database, neither layer). Format
// (docs/tuning.md):
//   {"format": "sdfbrick tuning 1", "entries": [{"device": ..., "driver": ..., "vendor": ...,
//    "kernel": "brick_evaluate", "params": {"chunk": 64, "group": 128}, "time_ms": ..., "tuned_at": ...,
//    "default_ms": ..., "scene": ..., "brick_size": ..., "strategy": ..., "evaluated": N, "space": N}]}
#pragma once

#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <string_view>
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

// Where a look-up's values came from, in look-up order. fallback: the built-in default.
enum class Source { device, vendor, builtin_device, builtin_vendor, fallback };
// "device", "vendor", "builtin device", "builtin vendor", "default"
std::string_view to_string(Source s);
// The layer of a source: "file" (device, vendor), "builtin" (builtin_*), "default".
std::string_view layer_of(Source s);

struct Lookup {
    std::map<std::string, int> params;  // empty for the built-in default
    Source source = Source::fallback;
    const Entry* entry = nullptr;
};

// The compiled-in layer: values measured on known devices, in the order measured (tune/builtin_db.cpp).
const std::vector<Entry>& builtin_entries();

// Whether a database has the compiled-in layer under the user's entries. Unit tests that need "no entry
// means the default" use without_builtin.
enum class Layers { with_builtin, without_builtin };

class TuningDb {
public:
    explicit TuningDb(Layers layers = Layers::with_builtin) : builtin_(layers == Layers::with_builtin) {}

    // The database file now in effect, or std::nullopt when it is off.
    static std::optional<std::filesystem::path> default_path();
    // Reads path; a missing file gives an empty database. Throws InputError for a file that is not a
    // tuning database (naming the file and the problem).
    static TuningDb load(const std::filesystem::path& path, Layers layers = Layers::with_builtin);

    // The file's entry for (device, driver, kernel), else its most recently tuned entry of the vendor
    // for the kernel, else the compiled-in entry of the device name (the driver's own first, else the
    // most recent), else the compiled-in layer's most recent entry of the vendor, else the default.
    Lookup find(const std::string& device, const std::string& driver, const std::string& vendor,
                const std::string& kernel) const;
    // Adds or replaces the file's entry of (device, driver, kernel).
    void put(Entry e);
    const std::vector<Entry>& entries() const { return entries_; }  // the file's
    bool has_builtin() const { return builtin_; }

    nlohmann::json to_json() const;                      // the file's entries only
    void save(const std::filesystem::path& path) const;  // atomically

private:
    std::vector<Entry> entries_;  // the file's, in the order tuned (later = more recent)
    bool builtin_ = true;
};

}  // namespace sdfbrick::tune
