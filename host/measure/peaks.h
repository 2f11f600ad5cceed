// A device's measured peaks, as clpeak measures them (kernels/peak.cl): global-memory bandwidth
// (a float4 copy kernel) and FP32 FMA throughput (chains of explicit fma() in registers, float4 and
// float16, the better of the two). Device time comes from profiling events; each figure is the best of
// a few repeats after a warm-up. Work rates of the engine's stages are reported against them.
#pragma once

#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "cl/device.h"

namespace sdfbrick::measure {

struct DevicePeaks {
    double bandwidth_gbps = 0;  // bytes read + written per second, 1e9 bytes/s
    double fma_gflops = 0;      // 2 FLOP per FMA lane, 1e9 FLOP/s
    std::string device, driver;
    std::string measured_at;    // ISO 8601 UTC, e.g. "2025-01-31T12:34:56.789Z"
    bool cached = false;        // device_peaks found them in the cache (not part of to_json)
};

// Measures now. The bandwidth buffers hold min(256 MiB, max allocation / 4, global memory / 8) on GPUs
// and accelerators, and at most 32 MiB elsewhere (CPU devices), so a CPU measurement stays short.
// Throws ClError when a build or launch fails.
DevicePeaks measure_peaks(ocl::Device& device);

// The cached peaks of the device (matched by device name and driver version) in <cache dir>/peaks.json,
// the cache directory being ocl::program_cache_dir(); on a miss, with refresh, or when the entry or the
// file is damaged, measures and rewrites the file atomically (a file that cannot be written is left
// alone: the figures are still returned). With the cache off, measures every time.
DevicePeaks device_peaks(ocl::Device& device, bool refresh = false);

// The cached peaks of the device, without measuring; none on a miss or with the cache off.
std::optional<DevicePeaks> cached_peaks(const ocl::DeviceInfo& device);

// {"device", "driver", "bandwidth_gbps", "fma_gflops", "measured_at"}.
nlohmann::json to_json(const DevicePeaks& peaks);

// Name of the cache file inside the cache directory.
inline constexpr const char* kPeaksFile = "peaks.json";

}  // namespace sdfbrick::measure
