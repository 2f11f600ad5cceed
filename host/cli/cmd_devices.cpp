#include <algorithm>
#include <cstdio>
#include <map>
#include <memory>

#include <fmt/format.h>

#include "cl/device.h"
#include "cli/commands.h"
#include "measure/peaks.h"

namespace sdfbrick::cli {

namespace {

// Peaks of the selected devices by global index: from the cache, measured when missing (or always
// with refresh).
std::map<std::size_t, measure::DevicePeaks> selected_peaks(const GlobalOptions& global, bool refresh) {
    apply_global_options(global);
    std::map<std::size_t, measure::DevicePeaks> peaks;
    ocl::DeviceSet devices = ocl::DeviceSet::open(global.device);
    for (ocl::Device& device : devices) {
        peaks.emplace(device.info().index, measure::device_peaks(device, refresh));
    }
    return peaks;
}

}  // namespace

void add_devices_command(CLI::App& app, const GlobalOptions& global) {
    auto* cmd = app.add_subcommand(
        "devices",
        "List every OpenCL device: index, type, name, platform, compute units, clock, memory, work-group "
        "limits, driver, and the vendor attributes occupancy estimates need (NVIDIA compute capability, "
        "warp size, registers per block; AMD wavefront width, ...). Marks the devices --device selects.");
    auto as_json = std::make_shared<bool>(false);
    auto show_peaks = std::make_shared<bool>(false);
    auto refresh_peaks = std::make_shared<bool>(false);
    cmd->add_flag("--json", *as_json, "print a JSON array of device objects instead of the table");
    cmd->add_flag("--peaks", *show_peaks,
                  "also show the selected devices' measured peaks (global-memory bandwidth, FP32 FMA "
                  "throughput), cached in peaks.json beside the program cache; measured when not cached");
    cmd->add_flag("--refresh-peaks", *refresh_peaks, "measure the selected devices' peaks again (implies --peaks)");
    cmd->callback([as_json, show_peaks, refresh_peaks, &global] {
        const auto devices = ocl::list_devices();
        const auto selected = ocl::select_devices(global.device, devices);
        std::map<std::size_t, measure::DevicePeaks> peaks;
        if (*show_peaks || *refresh_peaks) {
            peaks = selected_peaks(global, *refresh_peaks);
        }
        if (*as_json) {
            nlohmann::json out = nlohmann::json::array();
            for (const auto& d : devices) {
                nlohmann::json j = d.to_json();
                j["selected"] = std::find(selected.begin(), selected.end(), d.index) != selected.end();
                if (const auto it = peaks.find(d.index); it != peaks.end()) {
                    j["peaks"] = measure::to_json(it->second);
                    j["peaks"]["from_cache"] = it->second.cached;
                }
                out.push_back(j);
            }
            std::fputs((out.dump(2) + "\n").c_str(), stdout);
            return;
        }
        std::fputs(ocl::devices_table(devices).c_str(), stdout);
        std::string chosen;
        for (auto i : selected) chosen += fmt::format("{}{}", chosen.empty() ? "" : ", ", i);
        std::fputs(fmt::format("selected (--device / $SDFBRICK_DEVICE / default): {}\n", chosen).c_str(), stdout);
        for (const auto& [index, p] : peaks) {
            std::fputs(fmt::format("peaks of device {} ({}): global-memory bandwidth {:.1f} GB/s, FP32 FMA {:.1f} "
                                   "GFLOP/s ({} {})\n",
                                   index, p.device, p.bandwidth_gbps, p.fma_gflops,
                                   p.cached ? "cached, measured" : "measured", p.measured_at)
                           .c_str(),
                       stdout);
        }
    });
}

}  // namespace sdfbrick::cli
