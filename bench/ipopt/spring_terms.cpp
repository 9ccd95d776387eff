#include "spring_terms.h"

#include <cmath>

namespace moreau::bench {

bool ControlEntropy(double rest, double rest_min, double rest_max, EntropyPenalty& out) {
  const double range = rest_max - rest_min;
  const double theta = (rest - rest_min) / range;
  if (!(theta > 0.0 && theta < 1.0)) return false;
  out.value =
      0.5 * range * (theta * std::log(theta) + (1.0 - theta) * std::log1p(-theta) + std::log(2.0));
  out.slope = 0.5 * (std::log(theta) - std::log1p(-theta));
  out.curvature = 1.0 / (2.0 * range * theta * (1.0 - theta));
  return true;
}

}  // namespace moreau::bench
