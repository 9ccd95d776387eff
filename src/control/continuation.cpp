#include "moreau/control/continuation.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>

#include "moreau/common/error.h"

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

void ContinuationOptions::Validate() const {
  auto fail = [](const char* field, const std::string& reason) {
    throw InputError(fmt::format("continuation.{}: {}", field, reason));
  };
  if (!(path_start > 0.0 && path_start <= 1.0)) {
    fail("path_start", fmt::format("must be in (0, 1], got {}", path_start));
  }
  if (!(path_increase > 0.0))
    fail("path_increase", fmt::format("must be > 0, got {}", path_increase));
  if (!(stiffness_start > 0.0 && stiffness_start <= 1.0)) {
    fail("stiffness_start", fmt::format("must be in (0, 1], got {}", stiffness_start));
  }
  if (!(stiffness_increase > 0.0)) {
    fail("stiffness_increase", fmt::format("must be > 0, got {}", stiffness_increase));
  }
  if (!(gamma_start >= 0.0) || !std::isfinite(gamma_start)) {
    fail("gamma_start", fmt::format("must be >= 0, got {}", gamma_start));
  }
  if (!(gamma_decrease > 0.0 && gamma_decrease < 1.0)) {
    fail("gamma_decrease", fmt::format("must be in (0, 1), got {}", gamma_decrease));
  }
  if (!(min_increase > 0.0 && min_increase < 1.0)) {
    fail("min_increase", fmt::format("must be in (0, 1), got {}", min_increase));
  }
  if (max_solves < 1) fail("max_solves", fmt::format("must be >= 1, got {}", max_solves));
  fixed_point.Validate();
  newton.Validate();
}

