#include "moreau/control/refinement_study.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>

#include "moreau/common/error.h"
#include "moreau/common/stopwatch.h"
#include "moreau/common/summary_json.h"

namespace moreau::control {

double MaxPositionDifference(const TrackingProblem& problem, const Eigen::MatrixXd& za,
                             const Eigen::MatrixXd& zb, int samples) {
  const SpringNetwork& net = problem.network();
  const int d = net.dimension();
  const int na = static_cast<int>(za.cols()) - 1;
  const int nb = static_cast<int>(zb.cols()) - 1;
  auto at = [](const Eigen::MatrixXd& z, int n, double tau, Eigen::VectorXd& out) {
    const double s = tau * n;
    const int i = std::min(static_cast<int>(std::floor(s + 1e-9)), n - 1);
    double th = s - i;
    if (std::abs(th) < 1e-9) th = 0.0;
    if (std::abs(th - 1.0) < 1e-9) th = 1.0;
    out = (1.0 - th) * z.col(i) + th * z.col(i + 1);
  };
  Eigen::VectorXd a, b;
  double diff = 0.0;
  for (int k = 0; k <= samples; ++k) {
    const double tau = static_cast<double>(k) / samples;
    at(za, na, tau, a);
    at(zb, nb, tau, b);
    for (int j = 0; j < net.num_free(); ++j) {
      for (int i = 0; i < d; ++i) {
        diff = std::max(diff, std::abs(a[2 * d * j + i] - b[2 * d * j + i]));
      }
    }
  }
  return diff;
}

double TrackingRms(const PontryaginDiscretization& disc, const Eigen::MatrixXd& z) {
  const SpringNetwork& net = disc.problem().network();
  const int d = net.dimension();
  double sum = 0.0;
  long count = 0;
  for (int n = 0; n <= disc.steps(); ++n) {
    const Instant& in = disc.instant(n);
    for (int j = 0; j < net.num_free(); ++j) {
      if (!(in.ref_weight[j] > 0.0)) continue;
      for (int i = 0; i < d; ++i) {
        const double e = z(2 * d * j + i, n) - in.ref_position[d * j + i];
        sum += e * e;
      }
      ++count;
    }
  }
  return count > 0 ? std::sqrt(sum / static_cast<double>(count)) : 0.0;
}

void RefinementStudyOptions::Validate() const {
  if (steps.empty()) throw InputError("study.steps: needs at least one number of steps");
  for (std::size_t i = 0; i < steps.size(); ++i) {
    if (steps[i] < 1) {
      throw InputError(fmt::format("study.steps: every N must be >= 1, got {}", steps[i]));
    }
    if (i > 0 && steps[i] <= steps[i - 1]) {
      throw InputError("study.steps: the numbers of steps must increase");
    }
  }
  if (compare_samples < 0) throw InputError("study.compare_samples: must be >= 0");
  continuation.Validate();
}

nlohmann::json RefinementStudyOptions::ToJson() const {
  return {{"steps", steps},
          {"warm_start", warm_start},
          {"compare_samples", compare_samples},
          {"continuation", continuation.ToJson()}};
}

nlohmann::json RefinementLevel::ToJson() const {
  nlohmann::json j = SummaryJson(termination, message, total_seconds);
  j["steps"] = steps;
  j["value"] = FiniteOrNull(value);
  j["residual_norm"] = FiniteOrNull(residual);
  j["newton_iterations"] = newton_iterations;
  j["newton_total"] = newton_total;
  j["diff_previous"] = FiniteOrNull(diff_previous);
  j["diff_finest"] = FiniteOrNull(diff_finest);
  j["tracking_rms"] = FiniteOrNull(tracking_rms);
  return j;
}

nlohmann::json RefinementStudySummary::ToJson() const {
  nlohmann::json j = SummaryJson(termination, message, total_seconds);
  std::vector<int> n;
  nlohmann::json rows = nlohmann::json::array();
  for (const RefinementLevel& level : levels) {
    n.push_back(level.steps);
    rows.push_back(level.ToJson());
  }
  j["steps"] = n;
  j["levels"] = std::move(rows);
  j["settings"] = options.ToJson();
  return j;
}

namespace {

// Solves one N: Newton from the interpolated coarser solution (warm start), else continuation.
// Fills everything but the comparison columns; y is the solution.
RefinementLevel SolveLevel(const ProblemFamily& family, const RefinementStudyOptions& options,
                           const PontryaginDiscretization& disc,
                           const PontryaginDiscretization* coarser,
                           const Eigen::VectorXd& y_coarser, Eigen::VectorXd& y) {
  const Stopwatch stopwatch;
  RefinementLevel level;
  level.steps = disc.steps();
  bool done = false;
  if (options.warm_start && coarser != nullptr) {
    y = InterpolateSolution(*coarser, y_coarser, disc);
    const NewtonSummary ns = SolveNewton(disc, options.continuation.newton, y);
    level.newton_iterations = ns.iterations;
    level.newton_total = ns.iterations;
    level.termination = ns.termination;
    done = ns.ok();
    level.message = done ? "" : ns.message;
  }
  if (!done) {
    const ContinuationSummary cs =
        SolveWithContinuation(family, disc.steps(), options.continuation, y);
    level.newton_iterations = cs.last_newton.iterations;
    level.newton_total += cs.newton_iterations;
    level.termination = cs.termination;
    level.message = cs.message;
  }
  PontryaginWorkspace ws;
  Eigen::VectorXd residual;
  level.residual = EvaluateResidual(disc, y, ws, residual);
  level.value = DiscreteValue(disc, y, ws);
  Eigen::MatrixXd rho;
  disc.Unpack(y, level.z, rho);
  level.controls = EffectiveControls(disc, y);
  level.tracking_rms = TrackingRms(disc, level.z);
  level.total_seconds = stopwatch.Seconds();
  return level;
}

}  // namespace

RefinementStudySummary RunRefinementStudy(const ProblemFamily& family,
                                          const RefinementStudyOptions& options) {
  options.Validate();
  const Stopwatch stopwatch;
  RefinementStudySummary summary;
  summary.options = options;
  summary.options.on_level = nullptr;
  std::vector<RefinementLevel>& levels = summary.levels;
  const TrackingProblem target = family(1.0);
  try {
    CheckSolveMemory(target.network(), options.steps.back());  // the finest level, before any
  } catch (const InputError& e) {
    throw InputError("study.steps", e.what());
  }
  Eigen::VectorXd y_prev;
  std::unique_ptr<PontryaginDiscretization> disc_prev;
  for (int steps : options.steps) {
    auto disc = std::make_unique<PontryaginDiscretization>(target, steps);
    Eigen::VectorXd y;
    RefinementLevel level = SolveLevel(family, options, *disc, disc_prev.get(), y_prev, y);
    level.diff_previous = levels.empty() ? std::numeric_limits<double>::quiet_NaN()
                                         : MaxPositionDifference(target, level.z, levels.back().z,
                                                                 levels.back().steps);
    if (options.on_level) options.on_level(level);
    if (summary.ok() && !level.ok()) {
      summary.termination = level.termination;
      summary.message = fmt::format("N = {}: {}", steps, level.message);
    }
    levels.push_back(std::move(level));
    y_prev = y;
    disc_prev = std::move(disc);
  }
  const int samples = options.compare_samples > 0 ? options.compare_samples : options.steps.front();
  for (auto& level : levels) {
    level.diff_finest = MaxPositionDifference(target, level.z, levels.back().z, samples);
  }
  summary.total_seconds = stopwatch.Seconds();
  return summary;
}

}  // namespace moreau::control
