// The options that several verbs share (construction: `build`, `render`, `play`, ...; tracing:
// `render`, `play`; repeats): one definition of the flags, their parsing and their JSON record.
#pragma once

#include <optional>
#include <string>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "construct/brick_builder.h"
#include "render/brick_tracer.h"
#include "tune/apply.h"

namespace sdfbrick::cli {

struct BuildFlags {
    construct::BuildSettings settings;
    std::string format = "int8";
    bool no_cull = false;
    std::optional<double> tolerance_voxels;

    // Adds --brick-size --levels --branching --samples --format --band --guard --chunk --group
    // --eval-max-registers --no-cull --dependencies to cmd.
    void add_to(CLI::App* cmd);
    // The settings with --format, --no-cull and the adaptive flags applied (--tolerance without
    // --brick-size: the finest size from the tolerance); throws InputError for an unknown format.
    construct::BuildSettings resolve() const;
    // Which tuned parameters the command line set (add_to must have run).
    tune::Given given() const;

private:
    CLI::Option* brick_size_ = nullptr;
    CLI::Option* tolerance_ = nullptr;
    CLI::Option* chunk_ = nullptr;
    CLI::Option* group_ = nullptr;
    CLI::Option* registers_ = nullptr;
};

// The value of a --method flag; throws InputError naming the flag.
render::Method method_flag(const std::string& value);

// The trace options that `render` and `play` share: --width --height --mode --method --normals
// --group-x --group-y --shadow-rays --ao-rays --max-registers.
struct TraceFlags {
    render::TraceSettings trace;
    std::string mode = "normals";
    std::string method = "sphere";
    std::string normals = "continuous";

    void add_to(CLI::App* cmd);
    // The settings with --mode, --method and --normals applied; throws InputError naming the flag.
    render::TraceSettings resolve() const;
    // Whether --group-x or --group-y was given (add_to must have run).
    bool group_given() const { return group_x_->count() > 0 || group_y_->count() > 0; }
    bool registers_given() const { return registers_->count() > 0; }

private:
    CLI::Option* group_x_ = nullptr;
    CLI::Option* group_y_ = nullptr;
    CLI::Option* registers_ = nullptr;
};

// Repeats and what to report about them: --repeat, --warmup, --kernel-stats.
struct MeasureFlags {
    int repeat = 1;
    std::optional<int> warmup;
    bool kernel_stats = false;

    void add_to(CLI::App* cmd, const char* what);
    int warmups() const { return warmup.value_or(repeat > 1 ? 1 : 0); }
};

}  // namespace sdfbrick::cli
