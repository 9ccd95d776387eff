// Parameter continuation (thesis section 8.2).
//
// Continuation solves a sequence of easier problems and warm-starts Newton from each accepted
// solution, in three stages, each with step halving on failure:
//   path:      p ← min(p (1 + C^p), 1); on failure C^p ← C^p / 2 (reference scaled by p),
//   stiffness: s ← min(s (1 + C^κξ), 1); on failure C^κξ ← C^κξ / 2 (κ, ξ scaled by s),
//   δ:         γ ← max(γ C^δ, γ_target); on failure C^δ ← √C^δ (δ ∝ γ).
// (The thesis prints "C^p = √C^p" in step 6, a misprint for C^δ; Deltaforward.m does coe^.5.)
// A stage gives up when its coefficient falls below min_increase (for δ: when 1 − C^δ does).
// Every attempt, accepted or not, is recorded.
//
// Coarse to fine (coarse_steps > 0, no warm start): the grids form one chain
// N_k = ⌈N_{k+1} / refine_factor⌉ ending at the requested N. The γ stages run on N_0, the largest
// grid of the chain <= coarse_steps. With δ continuation (gamma_start > target γ) and
// start_steps > 0, the stages before γ run on the largest grid of the chain <= start_steps, and
// their solution at (1, 1, gamma_start) is prolonged (InterpolateSolution) grid by grid up to N_0
// and polished there by Newton ("refine" records). After the γ stages the target solution is
// prolonged to N_1, N_2, …, N and polished alike. The last solve is Newton on the requested grid
// to the same tolerance, so the answer is that grid's solution (the one the plain path finds when
// both converge to the same root). If any solve of the coarse-to-fine path fails, the plain path
// runs on the requested grid. Both sizes are numbers of steps, not fractions of N: a grid has to
// resolve the controls' switches, whose width shrinks with γ (docs/control.md, "Performance").
#pragma once

#include <Eigen/Core>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "moreau/control/newton.h"
#include "moreau/control/pontryagin.h"
#include "moreau/control/tracking_problem.h"

namespace moreau::control {

// The problem with its reference scaled to the path fraction p ∈ (0, 1] (p = 1: the target
// problem, whose κ, ξ and γ are the targets of continuation).
using ProblemFamily = std::function<TrackingProblem(double path_fraction)>;

// A family for a generic problem: X_p(t) = x(0) + p (X(t) − x(0)), V_p = p V.
ProblemFamily LinearPathFamily(const TrackingProblem& problem);

struct ContinuationOptions {
  double path_start = 1.0;          // p_0 ∈ (0, 1]; 1: no path continuation
  double path_increase = 0.5;       // C^p > 0
  double stiffness_start = 1.0;     // s_0 ∈ (0, 1]: κ and ξ start at s_0 × target; 1: none
  double stiffness_increase = 0.5;  // C^κξ > 0
  double gamma_start = 0.0;         // γ_0; <= target γ (e.g. 0): no δ continuation
  double gamma_decrease = 0.1;      // C^δ ∈ (0, 1)
  double min_increase = 1e-4;       // smallest coefficient before a stage gives up
  int max_solves = 400;             // Newton solves in all, accepted or not (>= 1)
  int coarse_steps = 512;           // coarse-to-fine: largest coarse grid (>= 0; 0: every stage
                                    // on the requested grid, the plain path)
  int refine_factor = 2;            // ratio of successive grids (>= 2)
  int start_steps = 64;             // coarse-to-fine with δ continuation (gamma_start > target
                                    // γ): largest grid of the stages before γ (>= 0; 0: they run
                                    // on the coarse grid too)
  FixedPointOptions fixed_point;    // initial dual from the guess (section 7.1)
  NewtonOptions newton;             // every Newton solve
  static const FieldList<ContinuationOptions>& Fields();  // with fixed_point.*, newton.*
  // Throws InputError(key, reason) on a value out of range.
  void Validate() const;
  // The continuation fields, with "fixed_point" and "newton" as nested objects.
  nlohmann::json ToJson() const;
};

struct ContinuationRecord {
  std::string stage;  // "initial", "path", "stiffness", "gamma", "refine"
  int steps = 0;      // N of the grid solved on
  double path_fraction = 1.0;
  double stiffness_scale = 1.0;
  double gamma = 0.0;
  bool accepted = false;
  int newton_iterations = 0;
  double residual = 0.0;                              // ‖F‖_∞ at the end of the solve
  Termination termination = Termination::kConverged;  // of the Newton solve
  // {"stage", "steps", "path_fraction", "stiffness_scale", "gamma", "accepted",
  //  "newton_iterations", "residual_norm", "termination"}
  nlohmann::json ToJson() const;
};

// The Newton solves on one grid, in the order the grids were visited.
struct GridRecord {
  int steps = 0;
  int newton_solves = 0;
  int newton_iterations = 0;
  double total_seconds = 0.0;  // the solves on this grid, with their set-up
  // {"steps", "newton_solves", "newton_iterations", "total_seconds"}
  nlohmann::json ToJson() const;
};

struct ContinuationSummary {
  // kConverged: the target problem was solved. Otherwise the termination of the Newton solve
  // that failed, or kMaxIterations when the budget of Newton solves ran out.
  Termination termination = Termination::kMaxIterations;
  std::string message;  // why not, if not
  std::vector<ContinuationRecord> path;
  int newton_solves = 0;
  int newton_iterations = 0;      // summed over all solves
  std::vector<GridRecord> grids;  // one per visited grid (coarse to fine; the plain path: one)
  double total_seconds = 0.0;
  NewtonSummary last_newton;  // of the final accepted (or last attempted) solve
  // Parameters of the last accepted solution (y belongs to this problem).
  double path_fraction = 0.0;
  double stiffness_scale = 0.0;
  double gamma = 0.0;
  ContinuationOptions options;  // the settings used

