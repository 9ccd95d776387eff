// The observed order of the scheme on smooth solutions: first in Δt, second in h (zero-flux and
// fixed faces), fitted as the slope of log(error).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "fields/test_util.h"

namespace moreau::fields {
namespace {

using testing::Fill;
using testing::GridOf;
using testing::LogSlope;
using testing::MaxError;
using testing::SubstrateWith;

// The mode cos(π x / L) cos(π y / L) on [0, L]² with zero-flux faces (or sin with faces fixed at
// 0), D k² = 1 with k² = 2 π²/L²: exactly exp(−t) times the mode at t. The error at t = T of n
// voxels per axis and `steps` steps.
double ModeError(int n, int steps, BoundaryKind kind) {
  const double length = 1.0;
  const double k = std::numbers::pi / length;
  const double d = 1.0 / (2.0 * k * k);
  const double end = 0.5;
  Substrate sub = SubstrateWith(d, 0.0, kind);
  const auto mode = [&](const double* x) {
    return kind == BoundaryKind::kFixed ? std::sin(k * x[0]) * std::sin(k * x[1])
                                        : std::cos(k * x[0]) * std::cos(k * x[1]);
  };
  FieldSet fields(GridOf(2, {n, n, 1}, length / n), {sub});
  Fill(fields, 0, mode);
  for (int i = 0; i < steps; ++i) fields.Step(end / steps);
  return MaxError(fields, 0, [&](const double* x) { return std::exp(-end) * mode(x); });
}

// Δt → Δt/2 on a fine grid (its spatial error 1e-4 of the time error's smallest).
TEST(FieldConvergence, FirstOrderInTime) {
  std::vector<double> steps, errors;
  for (int s : {8, 16, 32, 64}) {
    steps.push_back(s);
    errors.push_back(ModeError(128, s, BoundaryKind::kZeroFlux));
  }
  const double order = -LogSlope(steps, errors);
  EXPECT_NEAR(order, 1.0, 0.05) << "errors " << errors[0] << " … " << errors[3];
}

// h → h/2 with Δt ∝ h²: both errors O(h²).
TEST(FieldConvergence, SecondOrderInSpace) {
  for (BoundaryKind kind : {BoundaryKind::kZeroFlux, BoundaryKind::kFixed}) {
    std::vector<double> cells, errors;
    for (int n : {8, 16, 32, 64}) {
      cells.push_back(n);
      errors.push_back(ModeError(n, n * n / 8, kind));
    }
    const double order = -LogSlope(cells, errors);
    EXPECT_NEAR(order, 2.0, 0.05) << EnumName(kBoundaryKindNames, kind) << " errors " << errors[0]
                                  << " … " << errors[3];
  }
}

// The steady state of D c'' = λ c between faces fixed at 1 and 2 (zero flux across), c'' ≠ 0 at
// the faces: the ghost value 2 c_b − c is off by (h²/4) c'' there, and still the solution
// converges at second order.
TEST(FieldConvergence, FixedFacesSecondOrderAtSteadyState) {
  const double length = 1.0;
  const double decay_length = length / 3.0;
  std::vector<double> cells, errors;
  for (int n : {16, 32, 64, 128}) {
    Substrate sub =
        SubstrateWith(1.0, 1.0 / (decay_length * decay_length), BoundaryKind::kZeroFlux);
    sub.boundary[0] = {BoundaryKind::kFixed, 1.0};
    sub.boundary[1] = {BoundaryKind::kFixed, 2.0};
    FieldSet fields(GridOf(2, {n, 1, 1}, length / n), {sub});
    ASSERT_TRUE(fields.SolveSteadyState({1e-14, 1000}).ok());
    cells.push_back(n);
    errors.push_back(MaxError(fields, 0, [&](const double* x) {
      return (std::sinh((length - x[0]) / decay_length) + 2.0 * std::sinh(x[0] / decay_length)) /
             std::sinh(length / decay_length);
    }));
  }
  // Errors 7.7e-3, 2.1e-3, 5.3e-4, 1.35e-4: ratios 3.74, 3.87, 3.94, tending to 4.
  EXPECT_NEAR(-LogSlope(cells, errors), 2.0, 0.1);
  EXPECT_GT(errors[2] / errors[3], 3.9);
}

}  // namespace
}  // namespace moreau::fields
