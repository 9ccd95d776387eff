// Every built-in projection returns a point of its set, is idempotent, and agrees with a
// brute-force minimiser of the distance in low dimension.
#include "moreau/pbd/constraint_set.h"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <random>
#include <vector>

#include "moreau/common/error.h"

namespace moreau::pbd {
namespace {

constexpr double kFeasTol = 1e-12;

struct NamedSet {
  std::string name;
  std::shared_ptr<ConstraintSet> set;
};

std::vector<NamedSet> LowDimensionalSets() {
  return {
      {"ball_interior", std::make_shared<BallInterior>(Eigen::Vector2d(0.3, -0.2), 0.7)},
      {"ball_exterior", std::make_shared<BallExterior>(Eigen::Vector2d(0.3, -0.2), 0.7)},
      {"half_space", std::make_shared<HalfSpace>(Eigen::Vector2d(1.0, 2.0), 0.4)},
      // Two particles on a line (k = 1): {|X_0 − X_1| ≥ 0.5}.
      {"pair_1d", std::make_shared<PairNonOverlap>(2, 1, 0, 1, 0.5)},
      // g(x) = ‖x − c‖ − R is a signed distance, so one Gauss–Newton step is exact.
      {"function_distance",
       std::make_shared<FunctionSet>(
           2, [](ConstVectorRef x) { return (x - Eigen::Vector2d(0.1, 0.2)).norm() - 0.6; },
           [](ConstVectorRef x, VectorRef g) {
             g = (x - Eigen::Vector2d(0.1, 0.2)) / (x - Eigen::Vector2d(0.1, 0.2)).norm();
           })},
  };
}

// Brute force: the nearest point of a fine grid over [−2, 2]² that lies in the set.
Eigen::Vector2d GridMinimiser(const ConstraintSet& set, const Eigen::Vector2d& x, double* dist) {
  constexpr int kN = 1601;
  double best = std::numeric_limits<double>::infinity();
  Eigen::Vector2d arg = x;
  for (int i = 0; i < kN; ++i) {
    for (int j = 0; j < kN; ++j) {
      const Eigen::Vector2d p(-2.0 + 4.0 * i / (kN - 1), -2.0 + 4.0 * j / (kN - 1));
      if (set.Value(p) < 0.0) continue;
      const double d = (p - x).norm();
      if (d < best) {
        best = d;
        arg = p;
      }
    }
  }
  *dist = best;
  return arg;
}

TEST(ConstraintSet, ProjectionIsFeasibleAndIdempotent) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1.5, 1.5);
  for (const NamedSet& ns : LowDimensionalSets()) {
    for (int trial = 0; trial < 200; ++trial) {
      Vector x(2);
      x << u(rng), u(rng);
      Vector p = x;
      ns.set->Project(p);
      EXPECT_GE(ns.set->Value(p), -kFeasTol) << ns.name;
      Vector q = p;
      const bool moved = ns.set->Project(q);
      EXPECT_LE((q - p).norm(), 1e-14) << ns.name << " is not idempotent";
      if (ns.set->Value(p) > 1e-12) {
        EXPECT_FALSE(moved) << ns.name;
      }
      // Points of the set are fixed points.
      if (ns.set->Value(x) >= 0.0) {
        EXPECT_EQ((p - x).norm(), 0.0) << ns.name;
      }
      EXPECT_NEAR(ns.set->Distance(x), (p - x).norm(), 1e-14) << ns.name;
    }
  }
}

TEST(ConstraintSet, ProjectionAgreesWithBruteForceMinimiser) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1.2, 1.2);
  const double grid_step = 4.0 / 1600.0;
  for (const NamedSet& ns : LowDimensionalSets()) {
    int outside = 0;
    for (int trial = 0; trial < 12; ++trial) {
      Eigen::Vector2d x(u(rng), u(rng));
      if (ns.set->Value(x) >= 0.0) continue;
      ++outside;
      Vector p = x;
      ns.set->Project(p);
      double brute = 0.0;
      const Eigen::Vector2d arg = GridMinimiser(*ns.set, x, &brute);
      // The projection is at least as close as every feasible grid point, and some feasible
      // grid point is within one grid diagonal of being as close.
      EXPECT_LE((p - x).norm(), brute + 1e-12) << ns.name;
      EXPECT_GE((p - x).norm(), brute - std::sqrt(2.0) * grid_step) << ns.name;
      EXPECT_GE(ns.set->Value(arg), 0.0);
    }
    EXPECT_GT(outside, 0) << ns.name << ": no trial point outside the set";
  }
}

