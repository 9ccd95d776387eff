// Internal to the optimal-control gap fill: one window (a group of gaps, their free markers and
// the anchors around them) turned into a control::TrackingProblem and solved.
#pragma once

#include <Eigen/Core>
#include <memory>
#include <string>
#include <vector>

#include "moreau/common/termination.h"
#include "moreau/control/continuation.h"
#include "moreau/mocap/ocp_fill.h"

namespace moreau::mocap::internal {

struct OcpWindow {
  std::int64_t first = 0;  // window frames, inclusive
  std::int64_t last = 0;
  std::vector<int> free;  // hidden markers (free nodes), in node order
};

struct OcpWindowResult {
  Eigen::MatrixXd positions;  // frames × 3 M: the free markers' solved positions (recording units)
  Termination termination = Termination::kDiverged;
  std::string message;
  int steps = 0;
  int anchors = 0;
  int springs = 0;
  int newton_iterations = 0;
  double residual = 0.0;
};

struct OcpWindowModel;  // the window's network and the free markers' prior tracks (ocp_window.cpp)

// A window's problem exactly as the fill solves it (solver units: lengths in `scale` about
// `origin`, time in frames).
struct OcpWindowProblem {
  std::shared_ptr<const OcpWindowModel> model;
  std::unique_ptr<control::TrackingProblem> target;  // at the target γ (options.gamma)
  int substeps = 1;                                  // steps per frame
  int steps = 0;                                     // N = (frames − 1) × substeps
  int anchors = 0;
  int springs = 0;
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();  // recording units
  double scale = 1.0;                                // network.length_scale
  control::ContinuationOptions continuation;         // the first solve's continuation
  Eigen::VectorXd warm_start;  // its start: the prior trajectory and one backward sweep
};

// Builds the window's problem into `p`, field by field (anchors and springs, then steps, then
// the warm start), as SolveOcpWindow does. edge_as_observed: the hidden frames that no
// observation of their marker follows (or precedes) in the window, at an edge of the take,
// track the prior with min(prior_weight, observed_weight) (SolveOcpWindow's last attempt).
// Throws InputError for a degenerate window (e.g. an anchor on top of a free marker); the fields
// set before the throw stay set.
void MakeOcpWindowProblem(const Recording& in, const Recording& base, const MarkerNetwork& network,
                          const OcpWindow& window, const OcpFillOptions& options,
                          OcpWindowProblem& p, bool edge_as_observed = false);

// The fill's solve of `p`: continuation from p.warm_start with p.continuation; on failure, again
// from a smooth problem (options.stiffness_start, options.retry_gamma_start). `y`: the solution
// (PontryaginDiscretization(*p.target, p.steps)); `newton_iterations`: of both attempts.
control::ContinuationSummary SolveOcpWindowProblem(const OcpWindowProblem& p,
                                                   const OcpFillOptions& options,
                                                   Eigen::VectorXd& y, int& newton_iterations);

// `in`: the recording (its observed mask gives the weights); `base`: `in` with every gap to fill
// set to its prior (anchors follow `base`, free nodes track it). Attempts, until one converges:
// SolveOcpWindowProblem; again with each free marker's retry_anchor_springs most rigid springs
// to anchors (unless 0 or anchor_springs is already at most that; the message of a failure then
// holds "with N anchor springs per marker"); if a free marker is hidden at the window's first or
// last frame (a gap at an edge of the take) and prior_weight > observed_weight, the options'
// network with the edge's prior weighted like the observations (edge_as_observed).
// newton_iterations: of all attempts. Never throws for a numerical failure: the result's
// termination says what happened.
OcpWindowResult SolveOcpWindow(const Recording& in, const Recording& base,
                               const MarkerNetwork& network, const OcpWindow& window,
                               const OcpFillOptions& options);

}  // namespace moreau::mocap::internal
