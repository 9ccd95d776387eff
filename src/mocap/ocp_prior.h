// Internal to the optimal-control gap fill: the two built-in candidate fills (linear and rigid
// body) and the candidates' agreement with the network's distance distributions (Tits et al.
// 2018), from which the prior and the fallback are chosen.
#pragma once

#include <Eigen/Core>

#include "moreau/mocap/network_from_recording.h"
#include "moreau/mocap/recording.h"

namespace moreau::mocap::internal {

// gap.length() × 3 positions.
using GapTrack = Eigen::Matrix<double, Eigen::Dynamic, 3>;

// Straight line between the observed samples bounding the gap (held constant at an end of the
// recording).
GapTrack LinearGapFill(const Recording& in, const Gap& gap);

// Rigid-body fill: at each gap frame f, the marker's spring partners observed at f and at a
// reference frame (the observed frame just before, resp. after, the gap) give the rotation and
// translation (Kabsch, >= 3 partners; translation only with 1 or 2) that carries the marker from
// the reference frame to f; the two estimates are blended linearly across the gap. Frames
// without any usable partner take the linear fill.
GapTrack RigidGapFill(const Recording& in, const MarkerNetwork& network, const Gap& gap);

// Mean squared z-score of the distances from the filled marker to its spring partners observed at
// the same frames, (d − mean) / max(spread, margin) with margin = L+ − d_max of the spring, over
// the gap. 0 when no partner is seen.
double DistanceDisagreement(const Recording& in, const MarkerNetwork& network, const Gap& gap,
                            const GapTrack& fill);

}  // namespace moreau::mocap::internal
