#include "control/control_run.h"

#include <fmt/format.h>

#include "moreau/common/error.h"
#include "moreau/common/stopwatch.h"
#include "moreau/control/pontryagin.h"
#include "progress.h"

namespace moreau::cli {

ControlRunResult RunControl(const ControlScenario& scenario) {
  const Stopwatch stopwatch;
  const control::ProblemFamily family = MakeProblemFamily(scenario);
  const control::TrackingProblem target = family(1.0);
  const control::PontryaginDiscretization disc(target, scenario.steps);
  ControlRunResult r;
  Eigen::VectorXd y;
  r.continuation = control::SolveWithContinuation(family, scenario.steps, scenario.continuation, y);
  // y belongs to the last accepted problem; evaluate it on the target (its residual says whether
  // it solves the target).
  control::PontryaginWorkspace ws;
  Eigen::VectorXd residual;
  r.residual_norm = control::EvaluateResidual(disc, y, ws, residual);
  r.value = control::DiscreteValue(disc, y, ws);
  Eigen::MatrixXd rho;
  disc.Unpack(y, r.z, rho);
  r.controls = control::EffectiveControls(disc, y);
  r.tracking_rms = control::TrackingRms(disc, r.z);
  r.delta = target.RegularizationDelta();
  r.dt = disc.dt();
  r.total_seconds = stopwatch.Seconds();
  return r;
}

control::RefinementStudySummary RunControlStudy(const ControlScenario& scenario,
                                                const std::vector<int>& steps) {
  control::RefinementStudyOptions options;
  options.steps = steps;
  options.continuation = scenario.continuation;
  options.warm_start = scenario.warm_start;
  options.compare_samples = scenario.compare_samples;
  try {
    options.Validate();
    // The finest level's memory, checked before the coarser levels run.
    control::CheckSolveMemory(MakeProblemFamily(scenario)(1.0).network(), steps.back());
  } catch (const InputError& e) {
    throw InputError(fmt::format("--study-steps: {}", e.what()));
  }
  ProgressBar progress("control study", static_cast<std::int64_t>(steps.size()));
  std::int64_t done = 0;
  options.on_level = [&](const control::RefinementLevel&) { progress.Update(++done); };
  control::RefinementStudySummary study =
      control::RunRefinementStudy(MakeProblemFamily(scenario), options);
  progress.Finish();
  return study;
}

}  // namespace moreau::cli
