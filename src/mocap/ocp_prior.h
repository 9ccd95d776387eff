// Internal to the optimal-control gap fill: a candidate fill's agreement with the network's
// distance distributions (Tits et al. 2018), from which the prior's weights and the guard come.
#pragma once

#include <Eigen/Core>

#include "moreau/mocap/network_from_recording.h"
#include "moreau/mocap/recording.h"

namespace moreau::mocap::internal {

// gap.length() × 3 positions.
using GapTrack = Eigen::Matrix<double, Eigen::Dynamic, 3>;

// Mean squared z-score of the distances from the filled marker to its spring partners observed at
// the same frames, (d − mean) / max(spread, margin) with margin = L+ − d_max of the spring, over
// the gap. 0 when no partner is seen.
double DistanceDisagreement(const Recording& in, const MarkerNetwork& network, const Gap& gap,
                            const GapTrack& fill);

}  // namespace moreau::mocap::internal
