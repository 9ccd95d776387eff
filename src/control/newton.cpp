#include "moreau/control/newton.h"

#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <memory>

#include "moreau/common/error.h"

namespace moreau::control {
namespace {

double Seconds(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

}  // namespace

void FixedPointOptions::Validate() const {
  if (sweeps < 0) throw InputError(fmt::format("fixed_point.sweeps: must be >= 0, got {}", sweeps));
  if (!(damping > 0.0 && damping <= 1.0)) {
    throw InputError(fmt::format("fixed_point.damping: must be in (0, 1], got {}", damping));
  }
  if (!(tolerance >= 0.0)) {
    throw InputError(fmt::format("fixed_point.tolerance: must be >= 0, got {}", tolerance));
  }
}

FixedPointSummary FixedPointSweep(const PontryaginDiscretization& disc,
                                  const Eigen::MatrixXd& z_guess, const FixedPointOptions& options,
                                  Eigen::VectorXd& y) {
  options.Validate();
  const int N = disc.steps();
  const int nz = disc.state_size();
  MOREAU_ASSERT(z_guess.rows() == nz && z_guess.cols() == N + 1);
  const TrackingProblem& problem = disc.problem();
  Eigen::MatrixXd z = z_guess;
  z.col(0) = disc.initial_state();
  Eigen::MatrixXd rho(nz, N + 1);
  HamiltonianEval eval;
  Eigen::VectorXd zn, rn, dg;
  auto backward = [&]() {
    zn = z.col(N);
    TerminalCost(problem, disc.instant(N), zn, &dg, nullptr);
    rho.col(N) = dg;
    for (int n = N - 1; n >= 0; --n) {
      zn = z.col(n);
      rn = rho.col(n + 1);
      EvaluateRegularizedHamiltonian(problem, disc.instant(n), zn, rn, HamiltonianOrder::kGradient,
                                     eval);
      rho.col(n) = rn + disc.dt() * eval.dz;
    }
  };
  FixedPointSummary summary;
  Eigen::MatrixXd zt(nz, N + 1);
  for (int s = 0; s < options.sweeps; ++s) {
    backward();
    zt.col(0) = z.col(0);
    for (int n = 0; n < N; ++n) {
      zn = zt.col(n);
      rn = rho.col(n + 1);
      EvaluateRegularizedHamiltonian(problem, disc.instant(n), zn, rn, HamiltonianOrder::kGradient,
                                     eval);
      zt.col(n + 1) = zn + disc.dt() * eval.drho;
    }
    if (!zt.allFinite()) {
      summary.finite = false;
      break;
    }
    const double change = (zt - z).lpNorm<Eigen::Infinity>();
    summary.change.push_back(change);
    z += options.damping * (zt - z);
    ++summary.sweeps;
    if (change < options.tolerance) break;
  }
  backward();
  if (!rho.allFinite()) summary.finite = false;
  y = disc.Pack(z, rho);
  return summary;
}

void NewtonOptions::Validate() const {
  if (max_iterations < 1) {
    throw InputError(fmt::format("newton.max_iterations: must be >= 1, got {}", max_iterations));
  }
  if (!(residual_tolerance > 0.0)) {
    throw InputError(
        fmt::format("newton.residual_tolerance: must be > 0, got {}", residual_tolerance));
  }
  if (!(armijo > 0.0 && armijo < 0.5)) {
    throw InputError(fmt::format("newton.armijo: must be in (0, 0.5), got {}", armijo));
  }
  if (!(min_step > 0.0 && min_step <= 1.0)) {
    throw InputError(fmt::format("newton.min_step: must be in (0, 1], got {}", min_step));
  }
  if (!(divergence_threshold > residual_tolerance)) {
    throw InputError("newton.divergence_threshold: must exceed newton.residual_tolerance");
  }
}

const char* ToString(NewtonTermination termination) {
  switch (termination) {
    case NewtonTermination::kConverged:
      return "converged";
    case NewtonTermination::kMaxIterations:
      return "max_iterations";
    case NewtonTermination::kLineSearchFailed:
      return "line_search_failed";
    case NewtonTermination::kSingularJacobian:
      return "singular_jacobian";
    case NewtonTermination::kDiverged:
      return "diverged";
  }
  return "unknown";
}

std::string NewtonSummary::BriefReport() const {
  return fmt::format("Newton: {} after {} iterations, |F| {:.3e} -> {:.3e} ({:.3f} s){}{}",
                     ToString(termination), iterations, initial_residual, final_residual,
                     time_total, message.empty() ? "" : ": ", message);
}

std::string NewtonSummary::FullReport() const {
  std::string r = BriefReport() + "\n  iteration  |F|_inf       step\n";
  for (std::size_t i = 0; i < residual_norms.size(); ++i) {
    r += fmt::format("  {:9d}  {:.6e}  {}\n", i, residual_norms[i],
                     i == 0 ? std::string("-") : fmt::format("{:.4g}", step_lengths[i - 1]));
  }
  r += fmt::format(
      "  time [s]: residual+Jacobian {:.4f}, factorize {:.4f}, solve {:.4f}, line search {:.4f}, "
      "total {:.4f}\n",
      time_residual_jacobian, time_factorize, time_solve, time_line_search, time_total);
  return r;
}

NewtonSummary SolveNewton(const PontryaginDiscretization& disc, const NewtonOptions& options,
                          Eigen::VectorXd& y) {
  options.Validate();
  const auto start = std::chrono::steady_clock::now();
  NewtonSummary summary;
  std::unique_ptr<NewtonLinearSolver> solver;
  if (options.linear_solver == LinearSolverType::kRiccati) {
    solver = std::make_unique<RiccatiSolver>();
  } else {
    solver = std::make_unique<SparseLuSolver>();
  }
  PontryaginWorkspace ws;
  Eigen::VectorXd residual, trial_residual, step, trial;
  auto t0 = std::chrono::steady_clock::now();
  double norm = EvaluateResidualAndJacobian(disc, y, ws, residual);
  summary.time_residual_jacobian += Seconds(t0);
  summary.initial_residual = norm;
  summary.residual_norms.push_back(norm);
  auto finish = [&](NewtonTermination termination, std::string message) {
    summary.termination = termination;
    summary.message = std::move(message);
    summary.final_residual = summary.residual_norms.back();
    summary.time_total = Seconds(start);
    return summary;
  };
  if (!std::isfinite(norm) || norm > options.divergence_threshold) {
    return finish(NewtonTermination::kDiverged,
                  fmt::format("the initial guess has residual {:.3e}", norm));
  }
  for (int it = 0;; ++it) {
    if (norm <= options.residual_tolerance) {
      return finish(NewtonTermination::kConverged, "");
    }
    if (it >= options.max_iterations) {
      return finish(NewtonTermination::kMaxIterations,
                    fmt::format("residual {:.3e} > tolerance {:.1e} after {} iterations", norm,
                                options.residual_tolerance, it));
    }
    t0 = std::chrono::steady_clock::now();
    const bool ok = solver->Factorize(disc, ws.jacobian);
    summary.time_factorize += Seconds(t0);
    if (!ok) {
      return finish(NewtonTermination::kSingularJacobian,
                    fmt::format("singular Jacobian at iteration {}", it + 1));
    }
    t0 = std::chrono::steady_clock::now();
    solver->Solve(-residual, step);
    summary.time_solve += Seconds(t0);
    if (!step.allFinite()) {
      return finish(NewtonTermination::kSingularJacobian,
                    fmt::format("non-finite Newton step at iteration {}", it + 1));
    }
    // Backtracking line search on ½‖F‖₂².
    t0 = std::chrono::steady_clock::now();
    const double merit = 0.5 * residual.squaredNorm();
    double alpha = 1.0;
    bool accepted = false;
    double trial_norm = 0.0;
    while (alpha >= options.min_step) {
      trial = y + alpha * step;
      trial_norm = EvaluateResidual(disc, trial, ws, trial_residual);
      if (std::isfinite(trial_norm) &&
          0.5 * trial_residual.squaredNorm() <= (1.0 - 2.0 * options.armijo * alpha) * merit) {
        accepted = true;
        break;
      }
      alpha *= 0.5;
    }
    summary.time_line_search += Seconds(t0);
    if (!accepted) {
      return finish(NewtonTermination::kLineSearchFailed,
                    fmt::format("no decrease of |F| along the Newton direction at iteration {} "
                                "(residual {:.3e})",
                                it + 1, norm));
    }
    y.swap(trial);
    ++summary.iterations;
    summary.step_lengths.push_back(alpha);
    t0 = std::chrono::steady_clock::now();
    norm = EvaluateResidualAndJacobian(disc, y, ws, residual);
    summary.time_residual_jacobian += Seconds(t0);
    summary.residual_norms.push_back(norm);
    if (!std::isfinite(norm) || norm > options.divergence_threshold) {
      return finish(NewtonTermination::kDiverged,
                    fmt::format("residual {:.3e} at iteration {}", norm, it + 1));
    }
  }
}

}  // namespace moreau::control
