// Solvers for the discrete Hamiltonian system F(y) = 0 (thesis sections 7.1–7.3).
//
// FixedPointSweep (7.1): from a guess of the state trajectory, alternately sweep the dual
// backward (ρ^N = Dg(z^N), ρ^n = ρ^{n+1} + Δt H_z(z^n, ρ^{n+1})) and the state forward
// (z̃^{n+1} = z̃^n + Δt H_ρ(z̃^n, ρ^{n+1})), relaxing z ← z + θ (z̃ − z) ("damped"); ends with a
// backward sweep so that the returned y satisfies every F^ρ equation exactly. Used to obtain the
// initial dual for Newton.
//
// SolveNewton (7.2, 7.3): Newton's method on F(y) = 0 with a backtracking (Armijo) line search on
// ½‖F‖₂²; the linear system is solved by the Riccati sweep (default) or sparse LU. The line search
// only accepts decreasing merit, so on any failure y holds the best iterate found.
#pragma once

#include <Eigen/Core>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "moreau/common/field_list.h"
#include "moreau/common/termination.h"
#include "moreau/control/linear_solver.h"
#include "moreau/control/pontryagin.h"

namespace moreau::control {

struct FixedPointOptions {
  int sweeps = 0;          // forward/backward sweep pairs before the final backward sweep (>= 0)
  double damping = 0.5;    // θ ∈ (0, 1]: z ← z + θ (z̃ − z)
  double tolerance = 0.0;  // stop early when max |z̃ − z| < tolerance (0: never)
  static const FieldList<FixedPointOptions>& Fields();  // key, range, help of every field
  // Throws InputError(key, reason) on sweeps < 0, θ ∉ (0, 1] or tolerance < 0.
  void Validate() const;
  nlohmann::json ToJson() const;  // {"sweeps", "damping", "tolerance"}
};

struct FixedPointSummary {
  // kConverged: a sweep changed z by less than the tolerance; kCompleted: every sweep ran;
  // kDiverged: a sweep produced a non-finite value.
  Termination termination = Termination::kCompleted;
  std::string message;         // why it failed (empty on success)
  int sweeps = 0;              // forward sweeps done
  std::vector<double> change;  // max |z̃ − z| per forward sweep
  double total_seconds = 0.0;
  FixedPointOptions options;  // the settings used

  bool ok() const { return IsSuccess(termination); }
  nlohmann::json ToJson() const;  // SummaryJson + sweeps, change, settings
};

// `z_guess`: n_z × (N+1) state trajectory guess (column 0 is replaced by z(0)). Writes y.
FixedPointSummary FixedPointSweep(const PontryaginDiscretization& disc,
                                  const Eigen::MatrixXd& z_guess, const FixedPointOptions& options,
                                  Eigen::VectorXd& y);

struct NewtonOptions {
  int max_iterations = 40;            // Newton iterations (Jacobian factorisations), >= 1
  double residual_tolerance = 1e-10;  // converged when ‖F(y)‖_∞ <= this
  LinearSolverType linear_solver = LinearSolverType::kRiccati;  // structure-exploiting or LU
  double armijo = 1e-4;  // sufficient decrease: ½‖F(y+αδ)‖² <= (1 − 2cα) ½‖F(y)‖²
  double min_step = 1e-6;              // line search gives up below this step length α
  double divergence_threshold = 1e12;  // ‖F‖_∞ above this (or non-finite) counts as divergence
  int threads = 0;  // OpenMP threads of the residual/Jacobian over time steps (>= 0; 0: the
                    // OpenMP default); results are bit-identical for every thread count
  static const FieldList<NewtonOptions>& Fields();  // key, range, help of every field
  // Throws InputError(key, reason) on a value out of range.
  void Validate() const;
  // {"max_iterations", "residual_tolerance", "linear_solver", "armijo", "min_step",
  //  "divergence_threshold", "threads"}
  nlohmann::json ToJson() const;
};

struct NewtonSummary {
  // kConverged: ‖F‖_∞ <= tolerance; kMaxIterations: iteration limit reached; kLineSearchFailed:
  // no step length >= min_step decreased the merit; kSingularJacobian: the linear solver met a
  // singular (or non-finite) pivot block; kDiverged: the residual is non-finite or above the
  // divergence threshold.
  Termination termination = Termination::kMaxIterations;
  std::string message;
  int iterations = 0;                  // Newton steps taken (accepted)
  std::vector<double> residual_norms;  // ‖F‖_∞ at the start and after each accepted step
  std::vector<double> step_lengths;    // α of each accepted step
  double initial_residual = 0.0;
  double final_residual = 0.0;
  double residual_jacobian_seconds = 0.0;  // F and Jacobian evaluation
  double factorize_seconds = 0.0;          // linear solver factorisation
  double solve_seconds = 0.0;              // triangular/Riccati solves
  double line_search_seconds = 0.0;        // residual evaluations in the line search
  double total_seconds = 0.0;              // the whole solve
  NewtonOptions options;                   // the settings used

  bool ok() const { return IsSuccess(termination); }
  std::string BriefReport() const;  // one line
  std::string FullReport() const;   // residual and step length per iteration, time per phase
  // SummaryJson + iterations, residual_norms, step_lengths, initial/final_residual, the phase
  // *_seconds and settings.
  nlohmann::json ToJson() const;
};

// Newton on F(y) = 0 starting from y (overwritten by the best iterate). Throws Interrupted
// (common/stop.h) before an iteration when a stop was requested.
NewtonSummary SolveNewton(const PontryaginDiscretization& disc, const NewtonOptions& options,
                          Eigen::VectorXd& y);

// Scratch of SolveNewton (residuals, the Jacobian blocks, the linear solver's factors), kept
// between solves so that a sequence of solves (continuation) allocates its N-block storage once
// instead of once per solve. Any grid size; results do not depend on what it held before.
struct NewtonWorkspace {
  PontryaginWorkspace pontryagin;
  std::unique_ptr<NewtonLinearSolver> solver;  // of the type `solver_type` (made on first use)
  LinearSolverType solver_type = LinearSolverType::kRiccati;
  Eigen::VectorXd residual, trial_residual, step, trial;
};

// SolveNewton with the caller's scratch.
NewtonSummary SolveNewton(const PontryaginDiscretization& disc, const NewtonOptions& options,
                          Eigen::VectorXd& y, NewtonWorkspace& workspace);

}  // namespace moreau::control
