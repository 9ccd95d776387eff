// `moreau run SCENARIO.toml [--set key=value ...] [--out DIR] [--fix-overlaps]
// [--checkpoint-every K] [--resume DIR]`: one simulation. Which kind of run a scenario is (the
// paper's cases, particles, an agent-based model) is told in run/dispatch.h, which `moreau
// sweep` shares.
#include <cstdio>
#include <memory>

#include "commands.h"
#include "run/dispatch.h"
#include "run/particles_checkpoint.h"
#include "signals.h"

namespace moreau::cli {
namespace {

struct RunArgs : ScenarioArgs {
  bool fix_overlaps = false;
  std::int64_t checkpoint_every = 0;
  std::string resume;
};

// Every input is read and checked, the run set up on its initial state, before the output
// folder is made.
int Run(const RunArgs& args) {
  Scenario scenario = Scenario::Load(args.scenario, args.overrides);
  RunRequest request;
  request.fix_overlaps = args.fix_overlaps;
  request.checkpoint_every = args.checkpoint_every;
  request.resume = args.resume;
  request.out_dir = args.OutDir();
  request.fingerprint = ScenarioFingerprint(args.scenario, args.overrides, args.fix_overlaps);
  PreparedRun run(scenario, std::move(request));
  const RunOutcome outcome = run.Run(args.OutDir());
  std::fputs(outcome.report.c_str(), stdout);
  return RunExitCode(outcome.termination, outcome.message);
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
                  "Particle scenarios (rooms and [[types]] populations too): save a checkpoint "
                  "every K steps (populations: at the first rule step past each multiple of K) "
                  "into <out>.checkpoint/ (or the --resume folder)")
      ->type_name("K");
  cmd->add_option("--resume", args->resume,
                  "Particle scenarios (rooms and [[types]] populations too): continue from "
                  "DIR/checkpoint.bin (the same bits as a run that never stopped)")
      ->type_name("DIR");
}

}  // namespace moreau::cli
