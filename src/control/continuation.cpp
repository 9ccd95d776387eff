#include "moreau/control/continuation.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <memory>

#include "moreau/common/error.h"
#include "moreau/common/stopwatch.h"
#include "moreau/common/summary_json.h"

namespace moreau::control {

ProblemFamily LinearPathFamily(const TrackingProblem& problem) {
  return [problem](double p) {
    if (p == 1.0) return problem;
    const SpringNetwork& net = problem.network();
    const int d = net.dimension();
    const int m = net.num_free();
    Eigen::VectorXd x0(d * m);
    const Eigen::VectorXd z0 = net.InitialState();
    for (int k = 0; k < m; ++k) x0.segment(d * k, d) = z0.segment(2 * d * k, d);
    ReferenceFunction full = problem.reference();
    ReferenceFunction scaled = [full, x0, p, d, m](double t, double* x, double* v, double* w) {
      full(t, x, v, w);
      for (int i = 0; i < d * m; ++i) {
        x[i] = x0[i] + p * (x[i] - x0[i]);
        v[i] *= p;
      }
    };
    return TrackingProblem(net, problem.horizon(), scaled, problem.weights(), problem.gamma());
  };
}

const FieldList<ContinuationOptions>& ContinuationOptions::Fields() {
  using O = ContinuationOptions;
  static const FieldList<O> list = [] {
    FieldList<O> t;
    t.Number("path_start", &O::path_start, Range::LeftOpen(0, 1), "",
             "p_0 (1: no path continuation)")
        .Number("path_increase", &O::path_increase, Range::Positive(), "", "C^p")
        .Number("stiffness_start", &O::stiffness_start, Range::LeftOpen(0, 1), "",
                "s_0: κ and ξ start at s_0 × target (1: no stiffness continuation)")
        .Number("stiffness_increase", &O::stiffness_increase, Range::Positive(), "", "C^κξ")
        .Number("gamma_start", &O::gamma_start, Range::NonNegative(), "",
                "γ_0 (≤ the target γ: no δ continuation)")
        .Number("gamma_decrease", &O::gamma_decrease, Range::Open(0, 1), "", "C^δ")
        .Number("min_increase", &O::min_increase, Range::Open(0, 1), "",
                "smallest coefficient before a stage gives up")
        .Integer("max_solves", &O::max_solves, Range::AtLeast(1), "",
                 "Newton solves in all, accepted or not")
        .Integer("coarse_steps", &O::coarse_steps, Range::NonNegative(), "",
                 "coarse-to-fine: largest coarse grid (0: all stages on the requested grid)")
        .Integer("refine_factor", &O::refine_factor, Range::AtLeast(2), "",
                 "ratio of successive grids")
        .Integer("start_steps", &O::start_steps, Range::NonNegative(), "",
                 "largest grid of the stages before γ (0: the coarse grid)")
        .Mount("fixed_point", &O::fixed_point, FixedPointOptions::Fields())
        .Mount("newton", &O::newton, NewtonOptions::Fields());
    return t;
  }();
  return list;
}

void ContinuationOptions::Validate() const { Fields().Validate(*this); }

nlohmann::json ContinuationOptions::ToJson() const { return Fields().ToJson(*this); }

nlohmann::json GridRecord::ToJson() const {
  return {{"steps", steps},
          {"newton_solves", newton_solves},
          {"newton_iterations", newton_iterations},
          {"total_seconds", total_seconds}};
}

nlohmann::json ContinuationRecord::ToJson() const {
  return {{"stage", stage},
          {"steps", steps},
          {"path_fraction", path_fraction},
          {"stiffness_scale", stiffness_scale},
          {"gamma", gamma},
          {"accepted", accepted},
          {"newton_iterations", newton_iterations},
          {"residual_norm", FiniteOrNull(residual)},
          {"termination", std::string(moreau::ToString(termination))}};
}

std::string ContinuationSummary::BriefReport() const {
  std::string on_grids;  // "; grids 512 (54 it.) -> 1024 (3 it.)" when there is more than one
  for (std::size_t k = 0; grids.size() > 1 && k < grids.size(); ++k) {
    on_grids += fmt::format("{}{} ({} it.)", k == 0 ? "; grids " : " -> ", grids[k].steps,
                            grids[k].newton_iterations);
  }
  return fmt::format(
      "continuation: {} after {} Newton solves ({} iterations, {:.2f} s); "
      "reached p = {:.4g}, s = {:.4g}, gamma = {:.3g}{}{}{}",
      moreau::ToString(termination), newton_solves, newton_iterations, total_seconds, path_fraction,
      stiffness_scale, gamma, on_grids, message.empty() ? "" : ": ", message);
}

nlohmann::json ContinuationSummary::ToJson() const {
  nlohmann::json j = SummaryJson(termination, message, total_seconds);
  j["newton_solves"] = newton_solves;
  j["newton_iterations"] = newton_iterations;
  nlohmann::json grid_records = nlohmann::json::array();
  for (const GridRecord& g : grids) grid_records.push_back(g.ToJson());
  j["grids"] = std::move(grid_records);
  j["reached"] = {
      {"path_fraction", path_fraction}, {"stiffness_scale", stiffness_scale}, {"gamma", gamma}};
  nlohmann::json records = nlohmann::json::array();
  for (const ContinuationRecord& r : path) records.push_back(r.ToJson());
  j["continuation_path"] = std::move(records);
  j["last_newton"] = last_newton.ToJson();
  j["last_newton"].erase("settings");  // the same as settings.newton
  j["settings"] = options.ToJson();
  return j;
}

TrackingProblem ContinuationProblem(const ProblemFamily& family, double path_fraction,
                                    double stiffness_scale, double gamma) {
  TrackingProblem problem = family(path_fraction);
  if (stiffness_scale != 1.0) {
    problem = problem.WithNetwork(problem.network().Scaled(stiffness_scale, stiffness_scale));
  }
  if (gamma != problem.gamma()) problem = problem.WithGamma(gamma);
  return problem;
}

Eigen::MatrixXd ReferenceGuess(const PontryaginDiscretization& disc) {
  const SpringNetwork& net = disc.problem().network();
  const int d = net.dimension();
  Eigen::MatrixXd z(disc.state_size(), disc.steps() + 1);
  const Eigen::VectorXd z0 = disc.initial_state();
  for (int n = 0; n <= disc.steps(); ++n) {
    const Instant& in = disc.instant(n);
    for (int k = 0; k < net.num_free(); ++k) {
      if (in.ref_weight[k] > 0.0) {
        z.col(n).segment(2 * d * k, d) = in.ref_position.segment(d * k, d);
        z.col(n).segment(2 * d * k + d, d) = in.ref_velocity.segment(d * k, d);
      } else {
        z.col(n).segment(2 * d * k, 2 * d) = z0.segment(2 * d * k, 2 * d);
      }
    }
  }
  return z;
}

namespace {

// One continuation: the Newton solves at (p, s, γ), recorded in the summary.
class ContinuationRun {
 public:
  ContinuationRun(const ProblemFamily& family, const ContinuationOptions& options,
                  Eigen::VectorXd& y)
      : family_(family), options_(options), y_(y) {
    summary_.options = options;
    y_.resize(0);
  }

