#include "measure/peaks.h"

#include <CL/cl.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <filesystem>
#include <limits>
#include <optional>
#include <stdexcept>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "cl/buffer.h"
#include "cl/launch.h"
#include "cl/program.h"
#include "core/files.h"
#include "measure/scheduler.h"

namespace sdfbrick::measure {

namespace {

constexpr const char* kCacheFormat = "sdfbrick peaks 1";
constexpr double kFlopPerIterationAndLane = 256.0;  // per work-item, loop iteration and vector lane of peak_fma
constexpr int kBandwidthRepeats = 5;
constexpr int kFmaRepeats = 3;
constexpr double kFmaTargetMs = 20.0;  // device time of one timed FMA launch
constexpr cl_uint kMaxFmaIterations = 1u << 20;

std::string now_iso() {
    const auto now = std::chrono::system_clock::now();
    const std::time_t seconds = std::chrono::system_clock::to_time_t(now);
    const auto ms = std::chrono::duration_cast<std::chrono::milliseconds>(now.time_since_epoch()).count() % 1000;
    std::tm utc{};
    gmtime_r(&seconds, &utc);
    char text[32];
    std::strftime(text, sizeof(text), "%Y-%m-%dT%H:%M:%S", &utc);
    return fmt::format("{}.{:03}Z", text, ms);
}

double device_ms(ocl::Device& device, cl_kernel kernel, const char* name, std::size_t global) {
    Scheduler scheduler(device);
    scheduler.launch(Stage::peaks, -1, kernel, global);
    const double ms = scheduler.resolve().front().device_ms;
    if (!(ms > 0.0)) {
        throw std::runtime_error(fmt::format("kernel {} on {} took {} ms of device time by its profiling events: "
                                             "no peak can be derived from that",
                                             name, device.info().name, ms));
    }
    return ms;
}

double measure_bandwidth(ocl::Device& device) {
    const ocl::Program program = ocl::build_program(device, "peak.cl");
    const ocl::DeviceInfo& info = device.info();
    const bool gpu_like = info.type == "gpu" || info.type == "accelerator";
    std::uint64_t bytes = std::min<std::uint64_t>(gpu_like ? 256ull << 20 : 32ull << 20, info.max_alloc_bytes / 4);
    if (gpu_like) {
        bytes = std::min<std::uint64_t>(bytes, info.global_mem_bytes / 8);
    }
    const std::size_t count = static_cast<std::size_t>(bytes / 16 / 1024 * 1024);  // float4s, a multiple of 1024
    ocl::Buffer<cl_float4> in(device, count, CL_MEM_READ_WRITE);  // peak_fill writes it
    ocl::Buffer<cl_float4> out(device, count, CL_MEM_WRITE_ONLY);
    const ocl::Kernel fill = ocl::make_kernel(program, "peak_fill");
    ocl::set_args(fill.get(), in);
    const ocl::Kernel copy = ocl::make_kernel(program, "peak_copy");
    ocl::set_args(copy.get(), in, out);
    device_ms(device, fill.get(), "peak_fill", count);
    device_ms(device, copy.get(), "peak_copy", count);  // warm-up
    double best = std::numeric_limits<double>::infinity();
    for (int r = 0; r < kBandwidthRepeats; ++r) {
        best = std::min(best, device_ms(device, copy.get(), "peak_copy", count));
    }
    return 2.0 * static_cast<double>(count * sizeof(cl_float4)) / (best * 1e6);
}

// GFLOP/s of peak_fma built with PEAK_WIDTH = width.
double measure_fma(ocl::Device& device, int width) {
    const ocl::Program program = ocl::build_program(device, "peak.cl", fmt::format("-DPEAK_WIDTH={}", width));
    const ocl::DeviceInfo& info = device.info();
    const bool gpu_like = info.type == "gpu" || info.type == "accelerator";
    // Enough work-groups for every compute unit, several times over on GPUs to hide latency.
    const std::size_t items = std::max<std::size_t>(info.compute_units, 1) *
                              std::clamp<std::size_t>(info.max_work_group_size, 64, 1024) * (gpu_like ? 4 : 1);
    ocl::Buffer<float> out(device, items * static_cast<std::size_t>(width), CL_MEM_WRITE_ONLY);
    const ocl::Kernel kernel = ocl::make_kernel(program, "peak_fma");
    const auto run = [&](cl_uint iterations) {
        ocl::set_args(kernel.get(), out, 0.9999f, 0.0001f, iterations);
        return device_ms(device, kernel.get(), "peak_fma", items);
    };
    // Calibrates the iteration count so that a launch takes about kFmaTargetMs of device time.
    cl_uint iterations = 16;
    for (double ms = run(iterations); ms < kFmaTargetMs / 2 && iterations < kMaxFmaIterations;) {
        const double factor = std::clamp(kFmaTargetMs / std::max(ms, 1e-3), 2.0, 64.0);
        iterations = static_cast<cl_uint>(std::min<double>(iterations * factor, kMaxFmaIterations));
        ms = run(iterations);
    }
    double best = std::numeric_limits<double>::infinity();
    for (int r = 0; r < kFmaRepeats; ++r) {
        best = std::min(best, run(iterations));
    }
    return static_cast<double>(items) * iterations * width * kFlopPerIterationAndLane / (best * 1e6);
}

std::optional<DevicePeaks> from_json(const nlohmann::json& j) {
    try {
        DevicePeaks p;
        p.device = j.at("device").get<std::string>();
        p.driver = j.at("driver").get<std::string>();
        p.bandwidth_gbps = j.at("bandwidth_gbps").get<double>();
        p.fma_gflops = j.at("fma_gflops").get<double>();
        p.measured_at = j.at("measured_at").get<std::string>();
        const auto valid = [](double x) { return std::isfinite(x) && x > 0; };
        if (!valid(p.bandwidth_gbps) || !valid(p.fma_gflops)) {
            return std::nullopt;
        }
        return p;
    } catch (const nlohmann::json::exception&) {
        return std::nullopt;
    }
}

// The valid entries of the cache file; none when it is missing or damaged.
std::vector<DevicePeaks> read_cache(const std::filesystem::path& file) {
    std::vector<DevicePeaks> entries;
    std::error_code error;
    if (!std::filesystem::is_regular_file(file, error)) {
        return entries;
    }
    try {
        const nlohmann::json doc = nlohmann::json::parse(read_file(file));
        if (doc.is_object() && doc.value("format", "") == kCacheFormat && doc.contains("devices") &&
            doc["devices"].is_array()) {
            for (const nlohmann::json& e : doc["devices"]) {
                if (std::optional<DevicePeaks> p = from_json(e)) {
                    entries.push_back(std::move(*p));
                }
            }
        }
    } catch (const std::exception&) {  // unreadable (InputError), not JSON, or of the wrong types
    }
    return entries;
}

}  // namespace

DevicePeaks measure_peaks(ocl::Device& device) {
    DevicePeaks p;
    p.device = device.info().name;
    p.driver = device.info().driver_version;
    p.bandwidth_gbps = measure_bandwidth(device);
    // The better of float4 and float16 chains: GPUs run either lane by lane, while CPU devices fill
    // their SIMD units only with the wide one (float4 leaves AVX-512 at a quarter of its rate).
    p.fma_gflops = std::max(measure_fma(device, 4), measure_fma(device, 16));
    p.measured_at = now_iso();
    return p;
}

std::optional<DevicePeaks> cached_peaks(const ocl::DeviceInfo& device) {
    const std::optional<std::filesystem::path> dir = ocl::program_cache_dir();
    if (!dir) return std::nullopt;
    for (DevicePeaks& p : read_cache(*dir / kPeaksFile))
        if (p.device == device.name && p.driver == device.driver_version) {
            p.cached = true;
            return p;
        }
    return std::nullopt;
}

DevicePeaks device_peaks(ocl::Device& device, bool refresh) {
    const std::optional<std::filesystem::path> dir = ocl::program_cache_dir();
    if (!dir) {
        return measure_peaks(device);
    }
    if (!refresh) {
        if (std::optional<DevicePeaks> cached = cached_peaks(device.info())) return *cached;
    }
    const std::filesystem::path file = *dir / kPeaksFile;
    std::vector<DevicePeaks> entries = read_cache(file);
    const auto same_device = [&](const DevicePeaks& p) {
        return p.device == device.info().name && p.driver == device.info().driver_version;
    };
    const DevicePeaks measured = measure_peaks(device);
    std::erase_if(entries, same_device);
    entries.push_back(measured);
    nlohmann::json kept = nlohmann::json::array();
    for (const DevicePeaks& p : entries) {
        kept.push_back(to_json(p));
    }
    try {
        std::filesystem::create_directories(*dir);
        write_file_atomic(file, nlohmann::json{{"format", kCacheFormat}, {"devices", kept}}.dump(2) + "\n");
    } catch (const std::exception&) {
        // A cache that cannot be written costs a re-measurement next time, nothing more.
    }
    return measured;
}

nlohmann::json to_json(const DevicePeaks& p) {
    return {{"device", p.device},
            {"driver", p.driver},
            {"bandwidth_gbps", p.bandwidth_gbps},
            {"fma_gflops", p.fma_gflops},
            {"measured_at", p.measured_at}};
}

}  // namespace sdfbrick::measure
