#include "run/dispatch.h"

#include <optional>
#include <utility>

#include "moreau/common/error.h"
#include "moreau/common/stop.h"
#include "run/particles_checkpoint.h"
#include "run/particles_report.h"
#include "run/particles_run.h"
#include "run/particles_scenario.h"
#include "run/pbd_report.h"
#include "run/pbd_run.h"
#include "run/pbd_scenario.h"
#include "run/population_run.h"

namespace moreau::cli {

struct PreparedRun::Impl {
  RunRequest request;
  std::string scenario_file;
  std::optional<PbdScenario> pbd;                   // kPaperCase
  std::optional<ParticleScenario> particles;        // kParticles, kPopulation
  std::optional<ParticleSetup> setup;               // kParticles
  CheckpointPlan checkpoints;                       // kParticles, kPopulation
  std::optional<particles::Population> population;  // kPopulation

  bool writes() const { return request.files != RunFiles::kNone; }
  bool figures() const { return request.files == RunFiles::kAll; }
  OutputDir MakeOut(const std::filesystem::path& dir) const {
    return writes() ? OutputDir(dir) : OutputDir::Scratch();
  }

  void PrepareParticles(Scenario& scenario) {
    particles = ReadParticleScenario(scenario, request.fix_overlaps);
    scenario.CheckAllKeysUsed();
    if (request.check_only) return;
    if (!writes()) {  // no trajectory, no figures: the numbers only
      particles->output.hdf5 = false;
      particles->output.vtu = false;
      particles->output.snapshots = false;
    }
    if (particles->is_population()) {
      population.emplace(SetUpPopulationRun(*particles, scenario));
      checkpoints = PlanCheckpoints(request.checkpoint_every, request.resume, request.out_dir,
                                    request.fingerprint, *population);
      return;
    }
    setup.emplace(SetUpParticleRun(*particles, scenario));
    checkpoints = PlanCheckpoints(request.checkpoint_every, request.resume, request.out_dir,
                                  request.fingerprint, setup->engine);
  }

  RunOutcome RunPaperCase(const std::filesystem::path& out_dir) const {
    const PbdRunResult result = RunPbdScenario(*pbd);
    // Only meaningful complete: a stop on request publishes nothing.
    if (result.summary.termination == Termination::kInterrupted) {
      throw Interrupted(result.summary.message);
    }
    RunOutcome o{PbdRunJson(*pbd, result, scenario_file), "", result.summary.termination,
                 result.summary.message};
    if (writes()) {
      OutputDir out(out_dir);  // after the run: a signal during it leaves nothing behind
      o.report = ReportPbdRun(*pbd, result, o.summary, out, figures());
    }
    return o;
  }

  RunOutcome RunParticles(const std::filesystem::path& out_dir) {
    OutputDir out = MakeOut(out_dir);
    const ParticleRunResult result = cli::RunParticles(*particles, *setup, out, checkpoints);
    RunOutcome o{ParticleRunJson(*particles, *setup, result, scenario_file), "",
                 result.summary.termination, result.summary.message};
    if (writes()) {
      o.report = ReportParticleRun(*particles, *setup, result, o.summary, out, figures());
    }
    return o;
  }

  RunOutcome RunPopulation(const std::filesystem::path& out_dir) {
    OutputDir out = MakeOut(out_dir);
    const PopulationRunResult result =
        cli::RunPopulation(*particles, *population, out, checkpoints);
    RunOutcome o{PopulationRunJson(*particles, *population, result, scenario_file), "",
                 result.summary.termination, result.summary.message};
    if (writes()) o.report = ReportPopulationRun(*population, result, o.summary, out);
    return o;
  }
};

PreparedRun::PreparedRun(Scenario& scenario, RunRequest request) : impl_(std::make_unique<Impl>()) {
  impl_->request = std::move(request);
  impl_->scenario_file = scenario.path();
  if (scenario.GetString("problem.kind", "") == "particles") {
    impl_->PrepareParticles(scenario);
    return;
  }
  impl_->pbd = ReadPbdScenario(scenario);
  scenario.CheckAllKeysUsed();
  if (impl_->request.checkpoint_every != 0 || !impl_->request.resume.empty()) {
    throw InputError(
        "--checkpoint-every/--resume: only particle scenarios (problem.kind = \"particles\") "
        "can be checkpointed");
  }
}

PreparedRun::~PreparedRun() = default;
PreparedRun::PreparedRun(PreparedRun&&) noexcept = default;
PreparedRun& PreparedRun::operator=(PreparedRun&&) noexcept = default;

RunKind PreparedRun::kind() const {
  if (impl_->pbd) return RunKind::kPaperCase;
  return impl_->population ? RunKind::kPopulation : RunKind::kParticles;
}

RunOutcome PreparedRun::Run(const std::filesystem::path& out_dir) {
  switch (kind()) {
    case RunKind::kPaperCase:
      return impl_->RunPaperCase(out_dir);
    case RunKind::kParticles:
      return impl_->RunParticles(out_dir);
    case RunKind::kPopulation:
      return impl_->RunPopulation(out_dir);
  }
  return {};
}

}  // namespace moreau::cli
