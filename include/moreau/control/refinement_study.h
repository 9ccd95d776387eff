// Grid-refinement studies (thesis section 9): the discrete value ū_N, the residual and the
// trajectories for increasing N, with the differences between grids that show convergence.
#pragma once

#include <Eigen/Core>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "moreau/common/termination.h"
#include "moreau/control/continuation.h"

namespace moreau::control {

// One level of a grid-refinement study.
struct RefinementLevel {
  int steps = 0;
  Termination termination = Termination::kConverged;  // of the last solve for this N
  std::string message;
  double value = 0.0;         // ū_N (31)
  double residual = 0.0;      // ‖F‖_∞
  int newton_iterations = 0;  // of the final solve (all solves for this N: newton_total)
  int newton_total = 0;
  double total_seconds = 0.0;  // solving and evaluating this N
  double diff_previous = 0.0;  // max |x_N − x_{N_prev}| on the coarser grid's nodes (NaN first)
  double diff_finest = 0.0;    // max |x_N − x_{N_max}| on `compare_samples` + 1 instants
  double tracking_rms = 0.0;   // RMS of |x_j(t_n) − X_j(t_n)| over data points
  Eigen::MatrixXd z;           // n_z × (N+1)
  Eigen::MatrixXd controls;    // num_springs × N effective rest lengths

  bool ok() const { return IsSuccess(termination); }
  // SummaryJson + steps, value, residual_norm, newton_iterations, newton_total, diff_previous,
  // diff_finest, tracking_rms (not z and controls).
  nlohmann::json ToJson() const;
};

struct RefinementStudyOptions {
  std::vector<int> steps;  // increasing N
  ContinuationOptions continuation;
  bool warm_start = false;  // first try Newton from the interpolated coarser solution; on
                            // failure (or when false) solve by continuation from the start
  int compare_samples = 0;  // instants for diff_finest (0: the coarsest grid's nodes)
  std::function<void(const RefinementLevel&)> on_level;  // called after each N (may be empty)
  // Throws InputError("study.<field>: ...").
  void Validate() const;
  nlohmann::json ToJson() const;  // {"steps", "warm_start", "compare_samples", "continuation"}
};

struct RefinementStudySummary {
  // kConverged when every level converged, else the termination of the first level that did not.
  Termination termination = Termination::kConverged;
  std::string message;                  // which N failed and why
  std::vector<RefinementLevel> levels;  // in increasing N
  double total_seconds = 0.0;
  RefinementStudyOptions options;  // the settings used (without on_level)

  bool ok() const { return IsSuccess(termination); }
  // SummaryJson + steps (the N of every level), levels and settings.
  nlohmann::json ToJson() const;
};

// Solves every N (the first with continuation; the next from the interpolated coarser solution,
// falling back to continuation if Newton fails) and fills the comparison columns.
RefinementStudySummary RunRefinementStudy(const ProblemFamily& family,
                                          const RefinementStudyOptions& options);

// Max-norm of the position difference between two state trajectories of the same problem on
// S + 1 equally spaced instants (linear interpolation between grid nodes).
double MaxPositionDifference(const TrackingProblem& problem, const Eigen::MatrixXd& z_a,
                             const Eigen::MatrixXd& z_b, int samples);

// RMS of the position tracking error over (node, time-step) pairs with positive weight.
double TrackingRms(const PontryaginDiscretization& disc, const Eigen::MatrixXd& z);

}  // namespace moreau::control
