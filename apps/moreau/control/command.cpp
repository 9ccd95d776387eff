// `moreau control SCENARIO.toml [--set key=value ...] [--out DIR] [--study-steps 32,64,...]`:
// optimal control of a mass–spring–damper network by the Symplectic Pontryagin method + Newton
// (docs/control.md): control_scenario → control_run → control_report.
#include <memory>

#include "commands.h"
#include "control/control_report.h"
#include "control/control_run.h"
#include "control/control_scenario.h"

namespace moreau::cli {
namespace {

struct ControlArgs : ScenarioArgs {
  std::vector<int> study_steps;
};

int Control(const ControlArgs& args) {
  Scenario scenario = Scenario::Load(args.scenario, args.overrides);
  const ControlScenario c = ReadControlScenario(scenario);
  scenario.CheckAllKeysUsed();
  if (!args.study_steps.empty()) {
    const control::RefinementStudySummary study = RunControlStudy(c, args.study_steps);
    return ReportControlStudy(c, study, args.scenario, args.OutDir("_study"));
  }
  const ControlRunResult result = RunControl(c);
  return ReportControlRun(c, result, args.scenario, args.OutDir());
}

}  // namespace

void AddControlCommand(CLI::App& app) {
  auto args = std::make_shared<ControlArgs>();
  CLI::App* cmd = AddScenarioCommand(
      app, "control", "Optimal control of a spring network (Symplectic Pontryagin + Newton)",
      args.get(), "out/<scenario name>", [args] { return Control(*args); });
  cmd->add_option("--study-steps", args->study_steps,
                  "Grid-refinement study over these numbers of steps N (comma separated)")
      ->delimiter(',');
}

}  // namespace moreau::cli
