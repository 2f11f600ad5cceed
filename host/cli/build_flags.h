// The construction options that `build`, `render` (and later verbs) share: one definition of the
// flags, their parsing and their JSON record.
#pragma once

#include <string>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "build/brick_builder.h"

namespace sdfbrick::cli {

struct BuildFlags {
    build::BuildSettings settings;
    std::string format = "int8";
    bool no_cull = false;

    // Adds --brick-size --levels --branching --samples --format --band --guard --chunk --group --no-cull
    // --dependencies to cmd.
    void add_to(CLI::App* cmd);
    // The settings with --format and --no-cull applied; throws InputError for an unknown format.
    build::BuildSettings resolve() const;
};

nlohmann::json settings_json(const build::BuildSettings& s);

}  // namespace sdfbrick::cli
