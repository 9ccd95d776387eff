// Internal to the optimal-control gap fill: one window (a group of gaps, their free markers and
// the anchors around them) turned into a control::TrackingProblem and solved.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "moreau/common/termination.h"
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

// `in`: the recording (its observed mask gives the weights); `base`: `in` with every gap to fill
// set to its prior (anchors follow `base`, free nodes track it). Never throws for a numerical
// failure: the result's termination says what happened.
OcpWindowResult SolveOcpWindow(const Recording& in, const Recording& base,
                               const MarkerNetwork& network, const OcpWindow& window,
                               const OcpFillOptions& options);

}  // namespace moreau::mocap::internal
