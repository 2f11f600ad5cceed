// The CLI's verbs. main.cpp builds the command line (CLI11) and maps errors to exit codes.
#pragma once

#include <optional>
#include <string>

#include <CLI/CLI.hpp>

namespace sdfbrick::cli {

// Options every verb shares.
struct GlobalOptions {
    std::string device;  // device spec; empty = SDFBRICK_DEVICE or the default (first GPU, else device 0)
    std::optional<std::string> kernel_dir;
};

// Applies options that change library state (kernel directory). Verbs that use a device call it.
void apply_global_options(const GlobalOptions& global);

void add_devices_command(CLI::App& app, const GlobalOptions& global);
void add_scene_commands(CLI::App& app, const GlobalOptions& global);
void add_eval_command(CLI::App& app, const GlobalOptions& global);
void add_build_command(CLI::App& app, const GlobalOptions& global);
void add_render_command(CLI::App& app, const GlobalOptions& global);

}  // namespace sdfbrick::cli
