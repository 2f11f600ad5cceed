// Options every verb shares, and the table of which flag sets each setting (commands.h).
#include <charconv>
#include <cmath>
#include <map>

#include <fmt/format.h>

#include "cl/kernel_source.h"
#include "cli/commands.h"
#include "core/quote.h"

namespace sdfbrick::cli {

namespace {

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
    if (device_mode(global) == pipeline::DeviceMode::split && !splits)
        throw InputError("--devices split: only build and render share one job among devices");
}

TuningChoice open_tuning(const GlobalOptions& global) {
    TuningChoice c;
    if (global.no_tuning) return c;
    c.path = global.tuning_db ? std::optional<std::filesystem::path>(*global.tuning_db) : tune::TuningDb::default_path();
    if (c.path) c.db = tune::TuningDb::load(*c.path);
    return c;
}

pipeline::DeviceMode device_mode(const GlobalOptions& global) {
    const auto mode = pipeline::device_mode_from_string(global.devices);
    if (!mode) throw InputError(fmt::format("--devices must be replicate or split, got \"{}\"", global.devices));
    return *mode;
}

SplitDevices open_split_devices(const GlobalOptions& global) {
    const std::vector<ocl::DeviceInfo> all = ocl::list_devices();
    std::vector<std::size_t> seen;
    std::string_view spec = global.device;
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
    SplitDevices s{ocl::DeviceSet::open(global.device), {}, pipeline::RateStore(pipeline::RateStore::default_path())};
    for (ocl::Device& d : s.set) s.devices.push_back(&d);
    return s;
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

std::string clock_text(double seconds) {
    const auto t = static_cast<long>(seconds + 0.5);
    return t >= 3600 ? fmt::format("{}h{:02}m", t / 3600, t / 60 % 60) : fmt::format("{}m{:02}s", t / 60, t % 60);
}

}  // namespace sdfbrick::cli
