#include "moreau/common/steps.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "moreau/common/error.h"

namespace moreau {

std::int64_t StepCount(double T, double h) {
  if (!(T > 0.0) || !std::isfinite(T)) throw InputError(fmt::format("T must be > 0 (got {})", T));
  if (!(h > 0.0) || !std::isfinite(h)) throw InputError(fmt::format("h must be > 0 (got {})", h));
  const double ratio = T / h;
  if (!(ratio <= static_cast<double>(kMaxSteps))) {
    throw InputError(
        fmt::format("T / h = {:.6g} steps is more than the {} allowed (T = {}, h = {})", ratio,
                    kMaxSteps, T, h));
  }
  const double n = std::round(ratio);
  if (n < 1.0 || std::abs(ratio - n) > 1e-9 * std::max(1.0, ratio)) {
    throw InputError(fmt::format("T / h must be a whole number (T = {}, h = {})", T, h));
  }
  return static_cast<std::int64_t>(n);
}

}  // namespace moreau
