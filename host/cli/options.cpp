// Options every verb shares, and the table of which flag sets each setting (commands.h).
#include <algorithm>
#include <charconv>
#include <cmath>
#include <iostream>
#include <map>

#include <fmt/format.h>

#include "cl/kernel_source.h"
#include "cli/commands.h"
#include "core/quote.h"
#include "scene/scene_json.h"

namespace sdfbrick::cli {

namespace {

pipeline::Placement placement(const GlobalOptions& global) {
    if (global.devices == "replicate") return pipeline::Placement::replicate;
    if (global.devices == "split") return pipeline::Placement::split;
    throw InputError(fmt::format("--devices must be replicate or split, got \"{}\"", global.devices));
}

// verb -> library setting -> flag
std::map<const CLI::App*, std::map<std::string, std::string>>& setting_flag_table() {
    static std::map<const CLI::App*, std::map<std::string, std::string>> table;
    return table;
}

const std::string* flag_of(const CLI::App& app, const std::string& setting) {
    for (const CLI::App* verb : app.get_subcommands()) {
        const auto& table = setting_flag_table();
        if (const auto it = table.find(verb); it != table.end())
            if (const auto flag = it->second.find(setting); flag != it->second.end()) return &flag->second;
        if (const std::string* flag = flag_of(*verb, setting)) return flag;  // scene info, ...
    }
    return nullptr;
}

}  // namespace

void add_setting_flags(const CLI::App* verb, std::initializer_list<std::pair<const char*, const char*>> setting_flags) {
    for (const auto& [setting, flag] : setting_flags) setting_flag_table()[verb][setting] = flag;
}

std::string setting_error_line(const CLI::App& app, const SettingError& e) {
    const std::string* flag = flag_of(app, e.setting());
    return flag ? *flag + ": " + e.what() : std::string(e.what());
}

void apply_global_options(const GlobalOptions& global, bool splits) {
    if (global.kernel_dir) ocl::set_kernel_dir(std::filesystem::path(*global.kernel_dir));
    std::vector<std::filesystem::path> folders;
    for (const std::string& f : global.allow_outside) {
        std::error_code ec;
        if (!std::filesystem::is_directory(f, ec))
            throw InputError(fmt::format("--allow-outside {}: not a folder", escaped(f)));
        folders.emplace_back(f);
    }
    allow_mesh_folders(std::move(folders));
    if (placement(global) == pipeline::Placement::split && !splits)
        throw InputError("--devices split: only build, render, export and sample share one job among devices");
}

TuningChoice open_tuning(const GlobalOptions& global) {
    TuningChoice c;
    if (global.no_tuning) return c;
    c.path = global.tuning_db ? std::optional<std::filesystem::path>(*global.tuning_db) : tune::TuningDb::default_path();
    if (c.path) c.db = tune::TuningDb::load(*c.path);
    return c;
}

namespace {

std::vector<ocl::Device*> device_pointers(ocl::DeviceSet& set) {
    std::vector<ocl::Device*> out;
    for (ocl::Device& d : set) out.push_back(&d);
    return out;
}

// A split uses each device once: a device named twice by --device is refused.
void check_named_once(std::string_view spec) {
    const std::vector<ocl::DeviceInfo> all = ocl::list_devices();
    std::vector<std::size_t> seen;
    while (!spec.empty()) {
        const std::size_t comma = spec.find(',');
        for (std::size_t i : ocl::select_devices(spec.substr(0, comma), all)) {
            if (std::find(seen.begin(), seen.end(), i) != seen.end())
                throw InputError(fmt::format("--device: device {} ({}) is named twice; a split run uses each device once",
                                             i, all[i].name));
            seen.push_back(i);
        }
        spec = comma == std::string_view::npos ? std::string_view{} : spec.substr(comma + 1);
    }
}

}  // namespace

std::unique_ptr<RunDevices> open_run_devices(const GlobalOptions& global) {
    pipeline::Placement p = placement(global);
    if (p == pipeline::Placement::split) check_named_once(global.device);
    ocl::DeviceSet set = ocl::DeviceSet::open(global.device);
    if (p == pipeline::Placement::replicate && set.size() == 1) p = pipeline::Placement::whole;
    std::optional<pipeline::RateStore> rates;
    if (p == pipeline::Placement::split) rates.emplace(pipeline::RateStore::default_path());
    std::vector<ocl::Device*> devices = device_pointers(set);
    return std::unique_ptr<RunDevices>(new RunDevices{std::move(set), p, std::move(rates), pipeline::Executor(devices)});
}

const CLI::Validator& finite_number() {
    static const CLI::Validator check(
        [](const std::string& text) -> std::string {
            double value = 0.0;
            const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
            if (ec == std::errc::result_out_of_range) return "number out of range: " + quoted_input(text);
            if (ec == std::errc() && end == text.data() + text.size() && !std::isfinite(value))
                return "must be a finite number, got " + quoted_input(text);
            return {};  // not a number at all: the option's own conversion says so
        },
        "FINITE");
    return check;
}

Scene load_scene_warned(const std::filesystem::path& file) {
    Scene s = load_scene(file);
    for (const std::string& w : s.warnings) std::cerr << "warning: " << w << '\n';
    return s;
}

std::string clock_text(double seconds) {
    const auto t = static_cast<long>(seconds + 0.5);
    return t >= 3600 ? fmt::format("{}h{:02}m", t / 3600, t / 60 % 60) : fmt::format("{}m{:02}s", t / 60, t % 60);
}

}  // namespace sdfbrick::cli
