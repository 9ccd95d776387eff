// `moreau control`: one optimal-control solve by continuation, or a grid-refinement study.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "control/control_scenario.h"
#include "moreau/control/continuation.h"
#include "moreau/control/refinement_study.h"

namespace moreau::cli {

struct ControlRunResult {
  control::ContinuationSummary continuation;
  double value = 0.0;          // ū_N of the solution on the target problem
  double residual_norm = 0.0;  // ‖F‖_∞ on the target problem (the last accepted problem may differ)
  double tracking_rms = 0.0;
  double delta = 0.0;  // δ of the target problem
  double dt = 0.0;
  Eigen::MatrixXd z;         // n_z × (N+1)
  Eigen::MatrixXd controls;  // num_springs × N effective rest lengths
  double total_seconds = 0.0;
};

ControlRunResult RunControl(const ControlScenario& scenario);

// The refinement study over `steps` (increasing; InputError "--study-steps: …" otherwise), with
// a progress bar on a terminal.
control::RefinementStudySummary RunControlStudy(const ControlScenario& scenario,
                                                const std::vector<int>& steps);

}  // namespace moreau::cli
