#include "moreau/control/newton.h"

#include <fmt/format.h>

#include <cmath>
#include <memory>

#include "moreau/common/error.h"
#include "moreau/common/stop.h"
#include "moreau/common/stopwatch.h"
#include "moreau/common/summary_json.h"

namespace moreau::control {

const FieldList<FixedPointOptions>& FixedPointOptions::Fields() {
  using O = FixedPointOptions;
  static const FieldList<O> list = [] {
    FieldList<O> t;
    t.Integer("sweeps", &O::sweeps, Range::NonNegative(), "",
              "forward/backward sweep pairs before the final backward sweep")
        .Number("damping", &O::damping, Range::LeftOpen(0, 1), "", "θ: z ← z + θ (z̃ − z)")
        .Number("tolerance", &O::tolerance, Range::NonNegative(), "",
                "stop early when max |z̃ − z| < this (0: never)");
    return t;
  }();
  return list;
}

void FixedPointOptions::Validate() const { Fields().Validate(*this); }

nlohmann::json FixedPointOptions::ToJson() const { return Fields().ToJson(*this); }

nlohmann::json FixedPointSummary::ToJson() const {
  nlohmann::json j = SummaryJson(termination, message, total_seconds);
  j["sweeps"] = sweeps;
  j["change"] = change;
  j["settings"] = options.ToJson();
  return j;
}

FixedPointSummary FixedPointSweep(const PontryaginDiscretization& disc,
                                  const Eigen::MatrixXd& z_guess, const FixedPointOptions& options,
                                  Eigen::VectorXd& y) {
  options.Validate();
  const Stopwatch stopwatch;
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
  summary.options = options;
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
      summary.termination = Termination::kDiverged;
      summary.message = fmt::format("non-finite state in forward sweep {}", s + 1);
      break;
    }
    const double change = (zt - z).lpNorm<Eigen::Infinity>();
    summary.change.push_back(change);
    z += options.damping * (zt - z);
    ++summary.sweeps;
    if (change < options.tolerance) {
      summary.termination = Termination::kConverged;
      break;
    }
  }
  backward();
  if (summary.ok() && !rho.allFinite()) {
    summary.termination = Termination::kDiverged;
    summary.message = "non-finite dual in the final backward sweep";
  }
  y = disc.Pack(z, rho);
  summary.total_seconds = stopwatch.Seconds();
  return summary;
}

const FieldList<NewtonOptions>& NewtonOptions::Fields() {
  using O = NewtonOptions;
  static const FieldList<O> list = [] {
    FieldList<O> t;
    t.Integer("max_iterations", &O::max_iterations, Range::AtLeast(1), "",
              "Newton iterations (Jacobian factorisations)")
        .Number("residual_tolerance", &O::residual_tolerance, Range::Positive(), "solver units",
                "converged when ‖F(y)‖_∞ ≤ this")
        .Choice("linear_solver", &O::linear_solver, kLinearSolverNames,
                "solver of the Newton system: the Riccati sweep or sparse LU")
        .Number("armijo", &O::armijo, Range::Open(0, 0.5), "",
                "sufficient decrease c: ½‖F(y+αδ)‖² ≤ (1 − 2cα) ½‖F(y)‖²")
        .Number("min_step", &O::min_step, Range::LeftOpen(0, 1), "",
                "the line search gives up below this step length α")
        .Number("divergence_threshold", &O::divergence_threshold, Range::Positive(), "solver units",
                "‖F‖_∞ above this (or non-finite) counts as divergence")
        .Integer("threads", &O::threads, Range::NonNegative(), "",
                 "OpenMP threads over time steps (0: the OpenMP default); same bits for any")
        .Rule("divergence_threshold", [](const O& o) {
          return o.divergence_threshold > o.residual_tolerance
                     ? std::string()
                     : std::string("must exceed residual_tolerance");
        });
    return t;
  }();
  return list;
}

void NewtonOptions::Validate() const { Fields().Validate(*this); }

nlohmann::json NewtonOptions::ToJson() const { return Fields().ToJson(*this); }

nlohmann::json NewtonSummary::ToJson() const {
  nlohmann::json j = SummaryJson(termination, message, total_seconds);
  j["iterations"] = iterations;
  j["residual_norms"] = residual_norms;
  j["step_lengths"] = step_lengths;
  j["initial_residual"] = FiniteOrNull(initial_residual);
  j["final_residual"] = FiniteOrNull(final_residual);
  j["residual_jacobian_seconds"] = residual_jacobian_seconds;
  j["factorize_seconds"] = factorize_seconds;
  j["solve_seconds"] = solve_seconds;
  j["line_search_seconds"] = line_search_seconds;
  j["settings"] = options.ToJson();
  return j;
}

std::string NewtonSummary::BriefReport() const {
  return fmt::format("Newton: {} after {} iterations, |F| {:.3e} -> {:.3e} ({:.3f} s){}{}",
                     ToString(termination), iterations, initial_residual, final_residual,
                     total_seconds, message.empty() ? "" : ": ", message);
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
      residual_jacobian_seconds, factorize_seconds, solve_seconds, line_search_seconds,
      total_seconds);
  return r;
}

