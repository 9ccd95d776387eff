// `moreau run SCENARIO.toml [--set key=value ...] [--out DIR] [--fix-overlaps]
// [--checkpoint-every K] [--resume DIR]`: one simulation.
// problem.kind = "particles" goes to the particle engine (particles_scenario → particles_run →
// particles_report; with [[types]], an agent-based model: population_run); "sliding" and "disks"
// to the paper's steppers (pbd_scenario → pbd_run → pbd_report).
#include <memory>

#include "commands.h"
#include "run/particles_report.h"
#include "run/particles_run.h"
#include "run/particles_scenario.h"
#include "run/pbd_report.h"
#include "run/pbd_run.h"
#include "run/pbd_scenario.h"
#include "run/population_run.h"

namespace moreau::cli {
namespace {

struct RunArgs : ScenarioArgs {
  bool fix_overlaps = false;
  std::int64_t checkpoint_every = 0;
  std::string resume;
};

// Every input is read and checked, the engine set up on its initial state, before the output
// folder is made: the run streams its trajectory there.
int RunParticleScenario(Scenario& scenario, const RunArgs& args) {
  const ParticleScenario settings = ReadParticleScenario(scenario, args.fix_overlaps);
  scenario.CheckAllKeysUsed();
  if (settings.is_population()) {
    particles::Population population = SetUpPopulationRun(settings, scenario);
    OutputDir out(args.OutDir());
    return RunPopulation(settings, population, scenario.path(), out);
  }
  ParticleSetup setup = SetUpParticleRun(settings, scenario);
  const CheckpointPlan checkpoints = PlanCheckpoints(
      settings, args.checkpoint_every, args.resume, args.OutDir(),
      ScenarioFingerprint(args.scenario, args.overrides, args.fix_overlaps), setup.engine);
  OutputDir out(args.OutDir());
  const ParticleRunResult result = RunParticles(settings, setup, out, checkpoints);
  return ReportParticleRun(settings, setup, result, scenario.path(), out);
}

int Run(const RunArgs& args) {
  Scenario scenario = Scenario::Load(args.scenario, args.overrides);
  if (scenario.GetString("problem.kind", "") == "particles") {
    return RunParticleScenario(scenario, args);
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
  cmd->add_option("--checkpoint-every", args->checkpoint_every,
                  "Particle scenarios: save a checkpoint every K steps into <out>.checkpoint/ "
                  "(or the --resume folder)")
      ->type_name("K");
  cmd->add_option("--resume", args->resume,
                  "Particle scenarios: continue from DIR/checkpoint.bin (the same bits as a run "
                  "that never stopped)")
      ->type_name("DIR");
}

}  // namespace moreau::cli