std::string ContinuationSummary::BriefReport() const {
  return fmt::format(
      "continuation: {} after {} Newton solves ({} iterations, {:.2f} s); "
      "reached p = {:.4g}, s = {:.4g}, gamma = {:.3g}{}{}",
      converged ? "converged" : "failed", newton_solves, newton_iterations, time_total,
      path_fraction, stiffness_scale, gamma, message.empty() ? "" : ": ", message);
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

ContinuationSummary SolveWithContinuation(const ProblemFamily& family, int steps,
                                          const ContinuationOptions& options, Eigen::VectorXd& y,
                                          const Eigen::VectorXd* warm) {
  options.Validate();
  const auto start = std::chrono::steady_clock::now();
  ContinuationSummary summary;
  const TrackingProblem target = family(1.0);
  const double gamma_target = target.gamma();
  double p = options.path_start;
  double s = options.stiffness_start;
  double gamma = std::max(options.gamma_start, gamma_target);

  // One Newton solve at (p, s, γ) from `guess`; on success y = solution.
  auto attempt = [&](const char* stage, double pp, double ss, double gg,
                     Eigen::VectorXd guess) -> bool {
    const TrackingProblem problem = ContinuationProblem(family, pp, ss, gg);
    const PontryaginDiscretization disc(problem, steps);
    if (guess.size() != disc.unknowns()) {
      FixedPointSweep(disc, ReferenceGuess(disc), options.fixed_point, guess);
    }
    NewtonSummary ns = SolveNewton(disc, options.newton, guess);
    ++summary.newton_solves;
    summary.newton_iterations += ns.iterations;
    ContinuationRecord rec;
    rec.stage = stage;
    rec.path_fraction = pp;
    rec.stiffness_scale = ss;
    rec.gamma = gg;
    rec.accepted = ns.converged();
    rec.newton_iterations = ns.iterations;
    rec.residual = ns.final_residual;
    rec.termination = ToString(ns.termination);
    summary.path.push_back(rec);
    const bool ok = ns.converged();
    summary.last_newton = std::move(ns);
    if (ok || y.size() == 0) y = guess;  // keep the best iterate if nothing was accepted yet
    if (ok) {
      summary.path_fraction = pp;
      summary.stiffness_scale = ss;
      summary.gamma = gg;
    }
    return ok;
  };
  auto finish = [&](bool converged, std::string message) {
    summary.converged = converged;
    summary.message = std::move(message);
    summary.time_total =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return summary;
  };

  y.resize(0);
  Eigen::VectorXd first = (warm != nullptr) ? *warm : Eigen::VectorXd();
  if (!attempt("initial", p, s, gamma, first)) {
    return finish(false, fmt::format("the initial problem (p = {}, s = {}, gamma = {}) did not "
                                     "converge: {}",
                                     p, s, gamma, summary.last_newton.message));
  }
  auto budget_left = [&]() { return summary.newton_solves < options.max_solves; };

  double cp = options.path_increase;
  while (p < 1.0) {
    if (!budget_left()) return finish(false, "Newton solve budget exhausted in the path stage");
    const double trial = std::min(p * (1.0 + cp), 1.0);
    if (attempt("path", trial, s, gamma, y)) {
      p = trial;
    } else {
      cp *= 0.5;
      if (cp < options.min_increase) {
        return finish(false, fmt::format("path continuation stalled at p = {}", p));
      }
    }
  }
  double cs = options.stiffness_increase;
  while (s < 1.0) {
    if (!budget_left())
      return finish(false, "Newton solve budget exhausted in the stiffness stage");
    const double trial = std::min(s * (1.0 + cs), 1.0);
    if (attempt("stiffness", p, trial, gamma, y)) {
      s = trial;
    } else {
      cs *= 0.5;
      if (cs < options.min_increase) {
        return finish(false, fmt::format("stiffness continuation stalled at scale {}", s));
      }
    }
  }
  double cd = options.gamma_decrease;
  while (gamma > gamma_target) {
    if (!budget_left()) return finish(false, "Newton solve budget exhausted in the gamma stage");
    double trial = gamma * cd;
    if (trial <= gamma_target * (1.0 + 1e-12)) trial = gamma_target;
    if (attempt("gamma", p, s, trial, y)) {
      gamma = trial;
    } else {
      cd = std::sqrt(cd);
      if (1.0 - cd < options.min_increase) {
        return finish(false, fmt::format("gamma continuation stalled at gamma = {}", gamma));
      }
    }
  }
  return finish(true, "");
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

void StudyOptions::Validate() const {
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

std::vector<StudyLevel> RunStudy(const ProblemFamily& family, const StudyOptions& options) {
  options.Validate();
  const TrackingProblem target = family(1.0);
  std::vector<StudyLevel> levels;
  Eigen::VectorXd y_prev;
  std::unique_ptr<PontryaginDiscretization> disc_prev;
  for (int steps : options.steps) {
    const auto start = std::chrono::steady_clock::now();
    auto disc = std::make_unique<PontryaginDiscretization>(target, steps);
    StudyLevel level;
    level.steps = steps;
    Eigen::VectorXd y;
    bool done = false;
    if (options.warm_start && disc_prev != nullptr) {
      y = InterpolateSolution(*disc_prev, y_prev, *disc);
      const NewtonSummary ns = SolveNewton(*disc, options.continuation.newton, y);
      level.newton_iterations = ns.iterations;
      level.newton_total = ns.iterations;
      done = ns.converged();
      level.message = done ? "" : ns.message;
    }
    if (!done) {
      const ContinuationSummary cs = SolveWithContinuation(family, steps, options.continuation, y);
      level.newton_iterations = cs.last_newton.iterations;
      level.newton_total += cs.newton_iterations;
      done = cs.converged;
      level.message = cs.message;
    }
    PontryaginWorkspace ws;
    Eigen::VectorXd residual;
    level.converged = done;
    level.residual = EvaluateResidual(*disc, y, ws, residual);
    level.value = DiscreteValue(*disc, y, ws);
    Eigen::MatrixXd rho;
    disc->Unpack(y, level.z, rho);
    level.controls = EffectiveControls(*disc, y);
    level.tracking_rms = TrackingRms(*disc, level.z);
    level.wall_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    level.diff_previous = levels.empty() ? std::numeric_limits<double>::quiet_NaN()
                                         : MaxPositionDifference(target, level.z, levels.back().z,
                                                                 levels.back().steps);
    if (options.on_level) options.on_level(level);
    levels.push_back(std::move(level));
    y_prev = y;
    disc_prev = std::move(disc);
  }
  const int samples = options.compare_samples > 0 ? options.compare_samples : options.steps.front();
  for (auto& level : levels) {
    level.diff_finest = MaxPositionDifference(target, level.z, levels.back().z, samples);
  }
  return levels;
}

}  // namespace moreau::control
