// Theorem 5.1 bounds: closed-form cases of the theorem and their behaviour in Δt.
#include "moreau/control/value_error_bounds.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "moreau/common/error.h"

namespace moreau::control {
namespace {

TEST(ValueErrorBounds, WithoutLipschitzGrowthOnlyTheRegularizationRemains) {
  // C2 = 0 makes e^{C2 T} = 1: every Δt term vanishes and the bounds are ∓T δ.
  const ValueErrorBounds b = Theorem51Bounds({0.7, 0.0, 3.0, 0.25}, 2.0, 0.1);
  EXPECT_DOUBLE_EQ(b.lower, -0.5);
  EXPECT_DOUBLE_EQ(b.upper, 0.5);
}

TEST(ValueErrorBounds, KnownAnswerForUnitConstants) {
  // C1 = C2 = 1, C3 = 0, δ = 0, T = 1, Δt = 1/10:
  //   lower = −½ ((e − 1)/10 + 1/100),  upper = ½ e / 10.
  const ValueErrorBounds b = Theorem51Bounds({1.0, 1.0, 0.0, 0.0}, 1.0, 0.1);
  const double e = std::exp(1.0);
  EXPECT_NEAR(b.lower, -0.5 * ((e - 1.0) / 10.0 + 0.01), 1e-15);
  EXPECT_NEAR(b.upper, 0.05 * e, 1e-15);
}

TEST(ValueErrorBounds, ShrinkToTheRegularizationErrorAsTheStepVanishes) {
  const ValueErrorConstants c{0.352, 2.00069, 0.5, 3.51772e-5};
  const double horizon = 2.0;
  double previous_width = std::numeric_limits<double>::infinity();
  for (double dt = 0.1; dt > 1e-6; dt /= 10.0) {
    const ValueErrorBounds b = Theorem51Bounds(c, horizon, dt);
    EXPECT_LT(b.lower, -horizon * c.delta);
    EXPECT_GT(b.upper, horizon * c.delta);
    const double width = b.upper - b.lower;
    EXPECT_LT(width, previous_width);
    previous_width = width;
  }
  // The upper bound is affine in Δt: equal steps in Δt add equal amounts.
  const double u1 = Theorem51Bounds(c, horizon, 0.01).upper;
  const double u2 = Theorem51Bounds(c, horizon, 0.02).upper;
  const double u3 = Theorem51Bounds(c, horizon, 0.03).upper;
  EXPECT_NEAR(u3 - u2, u2 - u1, 1e-12 * std::abs(u3));
  EXPECT_NEAR(Theorem51Bounds(c, horizon, 1e-12).upper, horizon * c.delta, 1e-9);
}

TEST(ValueErrorBounds, NegativeConstantIsAnInputErrorNamingIt) {
  try {
    Theorem51Bounds({1.0, -1.0, 0.0, 0.0}, 1.0, 0.1);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("study.theorem.c2"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace moreau::control
