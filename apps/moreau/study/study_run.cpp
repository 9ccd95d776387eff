#include "study/study_run.h"

#include <algorithm>
#include <cstdio>
#include <functional>
#include <memory>

#include <fmt/format.h>

#include "moreau/common/error.h"
#include "moreau/common/steps.h"
#include "moreau/common/stopwatch.h"
#include "progress.h"

namespace moreau::cli {

PbdStudyPlan MakeStudyPlan(const StudyRequest& request, const PbdScenario& scenario) {
  PbdStudyPlan plan;
  for (const std::string& m : request.methods) {
    try {
      plan.methods.push_back(pbd::ParseMethodSpec(m));
    } catch (const InputError& e) {
      throw InputError(fmt::format("--methods: {}", e.what()));
    }
  }
  if (plan.methods.empty()) throw InputError("--methods: at least one method is needed");
  plan.hs = request.hs;
  if (plan.hs.empty()) throw InputError("--h: at least one step size is needed");
  for (double h : plan.hs) {
    if (!(h > 0.0)) throw InputError(fmt::format("--h: step sizes must be > 0 (got {})", h));
    try {
      (void)StepCount(scenario.T(), h);
    } catch (const InputError& e) {
      throw InputError(fmt::format("--h: {}", e.what()));
    }
  }
  std::sort(plan.hs.begin(), plan.hs.end(), std::greater<>());
  if (request.fit_points < 2) throw InputError("--fit-points: must be ≥ 2");
  plan.fit_points = request.fit_points;
  return plan;
}

PbdStudyResult RunPbdStudy(const Scenario& file, const PbdScenario& scenario,
                           const PbdStudyPlan& plan) {
  const Stopwatch stopwatch;
  pbd::StudyProblem problem = scenario.MakeProblem();
  if (!problem.solution) {
    const double sample_dt = plan.hs.back();
    const pbd::StepperOptions& ref = scenario.reference;
    try {
      (void)StepCount(sample_dt, ref.h);
    } catch (const InputError&) {
      file.Fail("reference.h", fmt::format("the smallest study step {} must be a whole "
                                           "multiple of it ({})",
                                           sample_dt, ref.h));
    }
    std::fprintf(stderr, "moreau: computing the reference solution (%s, h = %g, reltol = %g)\n",
                 std::string(pbd::MethodName(ref.method)).c_str(), ref.h, ref.reltol);
    auto reference =
        std::make_shared<pbd::SampledTrajectory>(pbd::ComputeReference(problem, ref, sample_dt));
    problem.solution = [reference](double t) { return reference->At(t); };
  }
  ProgressBar progress("study", static_cast<std::int64_t>(plan.methods.size() * plan.hs.size()));
  PbdStudyResult result;
  result.rows = pbd::RunStudy(problem, plan.methods, plan.hs, scenario.solver,
                              [&](int done, int) { progress.Update(done); });
  progress.Finish();
  result.total_seconds = stopwatch.Seconds();
  return result;
}

}  // namespace moreau::cli
