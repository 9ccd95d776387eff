// `moreau run SCENARIO.toml [--set key=value ...] [--out DIR] [--fix-overlaps]`: one simulation.
// problem.kind = "particles" goes to the particle engine (particles_run.h); "sliding" and
// "disks" to the paper's steppers (pbd_scenario → pbd_run → pbd_report).
#include <memory>

#include "commands.h"
#include "particles_run.h"
#include "run/pbd_report.h"
#include "run/pbd_run.h"
#include "run/pbd_scenario.h"

namespace moreau::cli {
namespace {

struct RunArgs : ScenarioArgs {
  bool fix_overlaps = false;
};

int Run(const RunArgs& args) {
  Scenario scenario = Scenario::Load(args.scenario, args.overrides);
  if (scenario.GetString("problem.kind", "") == "particles") {
    return RunParticleScenario(scenario, {args.OutDir(), args.fix_overlaps});
  }
  const PbdScenario pbd_scenario = ReadPbdScenario(scenario);
  scenario.CheckAllKeysUsed();
  const PbdRunResult result = RunPbdScenario(pbd_scenario);
  return ReportPbdRun(pbd_scenario, result, args.scenario, args.OutDir());
}

}  // namespace

void AddRunCommand(CLI::App& app) {
  auto args = std::make_shared<RunArgs>();
  CLI::App* cmd =
      AddScenarioCommand(app, "run", "Run one simulation of a scenario file", args.get(),
                         "out/<scenario name>", [args] { return Run(*args); });
  cmd->add_flag("--fix-overlaps", args->fix_overlaps,
                "Particle scenarios: project an overlapping initial state to a feasible one "
                "(repeated PBD sweeps) instead of rejecting it");
}

}  // namespace moreau::cli
