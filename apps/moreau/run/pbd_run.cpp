#include "run/pbd_run.h"

#include <cmath>
#include <cstdio>
#include <memory>

#include <fmt/format.h>

#include "moreau/common/steps.h"
#include "progress.h"

namespace moreau::cli {

PbdRunResult RunPbdScenario(const PbdScenario& scenario) {
  pbd::StudyProblem problem = scenario.MakeProblem();
  const pbd::StepperOptions& options = scenario.solver;
  const std::int64_t steps = StepCount(problem.T, options.h);
  if (scenario.is_disks() && scenario.reference_for_run) {
    std::fprintf(stderr, "moreau: computing the reference solution (PNGS, h = %g)\n",
                 scenario.reference.h);
    auto reference = std::make_shared<pbd::SampledTrajectory>(
        pbd::ComputeReference(problem, scenario.reference, options.h));
    problem.solution = [reference](double t) { return reference->At(t); };
  }
  const std::int64_t stride = scenario.stride();

  // Disks: hold the particle constraints by their own type, for their neighbour-list statistics.
  std::unique_ptr<pbd::ParticleConstraints> particles;
  std::unique_ptr<pbd::Constraints> generic;
  if (scenario.is_disks()) {
    particles = scenario.MakeParticleConstraints();
  } else {
    generic = problem.constraints->MakeWorkspace();
  }
  pbd::Constraints& constraints = particles ? *particles : *generic;

  PbdRunResult result;
  double error = 0.0;
  std::int64_t diverged_step = -1;  // the first step whose |x| overflows (|x| > 1e154)
  ProgressBar progress("run", steps);
  result.summary = pbd::Simulate(*problem.drift, constraints, options, problem.x0, problem.T,
                                 [&](std::int64_t k, double t, pbd::ConstVectorRef x) {
                                   if (problem.solution)
                                     error = std::max(error, (x - problem.solution(t)).norm());
                                   if (diverged_step < 0 && !std::isfinite(x.squaredNorm()))
                                     diverged_step = k;
                                   if (k % stride == 0 || k == steps)
                                     result.frames.push_back({t, x});
                                   progress.Update(k);
                                   return true;
                                 });
  progress.Finish();
  if (diverged_step >= 0 && result.summary.ok()) {
    // A finite but unbounded state (a penalty step far too stiff for h) is no solution either.
    result.summary.termination = Termination::kDiverged;
    result.summary.failed_step = diverged_step;
    result.summary.message =
        fmt::format("the state diverged: |x| passed 1e154 at step {} (t = {:g})", diverged_step,
                    static_cast<double>(diverged_step) * options.h);
  }
  if (problem.solution && result.summary.ok()) result.error = error;
  if (particles) result.neighbour_list = particles->neighbour_stats();
  return result;
}

}  // namespace moreau::cli