TEST(ConstraintSet, PairProjectionIsOrthogonalInFourDimensions) {
  // Two disks in the plane: no feasible random point near x is closer than the projection, and
  // the projection moves both centres by half of the overlap.
  const PairNonOverlap pair(4, 2, 0, 1, 1.0);
  std::mt19937_64 rng(3);
  std::normal_distribution<double> n(0.0, 0.6);
  Vector x(4);
  x << 0.1, 0.2, 0.5, 0.4;
  Vector p = x;
  ASSERT_TRUE(pair.Project(p));
  EXPECT_NEAR(pair.Value(p), 0.0, 1e-14);
  EXPECT_NEAR((p.head<2>() - x.head<2>()).norm(), (p.tail<2>() - x.tail<2>()).norm(), 1e-14);
  const double dp = (p - x).norm();
  EXPECT_NEAR(dp, pair.Distance(x), 1e-14);
  for (int s = 0; s < 200000; ++s) {
    Vector q = x;
    for (int c = 0; c < 4; ++c) q[c] += n(rng);
    if (pair.Value(q) >= 0.0) {
      ASSERT_GE((q - x).norm(), dp - 1e-12);
    }
  }
}

TEST(ConstraintSet, GaussNewtonStepForNonDistanceFunction) {
  // g(x) = ‖x‖² − 1 is not a distance: one Gauss–Newton step x − g ∇g/‖∇g‖² from x = (0.3, 0.4)
  // lands at x + 0.75 · 2x / ‖2x‖² = 2.5 x: feasible, along the normal, but not the projection
  // x/‖x‖ (the price of not knowing the exact projection).
  const FunctionSet set(
      2, [](ConstVectorRef x) { return x.squaredNorm() - 1.0; },
      [](ConstVectorRef x, VectorRef g) { g = 2.0 * x; });
  Vector x(2);
  x << 0.3, 0.4;
  const Vector start = x;
  ASSERT_TRUE(set.Project(x));
  EXPECT_NEAR((x - 2.5 * start).norm(), 0.0, 1e-15);
  EXPECT_GE(set.Value(x), 0.0);
  EXPECT_FALSE(set.Project(x));
}

TEST(ConstraintSet, DegenerateCentresAreDeterministic) {
  const BallExterior ball(Eigen::Vector2d(1.0, 1.0), 0.5);
  Vector x = Eigen::Vector2d(1.0, 1.0);
  ball.Project(x);
  EXPECT_EQ(x, Vector(Eigen::Vector2d(1.5, 1.0)));
  const PairNonOverlap pair(4, 2, 0, 1, 1.0);
  Vector y(4);
  y << 0.0, 0.0, 0.0, 0.0;
  pair.Project(y);
  EXPECT_NEAR(pair.Value(y), 0.0, 1e-15);
}

TEST(ConstraintSet, InvalidParametersAreInputErrors) {
  EXPECT_THROW(BallInterior(Eigen::Vector2d::Zero(), 0.0), InputError);
  EXPECT_THROW(BallExterior(Eigen::Vector2d::Zero(), -1.0), InputError);
  EXPECT_THROW(HalfSpace(Eigen::Vector2d::Zero(), 1.0), InputError);
  EXPECT_THROW(PairNonOverlap(4, 2, 1, 1, 1.0), InputError);
  EXPECT_THROW(PairNonOverlap(4, 2, 0, 2, 1.0), InputError);
}

}  // namespace
}  // namespace moreau::pbd
