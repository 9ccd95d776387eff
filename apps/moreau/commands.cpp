#include "commands.h"

#include <filesystem>

#include "signals.h"

namespace moreau::cli {

std::string ScenarioArgs::OutDir(std::string_view suffix) const {
  if (!out.empty()) return out;
  const std::string stem = std::filesystem::path(scenario).stem().string();
  return (std::filesystem::path("out") / (stem + std::string(suffix))).string();
}

CLI::App* AddScenarioCommand(CLI::App& app, const std::string& name, const std::string& description,
                             ScenarioArgs* args, const std::string& default_out,
                             std::function<int()> run) {
  CLI::App* cmd = app.add_subcommand(name, description);
  cmd->add_option("scenario", args->scenario, "Scenario file (TOML)")->required();
  cmd->add_option("--set", args->overrides, "Override a scenario value: key=value (repeatable)");
  cmd->add_option("--out", args->out, "Output folder (default " + default_out + ")");
  cmd->callback([run = std::move(run)] {
    const int code = RunStoppable(run);
    if (code != 0) throw CLI::RuntimeError(code);
  });
  return cmd;
}

}  // namespace moreau::cli
