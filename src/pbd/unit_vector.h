// Internal: the unit vector along a line of centres.
#pragma once

#include <Eigen/Core>

namespace moreau::pbd::internal {

// u ← u / ‖u‖ and returns ‖u‖; when u = 0 (coincident centres) u becomes e_1, so such pairs are
// separated along a fixed axis and results stay deterministic.
inline double NormalizeOrFirstAxis(Eigen::Ref<Eigen::VectorXd> u) {
  const double r = u.norm();
  if (r > 0.0) {
    u /= r;
  } else {
    u.setZero();
    u[0] = 1.0;
  }
  return r;
}

}  // namespace moreau::pbd::internal
