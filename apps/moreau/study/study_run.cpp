#include "study/study_run.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <memory>
#include <numeric>

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

namespace {

// A double as JSON that reads back to the same bits, non-finite values included.
nlohmann::json ExactNumber(double value) {
  if (std::isfinite(value)) return value;
  return std::isnan(value) ? "nan" : (value > 0.0 ? "inf" : "-inf");
}
double FromExactNumber(const nlohmann::json& j) {
  if (j.is_number()) return j.get<double>();
  return std::stod(j.get<std::string>());
}

nlohmann::json StudyEntry(const pbd::StudyRow& row, std::int64_t index) {
  return {{"index", index},
          {"error", ExactNumber(row.error)},
          {"constraint_evaluations", row.constraint_evaluations},
          {"sweeps", row.sweeps},
          {"max_violation", ExactNumber(row.max_violation)},
          {"total_seconds", row.total_seconds},
          {"termination", ToString(row.termination)},
          {"message", row.message}};
}

pbd::StudyRow RowFromEntry(const PbdStudyPlan& plan, const nlohmann::json& entry) {
  const auto index = entry["index"].get<std::size_t>();
  const pbd::MethodSpec& spec = plan.methods[index / plan.hs.size()];
  pbd::StudyRow row;
  row.label = spec.label;
  row.method = spec.method;
  row.h = plan.hs[index % plan.hs.size()];
  row.error = FromExactNumber(entry["error"]);
  row.constraint_evaluations = entry["constraint_evaluations"].get<std::int64_t>();
  row.sweeps = entry["sweeps"].get<std::int64_t>();
  row.max_violation = FromExactNumber(entry["max_violation"]);
  row.total_seconds = entry["total_seconds"].get<double>();
  row.termination = ParseTermination(entry["termination"].get<std::string>());
  row.message = entry["message"].get<std::string>();
  return row;
}

// The exact solution, or a reference computed on this rank (every rank computes the same).
pbd::StudyProblem StudyProblemWithSolution(const Scenario& file, const PbdScenario& scenario,
                                           const PbdStudyPlan& plan, bool report) {
  pbd::StudyProblem problem = scenario.MakeProblem();
  if (problem.solution) return problem;
  const double sample_dt = plan.hs.back();
  const pbd::StepperOptions& ref = scenario.reference;
  try {
    (void)StepCount(sample_dt, ref.h);
  } catch (const InputError&) {
    file.Fail("reference.h", fmt::format("the smallest study step {} must be a whole "
                                         "multiple of it ({})",
                                         sample_dt, ref.h));
  }
  if (report) {
    std::fprintf(stderr, "moreau: computing the reference solution (%s, h = %g, reltol = %g)\n",
                 std::string(pbd::MethodName(ref.method)).c_str(), ref.h, ref.reltol);
  }
  auto reference =
      std::make_shared<pbd::SampledTrajectory>(pbd::ComputeReference(problem, ref, sample_dt));
  problem.solution = [reference](double t) { return reference->At(t); };
  return problem;
}

}  // namespace

sweep::Grid StudyGrid(const PbdStudyPlan& plan) {
  sweep::Grid grid;  // crossed, the last axis fastest: method by method, h decreasing
  sweep::Axis methods{"method", {}};
  for (const pbd::MethodSpec& m : plan.methods)
    methods.values.push_back(nlohmann::json(m.label).dump());
  sweep::Axis hs{"h", {}};
  for (double h : plan.hs) hs.values.push_back(fmt::format("{}", h));
  grid.axes = {methods, hs};
  return grid;
}

std::optional<PbdStudyResult> RunPbdStudy(const sweep::MpiSession& mpi, const Scenario& file,
                                          const PbdScenario& scenario, const PbdStudyPlan& plan,
                                          int jobs) {
  const Stopwatch stopwatch;
  const bool root = mpi.rank() == 0;
  const pbd::StudyProblem problem = StudyProblemWithSolution(file, scenario, plan, root);
  const sweep::Grid grid = StudyGrid(plan);
  std::vector<std::int64_t> todo(static_cast<std::size_t>(grid.RunCount()));
  std::iota(todo.begin(), todo.end(), 0);
  ProgressBar progress("study", grid.RunCount());
  std::int64_t done = 0;
  const std::vector<nlohmann::json> entries = sweep::Dispatch(
      mpi, todo, jobs,
      [&](std::int64_t index) {
        const auto i = static_cast<std::size_t>(index);
        return StudyEntry(pbd::RunStudyPoint(problem, plan.methods[i / plan.hs.size()],
                                             plan.hs[i % plan.hs.size()], scenario.solver),
                          index);
      },
      [&](const nlohmann::json&) {
        if (root) progress.Update(++done);  // rank 0's runs
      });
  progress.Finish();
  if (!root) return std::nullopt;
  PbdStudyResult result;
  result.runs = grid.RunCount();
  std::vector<std::optional<pbd::StudyRow>> rows(todo.size());
  for (const nlohmann::json& entry : entries) {
    rows[entry["index"].get<std::size_t>()] = RowFromEntry(plan, entry);
  }
  for (std::optional<pbd::StudyRow>& row : rows) {
    if (row && row->termination != Termination::kInterrupted) result.rows.push_back(*row);
  }
  result.interrupted = static_cast<std::int64_t>(result.rows.size()) < result.runs;
  result.total_seconds = stopwatch.Seconds();
  return result;
}

}  // namespace moreau::cli
