#include <chrono>
#include <cstdio>
#include <memory>

#include <fmt/format.h>

#include "cli/commands.h"
#include "core/errors.h"
#include "core/files.h"
#include "reference/surface_cells.h"
#include "scene/generate.h"
#include "scene/scene_info.h"
#include "scene/scene_json.h"

namespace sdfbrick::cli {

namespace {

struct InfoOptions {
    std::string file;
    bool json = false;
    std::optional<double> time;
    std::optional<double> leaf_size;
    int branching = 4;
};

struct GenerateOptions {
    std::string name;
    std::uint64_t seed = kDefaultSceneSeed;
    std::optional<std::string> out;
};

void run_info(const InfoOptions& o) {
    Scene scene = load_scene_warned(o.file);
    if (o.time) scene.time = *o.time;
    SceneSummary summary = scene_summary(scene);
    summary.file = o.file;
    if (o.leaf_size) {
        if (!(*o.leaf_size > 0.0)) throw InputError(fmt::format("--bricks: leaf size must be > 0, got {}", *o.leaf_size));
        const Scene at_t = scene_at(scene, scene.time);
        for (std::size_t i = 0; i < at_t.geometries.size(); ++i) {
            const Geometry& g = at_t.geometries[i];
            const Aabb b = bounds(g);
            if (b.empty()) continue;
            const auto domain = construct::make_domain(b, *o.leaf_size, o.branching);
            const auto start = std::chrono::steady_clock::now();
            auto per_level = reference::count_surface_cells(g, domain);
            const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
            summary.geometries[i].surface_cells =
                SurfaceCells{*o.leaf_size, o.branching, domain.levels, std::move(per_level), seconds};
        }
    }
    std::fputs(o.json ? format_json(to_json(summary)).c_str() : to_text(summary).c_str(), stdout);
}

void run_generate(const GenerateOptions& o) {
    const Scene scene = generate_scene(o.name, o.seed);
    if (o.out) {
        save_scene(scene, *o.out);
        std::fprintf(stderr, "wrote %s (%zu edits)\n", o.out->c_str(), scene.geometries[0].edits.size());
    } else {
        std::fputs(format_scene(scene).c_str(), stdout);
    }
}

}  // namespace

void add_scene_commands(CLI::App& app, const GlobalOptions& global) {
    auto* scene = app.add_subcommand("scene", "Inspect and generate scene files (see docs/scene-format.md)");
    scene->require_subcommand(1);

    auto info = std::make_shared<InfoOptions>();
    auto* cmd_info = scene->add_subcommand(
        "info", "Edits per geometry, primitive and operation histograms, bounds (at the scene's time)");
    cmd_info->add_option("file", info->file, "scene file (JSON)")->required();
    cmd_info->add_flag("--json", info->json, "print JSON instead of text");
    cmd_info->add_option("--time", info->time, "evaluate the animation at this time (s) instead of the file's")->check(finite_number());
    cmd_info->add_option("--bricks", info->leaf_size,
                         "also count the surface bricks at this leaf size with the double-precision host "
                         "reference (no culling: slow for large scenes, seconds to minutes)")
        ->check(finite_number());
    cmd_info->add_option("--branching", info->branching, "branching factor per axis for --bricks")
        ->check(CLI::IsMember({2, 4}));
    add_setting_flags(cmd_info, {{"leaf_size", "--bricks"}, {"branching", "--branching"}});
    cmd_info->callback([info, &global] {
        apply_global_options(global);
        run_info(*info);
    });

    auto gen = std::make_shared<GenerateOptions>();
    auto* cmd_gen = scene->add_subcommand(
        "generate", "Write a generated scene (one of the names below); same name and seed, same file");
    cmd_gen->add_option("name", gen->name, "scene name")->required()->check(CLI::IsMember(std::vector<std::string>(generated_scene_names().begin(), generated_scene_names().end())));
    cmd_gen->add_option("--seed", gen->seed, "random seed")->capture_default_str();
    cmd_gen->add_option("-o,--out", gen->out, "output file (default: standard output)");
    cmd_gen->callback([gen] { run_generate(*gen); });
}

}  // namespace sdfbrick::cli