  // Later attempts solve on N steps (a new grid record).
  void SetGrid(int steps) {
    steps_ = steps;
    summary_.grids.push_back(GridRecord{steps, 0, 0, 0.0});
  }
  int steps() const { return steps_; }

  // One Newton solve at (p, s, γ) from `guess` (the fixed-point sweep on the reference when it
  // has the wrong size); on success y = the solution.
  bool Attempt(const char* stage, double p, double s, double gamma, Eigen::VectorXd guess) {
    const Stopwatch stopwatch;
    const TrackingProblem problem = ContinuationProblem(family_, p, s, gamma);
    const PontryaginDiscretization disc(problem, steps_);
    if (guess.size() != disc.unknowns()) {
      FixedPointSweep(disc, ReferenceGuess(disc), options_.fixed_point, guess);
    }
    NewtonSummary ns = SolveNewton(disc, options_.newton, guess, newton_workspace_);
    ++summary_.newton_solves;
    summary_.newton_iterations += ns.iterations;
    GridRecord& grid = summary_.grids.back();
    ++grid.newton_solves;
    grid.newton_iterations += ns.iterations;
    grid.total_seconds += stopwatch.Seconds();
    ContinuationRecord record;
    record.stage = stage;
    record.steps = steps_;
    record.path_fraction = p;
    record.stiffness_scale = s;
    record.gamma = gamma;
    record.accepted = ns.ok();
    record.newton_iterations = ns.iterations;
    record.residual = ns.final_residual;
    record.termination = ns.termination;
    summary_.path.push_back(record);
    const bool ok = ns.ok();
    summary_.last_newton = std::move(ns);
    // Keep the best iterate when nothing was accepted on this grid yet.
    if (ok || y_.size() != guess.size()) y_ = guess;
    if (ok) {
      summary_.path_fraction = p;
      summary_.stiffness_scale = s;
      summary_.gamma = gamma;
    }
    return ok;
  }

