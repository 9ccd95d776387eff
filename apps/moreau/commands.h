// The subcommands of the `moreau` tool. Each adds itself to the app; main() runs the one chosen.
//
// A command has three parts ("Adding a command" in README.md): a scenario (a
// FieldTable of its settings, field_table.h), a run (scenario → model → library solver →
// summary) and a report (summary.json, CSV, figures, the lines printed). The helpers below give
// every command the same arguments and the same exit codes.
#pragma once

#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include <CLI/CLI.hpp>

namespace moreau::cli {

void AddRunCommand(CLI::App& app);
void AddStudyCommand(CLI::App& app);
void AddControlCommand(CLI::App& app);
void AddInspectCommand(CLI::App& app);
void AddFillGapsCommand(CLI::App& app);
void AddEvaluateGapsCommand(CLI::App& app);
void AddSweepCommand(CLI::App& app);
void AddKeysCommand(CLI::App& app);
void AddMeasureCommand(CLI::App& app);

// The arguments of every scenario command: SCENARIO.toml [--set key=value ...] [--out DIR].
struct ScenarioArgs {
  std::string scenario;
  std::vector<std::string> overrides;
  std::string out;

  // --out, or out/<scenario file stem><suffix>.
  std::string OutDir(std::string_view suffix = "") const;
};

// Adds subcommand NAME with the scenario arguments bound to *args; `run` returns the exit code
// (0, or 3 after a numerical failure). Bad input is an InputError (exit code 2, from main).
CLI::App* AddScenarioCommand(CLI::App& app, const std::string& name, const std::string& description,
                             ScenarioArgs* args, const std::string& default_out,
                             std::function<int()> run);

}  // namespace moreau::cli
