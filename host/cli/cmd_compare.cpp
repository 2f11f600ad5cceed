// `sdfbrick compare A.json B.json`: per-stage deltas between two reports (measure/compare.h); with
// --gate RULES, a verdict on whether B regressed against A (measure/gate.h): exit 3 when it did.
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>

#include <fmt/format.h>

#include "cli/commands.h"
#include "core/errors.h"
#include "core/files.h"
#include "measure/compare.h"
#include "measure/gate.h"
#include "scene/scene_json.h"

namespace sdfbrick::cli {

namespace {

struct CompareOptions {
    std::vector<std::string> files;  // A (BASE) and B (NEW)
    std::optional<std::string> gate, summary, junit, json;
    bool allow_digest_change = false, allow_different = false;
};

std::vector<measure::GateRule> gate_rules(const std::string& text) {
    try {
        return measure::parse_gate_rules(text);
    } catch (const InputError& e) {
        throw InputError(fmt::format("--gate: {}", e.what()));
    }
}

void run_gate(const CompareOptions& o) {
    const std::vector<measure::GateRule> rules = gate_rules(*o.gate);
    std::vector<std::filesystem::path> paths;
    for (const auto* p : {&o.summary, &o.junit, &o.json})
        if (*p) paths.push_back(**p);
    check_output_paths(paths);
    const measure::GateVerdict verdict =
        measure::gate_reports(load_json(o.files[0]), load_json(o.files[1]), rules,
                              {o.allow_digest_change, o.allow_different}, o.files[0], o.files[1]);
    const std::string summary = measure::to_markdown(verdict);
    std::vector<Output> outputs;
    if (o.summary) outputs.push_back(text_output(*o.summary, summary));
    if (o.junit) outputs.push_back(text_output(*o.junit, measure::to_junit(verdict)));
    if (o.json) outputs.push_back(text_output(*o.json, format_json(measure::to_json(verdict))));
    write_all(outputs);
    std::fputs(summary.c_str(), stdout);
    if (!verdict.passed()) {
        finish_stdout();
        throw VerdictFailure(measure::failure_line(verdict));
    }
}

}  // namespace

void add_compare_command(CLI::App& app) {
    auto o = std::make_shared<CompareOptions>();
    auto* cmd = app.add_subcommand("compare", "Per-stage deltas between two build or render --json reports; flags the "
                                              "stages whose change exceeds the runs' own spread. With --gate, a verdict: "
                                              "exit 3 when B regressed against A (docs/ci-gate.md)");
    cmd->add_option("files", o->files, "A.json B.json (with --gate: BASE.json NEW.json)")->required()->expected(2);
    auto* gate = cmd->add_option("--gate", o->gate,
                                 "gate NEW against BASE by these rules: default (= " +
                                     std::string(measure::kDefaultGateRules) +
                                     ") or a comma-separated list of NAME[?][<=LIMIT]; exit 3 when a rule fails");
    cmd->add_option("--summary", o->summary, "write the verdict as Markdown here")->needs(gate);
    cmd->add_option("--junit", o->junit, "write the verdict as JUnit XML here (one test case per check)")->needs(gate);
    cmd->add_option("--json", o->json, "write the verdict as JSON here")->needs(gate);
    cmd->add_flag("--allow-digest-change", o->allow_digest_change, "a changed digest passes (it is still reported)")
        ->needs(gate);
    cmd->add_flag("--allow-different", o->allow_different,
                  "gate reports of different commands, scenes or settings (the differences are noted)")
        ->needs(gate);
    cmd->callback([o] {
        if (o->gate) return run_gate(*o);
        const auto deltas = measure::compare_reports(load_json(o->files[0]), load_json(o->files[1]), o->files[0], o->files[1]);
        std::fputs(measure::compare_text(deltas).c_str(), stdout);
    });
}

}  // namespace sdfbrick::cli
