#include "mocap/ocp_prior.h"

#include <algorithm>
#include <cmath>

namespace moreau::mocap::internal {
double DistanceDisagreement(const Recording& in, const MarkerNetwork& net, const Gap& gap,
                            const GapTrack& fill) {
  double sum = 0.0;
  long count = 0;
  for (std::int64_t f = gap.first; f <= gap.last; ++f) {
    const Eigen::Vector3d x = fill.row(f - gap.first).transpose();
    for (int s : net.springs_of[static_cast<std::size_t>(gap.marker)]) {
      const int k = net.Partner(s, gap.marker);
      if (!in.observed(f, k)) continue;
      const MarkerSpring& sp = net.springs[static_cast<std::size_t>(s)];
      // Scale: the spread, at least the margin of the spring's rest-length bounds.
      const double scale = std::max(sp.spread, sp.rest_max - sp.max);
      const double z = ((x - in.point(f, k)).norm() - sp.mean) / std::max(scale, 1e-12);
      sum += z * z;
      ++count;
    }
  }
  return count > 0 ? sum / static_cast<double>(count) : 0.0;
}

}  // namespace moreau::mocap::internal
