#include <cstdio>
#include <memory>

#include <fmt/format.h>

#include "cl/device.h"
#include "cli/commands.h"

namespace sdfbrick::cli {

void add_devices_command(CLI::App& app, const GlobalOptions& global) {
    auto* cmd = app.add_subcommand(
        "devices",
        "List every OpenCL device: index, type, name, platform, compute units, clock, memory, work-group "
        "limits, driver, and the vendor attributes occupancy estimates need (NVIDIA compute capability, "
        "warp size, registers per block; AMD wavefront width, ...). Marks the devices --device selects.");
    auto as_json = std::make_shared<bool>(false);
    cmd->add_flag("--json", *as_json, "print a JSON array of device objects instead of the table");
    cmd->callback([as_json, &global] {
        const auto devices = ocl::list_devices();
        const auto selected = ocl::select_devices(global.device, devices);
        if (*as_json) {
            nlohmann::json out = nlohmann::json::array();
            for (const auto& d : devices) {
                nlohmann::json j = d.to_json();
                j["selected"] = std::find(selected.begin(), selected.end(), d.index) != selected.end();
                out.push_back(j);
            }
            std::fputs((out.dump(2) + "\n").c_str(), stdout);
            return;
        }
        std::fputs(ocl::devices_table(devices).c_str(), stdout);
        std::string chosen;
        for (auto i : selected) chosen += fmt::format("{}{}", chosen.empty() ? "" : ", ", i);
        std::fputs(fmt::format("selected (--device / $SDFBRICK_DEVICE / default): {}\n", chosen).c_str(), stdout);
    });
}

}  // namespace sdfbrick::cli