  bool ok() const { return IsSuccess(termination); }
  std::string BriefReport() const;
  // SummaryJson + newton_solves, newton_iterations, grids, reached {path_fraction,
  // stiffness_scale, gamma}, continuation_path, last_newton (its ToJson without settings) and
  // settings.
  nlohmann::json ToJson() const;
};

// The problem at continuation parameters (p, s, γ).
TrackingProblem ContinuationProblem(const ProblemFamily& family, double path_fraction,
                                    double stiffness_scale, double gamma);

// Guess of the state trajectory from the reference (n_z × (N+1)); a node without data (weight 0)
// keeps its initial state.
Eigen::MatrixXd ReferenceGuess(const PontryaginDiscretization& disc);

// Solves family(1) with N steps. If `warm` is non-null and has the right size, the first solve
// starts from it (at the start parameters, on the requested grid: no coarse-to-fine); otherwise
// from the fixed-point sweep on the reference guess. On return y holds the last accepted
// solution on the requested grid (or the best iterate of the first solve when none was
// accepted).
ContinuationSummary SolveWithContinuation(const ProblemFamily& family, int steps,
                                          const ContinuationOptions& options, Eigen::VectorXd& y,
                                          const Eigen::VectorXd* warm = nullptr);

// The grids the solve visits for N steps after the stages before γ: {N} for the plain path, else
// N_0 < N_1 < … < N (the γ stages run on N_0).
std::vector<int> ContinuationGrids(int steps, const ContinuationOptions& options, bool warm);

// The grids below N_0 on which the stages before γ run (the first) and which they are prolonged
// through at the start γ: N_0 / f^k … N_0 / f (rounded up as the grids above), the first <=
// start_steps; empty when start_steps = 0, coarse_steps = 0, warm or gamma_start <= gamma_target.
std::vector<int> StartGrids(int steps, const ContinuationOptions& options, double gamma_target,
                            bool warm);

// Interpolates a solution y on N_from steps to N_to steps (linear in time for z and ρ).
Eigen::VectorXd InterpolateSolution(const PontryaginDiscretization& from, const Eigen::VectorXd& y,
                                    const PontryaginDiscretization& to);

}  // namespace moreau::control
