// Tuning results others read: the T4 open auto-tuning results format (schema 1.0.0, the one Kernel
// Tuner and KTT read and write; docs/tuning.md cites it). A tuning run's every measured configuration
// becomes one T4 result; a T4 file's best valid result for a kernel can become a database entry for a
// device the database has none for.
#pragma once

#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "cl/device.h"
#include "tune/kernels.h"
#include "tune/tuning_db.h"

namespace sdfbrick::tune {

inline constexpr const char* kT4SchemaVersion = "1.0.0";

// The T4 results document of a tuning run: `devices` is the tune report's "devices" array (one
// tune_device report each). Each result: "timestamp", "configuration" (the kernel's parameters),
// "objectives" ["time"], "times" {"runtimes": [ms]}, "invalidity" ("correct", or "runtime" for a
// configuration the device could not run), "correctness", "measurements" [{"name": "time", "value",
// "unit": "ms"}], and sdfbrick's own "kernel" and "device" (T4 allows further properties).
nlohmann::json t4_results(const nlohmann::json& devices, const std::string& timestamp);

// The best result of `doc` for `kernel`: valid ("correct"), with a time, and a configuration of
// exactly the kernel's parameters (integers; one that needs an extension may be missing: TunedParam)
// that the device can run; a result that names its kernel must name this one. Throws InputError
// (naming `where` and the JSON path) for a document that is not T4 results; std::nullopt when no
// result fits.
struct T4Best {
    Config params;
    double ms = 0.0;
    std::size_t index = 0;  // of the result in the document
};
std::optional<T4Best> best_t4_result(const nlohmann::json& doc, const TunedKernel& kernel, const ocl::DeviceInfo& device,
                                     const std::string& where);

// The database entry for device made from a T4 best result (record: source "T4", the file, ms).
Entry t4_entry(const T4Best& best, const TunedKernel& kernel, const ocl::DeviceInfo& device, const std::string& where,
               const std::string& imported_at);

}  // namespace sdfbrick::tune