  bool BudgetLeft() const { return summary_.newton_solves < options_.max_solves; }
  const Eigen::VectorXd& y() const { return y_; }
  const NewtonSummary& last_newton() const { return summary_.last_newton; }

  // Success, or the failed solve's termination (kMaxIterations when the last solve succeeded:
  // the budget ran out).
  ContinuationSummary Finish(bool converged, std::string message) {
    if (converged) {
      summary_.termination = Termination::kConverged;
    } else {
      const Termination last = summary_.last_newton.termination;
      summary_.termination = IsSuccess(last) ? Termination::kMaxIterations : last;
    }
    summary_.message = std::move(message);
    summary_.total_seconds = stopwatch_.Seconds();
    return summary_;
  }

 private:
  const ProblemFamily& family_;
  int steps_ = 0;
  const ContinuationOptions& options_;
  Eigen::VectorXd& y_;
  ContinuationSummary summary_;
  NewtonWorkspace newton_workspace_;  // shared by every solve: its storage is allocated once
  Stopwatch stopwatch_;
};

// Raises `value` towards 1 by factors (1 + c), halving c on failure. Returns the reason it gave
// up, or an empty string once value = 1.
template <typename TryValue>
std::string IncreaseToOne(ContinuationRun& run, const char* stage, const char* what, double& value,
                          double coefficient, double min_increase, TryValue try_value) {
  while (value < 1.0) {
    if (!run.BudgetLeft()) {
      return fmt::format("Newton solve budget exhausted in the {} stage", stage);
    }
    const double trial = std::min(value * (1.0 + coefficient), 1.0);
    if (try_value(trial)) {
      value = trial;
    } else {
      coefficient *= 0.5;
      if (coefficient < min_increase) {
        return fmt::format("{} continuation stalled at {}{}", stage, what, value);
      }
    }
  }
  return "";
}

}  // namespace

namespace {

// The continuation stages on the run's current grid, from `first` at the start parameters.
// Returns why it failed, or an empty string when the target problem was solved.
// `before_gamma` runs between the stiffness and the γ stages (it may move the run to a finer
// grid); it returns why it failed, or an empty string.
std::string RunStages(ContinuationRun& run, const ContinuationOptions& options, double gamma_target,
                      const Eigen::VectorXd& first,
                      const std::function<std::string(double gamma)>& before_gamma = nullptr) {
  double p = options.path_start;
  double s = options.stiffness_start;
  double gamma = std::max(options.gamma_start, gamma_target);
  if (!run.Attempt("initial", p, s, gamma, first)) {
    return fmt::format("the initial problem (p = {}, s = {}, gamma = {}) did not converge: {}", p,
                       s, gamma, run.last_newton().message);
  }
  std::string failure =
      IncreaseToOne(run, "path", "p = ", p, options.path_increase, options.min_increase,
                    [&](double trial) { return run.Attempt("path", trial, s, gamma, run.y()); });
  if (!failure.empty()) return failure;
  failure = IncreaseToOne(
      run, "stiffness", "scale ", s, options.stiffness_increase, options.min_increase,
      [&](double trial) { return run.Attempt("stiffness", p, trial, gamma, run.y()); });
  if (!failure.empty()) return failure;
  if (before_gamma) {
    failure = before_gamma(gamma);
    if (!failure.empty()) return failure;
  }
  double cd = options.gamma_decrease;
  while (gamma > gamma_target) {
    if (!run.BudgetLeft()) return "Newton solve budget exhausted in the gamma stage";
    double trial = gamma * cd;
    if (trial <= gamma_target * (1.0 + 1e-12)) trial = gamma_target;
    if (run.Attempt("gamma", p, s, trial, run.y())) {
      gamma = trial;
    } else {
      cd = std::sqrt(cd);
      if (1.0 - cd < options.min_increase) {
        return fmt::format("gamma continuation stalled at gamma = {}", gamma);
      }
    }
  }
  return "";
}

// Newton at (p, s, γ) = (1, 1, gamma) on each grid of `grids` after the first, each from the
// previous grid's solution prolonged. Returns false when a solve fails.
bool Refine(const ProblemFamily& family, const std::vector<int>& grids, double gamma,
            ContinuationRun& run) {
  const TrackingProblem problem = ContinuationProblem(family, 1.0, 1.0, gamma);
  for (std::size_t k = 1; k < grids.size(); ++k) {
    if (!run.BudgetLeft()) return false;
    const PontryaginDiscretization coarse(problem, grids[k - 1]);
    const PontryaginDiscretization fine(problem, grids[k]);
    run.SetGrid(grids[k]);
    if (!run.Attempt("refine", 1.0, 1.0, gamma, InterpolateSolution(coarse, run.y(), fine))) {
      return false;
    }
  }
  return true;
}

// The stages before γ on start_grids[0] (if any), prolonged up to grids[0] at the start γ; the γ
// stages on grids[0]; then Newton on each finer grid from the prolonged solution. Returns false
// (y unusable) when a solve fails.
bool SolveCoarseToFine(const ProblemFamily& family, double gamma_target,
                       const std::vector<int>& start_grids, const std::vector<int>& grids,
                       const ContinuationOptions& options, ContinuationRun& run) {
  std::vector<int> up = start_grids;  // the start grids and the γ stages' grid
  up.push_back(grids.front());
  run.SetGrid(up.front());
  const auto to_gamma_grid = [&](double gamma) -> std::string {
    return Refine(family, up, gamma, run) ? "" : "refinement failed";
  };
  if (!RunStages(run, options, gamma_target, Eigen::VectorXd(), to_gamma_grid).empty()) {
    return false;
  }
  return Refine(family, grids, gamma_target, run);
}

}  // namespace

std::vector<int> StartGrids(int steps, const ContinuationOptions& options, double gamma_target,
                            bool warm) {
  const std::vector<int> grids = ContinuationGrids(steps, options, warm);
  std::vector<int> start;
  if (warm || options.coarse_steps <= 0 || options.start_steps <= 0 ||
      !(options.gamma_start > gamma_target)) {
    return start;
  }
  int n = grids.front();
  while (n > options.start_steps) {
    n = (n + options.refine_factor - 1) / options.refine_factor;
    start.push_back(n);
  }
  std::reverse(start.begin(), start.end());
  return start;
}

std::vector<int> ContinuationGrids(int steps, const ContinuationOptions& options, bool warm) {
  std::vector<int> grids = {steps};
  if (warm || options.coarse_steps <= 0) return grids;
  while (grids.back() > options.coarse_steps) {
    grids.push_back((grids.back() + options.refine_factor - 1) / options.refine_factor);
  }
  std::reverse(grids.begin(), grids.end());
  return grids;
}

ContinuationSummary SolveWithContinuation(const ProblemFamily& family, int steps,
                                          const ContinuationOptions& options, Eigen::VectorXd& y,
                                          const Eigen::VectorXd* warm) {
  options.Validate();
  ContinuationRun run(family, options, y);
  const double gamma_target = family(1.0).gamma();
  const std::vector<int> grids = ContinuationGrids(steps, options, warm != nullptr);
  const std::vector<int> start = StartGrids(steps, options, gamma_target, warm != nullptr);
  if ((grids.size() > 1 || !start.empty()) &&
      SolveCoarseToFine(family, gamma_target, start, grids, options, run)) {
    return run.Finish(true, "");
  }
  // The plain path (also the fallback when the coarse-to-fine path failed).
  run.SetGrid(steps);
  const Eigen::VectorXd first = (warm != nullptr) ? *warm : Eigen::VectorXd();
  const std::string failure = RunStages(run, options, gamma_target, first);
  return run.Finish(failure.empty(), failure);
}

Eigen::VectorXd InterpolateSolution(const PontryaginDiscretization& from, const Eigen::VectorXd& y,
                                    const PontryaginDiscretization& to) {
  Eigen::MatrixXd z, rho;
  from.Unpack(y, z, rho);
  const int nf = from.steps();
  const int nt = to.steps();
  Eigen::MatrixXd zt(z.rows(), nt + 1), rt(rho.rows(), nt + 1);
  for (int k = 0; k <= nt; ++k) {
    const double s = static_cast<double>(k) * nf / nt;
    const int i = std::min(static_cast<int>(std::floor(s)), nf - 1);
    const double th = s - i;
    zt.col(k) = (1.0 - th) * z.col(i) + th * z.col(i + 1);
    rt.col(k) = (1.0 - th) * rho.col(i) + th * rho.col(i + 1);
  }
  return to.Pack(zt, rt);
}

}  // namespace moreau::control
