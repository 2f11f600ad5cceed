// `sdfbrick compare A.json B.json`: per-stage deltas between two reports (measure/compare.h).
#include <cstdio>
#include <memory>

#include "cli/commands.h"
#include "measure/compare.h"
#include "scene/scene_json.h"

namespace sdfbrick::cli {

void add_compare_command(CLI::App& app) {
    auto files = std::make_shared<std::vector<std::string>>();
    auto* cmd = app.add_subcommand("compare", "Per-stage deltas between two build or render --json reports; flags the "
                                              "stages whose change exceeds the runs' own spread");
    cmd->add_option("files", *files, "A.json B.json")->required()->expected(2);
    cmd->callback([files] {
        const auto deltas = measure::compare_reports(load_json((*files)[0]), load_json((*files)[1]), (*files)[0], (*files)[1]);
        std::fputs(measure::compare_text(deltas).c_str(), stdout);
    });
}

}  // namespace sdfbrick::cli