namespace {

// Backtracking line search on ½‖F‖₂² from y along step: the first α = 1, ½, ¼, … ≥ min_step with
// ½‖F(y + α step)‖² ≤ (1 − 2 armijo α) ½‖F(y)‖² (trial holds y + α step), or 0 when none is.
double LineSearch(const PontryaginDiscretization& disc, const NewtonOptions& options,
                  const Eigen::VectorXd& y, const Eigen::VectorXd& step,
                  const Eigen::VectorXd& residual, PontryaginWorkspace& ws, Eigen::VectorXd& trial,
                  Eigen::VectorXd& trial_residual) {
  const double merit = 0.5 * residual.squaredNorm();
  for (double alpha = 1.0; alpha >= options.min_step; alpha *= 0.5) {
    trial = y + alpha * step;
    const double trial_norm = EvaluateResidual(disc, trial, ws, trial_residual);
    if (std::isfinite(trial_norm) &&
        0.5 * trial_residual.squaredNorm() <= (1.0 - 2.0 * options.armijo * alpha) * merit) {
      return alpha;
    }
  }
  return 0.0;
}

// Throws Interrupted before Newton iteration ITERATION (1-based) once a stop was requested.
void ThrowIfStopRequested(int iteration) {
  if (StopRequested()) {
    throw Interrupted(fmt::format("stopped on request before Newton iteration {}", iteration));
  }
}

}  // namespace

NewtonSummary SolveNewton(const PontryaginDiscretization& disc, const NewtonOptions& options,
                          Eigen::VectorXd& y) {
  NewtonWorkspace workspace;
  return SolveNewton(disc, options, y, workspace);
}

namespace {

// The workspace's linear solver of `type`, made on first use or when the type changes.
NewtonLinearSolver* LinearSolverOf(NewtonWorkspace& workspace, LinearSolverType type) {
  if (!workspace.solver || workspace.solver_type != type) {
    if (type == LinearSolverType::kRiccati) {
      workspace.solver = std::make_unique<RiccatiSolver>();
    } else {
      workspace.solver = std::make_unique<SparseLuSolver>();
    }
    workspace.solver_type = type;
  }
  return workspace.solver.get();
}

}  // namespace

NewtonSummary SolveNewton(const PontryaginDiscretization& disc, const NewtonOptions& options,
                          Eigen::VectorXd& y, NewtonWorkspace& workspace) {
  options.Validate();
  const Stopwatch total;
  NewtonSummary summary;
  summary.options = options;
  NewtonLinearSolver* solver = LinearSolverOf(workspace, options.linear_solver);
  PontryaginWorkspace& ws = workspace.pontryagin;
  ws.threads = options.threads;
  Eigen::VectorXd& residual = workspace.residual;
  Eigen::VectorXd& trial_residual = workspace.trial_residual;
  Eigen::VectorXd& step = workspace.step;
  Eigen::VectorXd& trial = workspace.trial;
  Stopwatch phase;
  double norm = EvaluateResidualAndJacobian(disc, y, ws, residual);
  summary.residual_jacobian_seconds += phase.Seconds();
  summary.initial_residual = norm;
  summary.residual_norms.push_back(norm);
  auto finish = [&](Termination termination, std::string message) {
    summary.termination = termination;
    summary.message = std::move(message);
    summary.final_residual = summary.residual_norms.back();
    summary.total_seconds = total.Seconds();
    return summary;
  };
  if (!std::isfinite(norm) || norm > options.divergence_threshold) {
    return finish(Termination::kDiverged,
                  fmt::format("the initial guess has residual {:.3e}", norm));
  }
  // After a step, the line search's F(y) is the residual; the Jacobian is evaluated only when
  // another step follows (F from EvaluateResidual and EvaluateResidualAndJacobian is the same).
  for (int it = 0;; ++it) {
    if (norm <= options.residual_tolerance) {
      return finish(Termination::kConverged, "");
    }
    ThrowIfStopRequested(it + 1);
    if (it >= options.max_iterations) {
      return finish(Termination::kMaxIterations,
                    fmt::format("residual {:.3e} > tolerance {:.1e} after {} iterations", norm,
                                options.residual_tolerance, it));
    }
    if (it > 0) {
      phase.Restart();
      EvaluateResidualAndJacobian(disc, y, ws, residual);
      summary.residual_jacobian_seconds += phase.Seconds();
    }
    phase.Restart();
    const bool ok = solver->Factorize(disc, ws.jacobian);
    summary.factorize_seconds += phase.Seconds();
    if (!ok) {
      return finish(Termination::kSingularJacobian,
                    fmt::format("singular Jacobian at iteration {}", it + 1));
    }
    phase.Restart();
    solver->Solve(-residual, step);
    summary.solve_seconds += phase.Seconds();
    if (!step.allFinite()) {
      return finish(Termination::kSingularJacobian,
                    fmt::format("non-finite Newton step at iteration {}", it + 1));
    }
    phase.Restart();
    const double alpha = LineSearch(disc, options, y, step, residual, ws, trial, trial_residual);
    const bool accepted = alpha > 0.0;
    summary.line_search_seconds += phase.Seconds();
    if (!accepted) {
      return finish(Termination::kLineSearchFailed,
                    fmt::format("no decrease of |F| along the Newton direction at iteration {} "
                                "(residual {:.3e})",
                                it + 1, norm));
    }
    y.swap(trial);
    residual.swap(trial_residual);
    norm = residual.lpNorm<Eigen::Infinity>();  // finite: the line search accepted it
    ++summary.iterations;
    summary.step_lengths.push_back(alpha);
    summary.residual_norms.push_back(norm);
    if (!std::isfinite(norm) || norm > options.divergence_threshold) {
      return finish(Termination::kDiverged,
                    fmt::format("residual {:.3e} at iteration {}", norm, it + 1));
    }
  }
}

}  // namespace moreau::control
