// The CLI's verbs. main.cpp builds the command line (CLI11) and maps errors to exit codes.
#pragma once

#include <filesystem>
#include <initializer_list>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <CLI/CLI.hpp>

#include "cl/device.h"
#include "core/errors.h"
#include "pipeline/executor.h"
#include "scene/scene.h"
#include "tune/tuning_db.h"

namespace sdfbrick::cli {

// Options every verb shares.
struct GlobalOptions {
    std::string device;  // device spec; empty = SDFBRICK_DEVICE or the default (first GPU, else device 0)
    std::optional<std::string> kernel_dir;
    std::optional<std::string> tuning_db;  // tuning database file (default: tune::TuningDb::default_path())
    bool no_tuning = false;                // ignore the tuning database
    std::string devices = "replicate";     // --devices: replicate or split
    std::vector<std::string> allow_outside;  // folders outside a scene's own whose meshes it may read
};

// Applies options that change library state (kernel directory, folders allowed for meshes). Verbs that use a device call it.
// splits: whether the verb can share its job among devices (--devices split); others refuse it.
void apply_global_options(const GlobalOptions& global, bool splits = false);

// The tuning database a run reads (and `tune` writes): --tuning-db, else the default path; no
// database with --no-tuning or when the default is off. A missing file is an empty database.
struct TuningChoice {
    std::optional<std::filesystem::path> path;
    std::optional<tune::TuningDb> db;
    const tune::TuningDb* get() const { return db ? &*db : nullptr; }
};
TuningChoice open_tuning(const GlobalOptions& global);

// The table of which flag of a verb sets each library setting (the name SettingError::setting()
// gives, e.g. "chunk" -> "--chunk"). BuildFlags::add_to adds the build settings' flags; the verbs
// add theirs.
void add_setting_flags(const CLI::App* verb, std::initializer_list<std::pair<const char*, const char*>> setting_flags);
// The one-line message for a SettingError raised by the verb that ran (a parsed subcommand of app):
// "FLAG: message" when that verb has a flag for the setting, else the message as it is.
std::string setting_error_line(const CLI::App& app, const SettingError& e);

// The devices a verb runs on and how its job is placed on them: --device's selection (a device named
// twice is refused with InputError), --devices (replicate or split; one device alone is whole unless
// split is asked for), the executor over them, and for split the rate store ($SDFBRICK_RATES, else
// the default path).
struct RunDevices {
    ocl::DeviceSet set;
    pipeline::Placement placement;
    std::optional<pipeline::RateStore> rates;
    pipeline::Executor executor;
};
std::unique_ptr<RunDevices> open_run_devices(const GlobalOptions& global);

// The scene file, its reading's warnings (a mesh's winding turned) printed as "warning: " lines on
// standard error.
Scene load_scene_warned(const std::filesystem::path& file);

// A number option's check: refuses nan, inf and values that overflow a double ("1e999").
const CLI::Validator& finite_number();

void add_devices_command(CLI::App& app, const GlobalOptions& global);
void add_scene_commands(CLI::App& app, const GlobalOptions& global);
void add_eval_command(CLI::App& app, const GlobalOptions& global);
void add_build_command(CLI::App& app, const GlobalOptions& global);
void add_render_command(CLI::App& app, const GlobalOptions& global);
void add_play_command(CLI::App& app, const GlobalOptions& global);
void add_sweep_commands(CLI::App& app, const GlobalOptions& global);  // sweep, merge
void add_tune_command(CLI::App& app, const GlobalOptions& global);
void add_export_commands(CLI::App& app, const GlobalOptions& global);  // export, sample
void add_compare_command(CLI::App& app);
void add_stability_command(CLI::App& app, const GlobalOptions& global);

// "4m05s", "1h02m": elapsed times and ETAs of progress lines.
std::string clock_text(double seconds);

}  // namespace sdfbrick::cli
