// Every projection of the engine lands in its set, is idempotent, leaves points of the set alone
// and is the nearest point of the set (checked against a brute-force search in the plane).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>

#include "moreau/common/random.h"
#include "moreau/pbd/cases.h"
#include "particles/kernels.h"

namespace moreau::particles::internal {
namespace {

constexpr double kTol = 1e-12;

// min over a fine polar grid of sample points y with g(y) ≥ 0 of ‖y − x‖ (plane only).
template <typename G>
double BruteForceDistance(const double* x, G&& g) {
  double best = std::numeric_limits<double>::infinity();
  for (int i = 0; i < 2000; ++i) {
    const double angle = 2.0 * std::numbers::pi * i / 2000;
    for (int j = 1; j <= 400; ++j) {
      const double rho = 3.0 * j / 400;
      const double y[2] = {x[0] + rho * std::cos(angle), x[1] + rho * std::sin(angle)};
      if (g(y) >= 0.0) {
        best = std::min(best, rho);
        break;
      }
    }
  }
  return best;
}

TEST(ParticleProjections, SphereExterior) {
  SplitMix64 rng(1);
  for (int k : {2, 3}) {
    for (int trial = 0; trial < 200; ++trial) {
      double c[3], x[3], x0[3];
      for (int a = 0; a < 3; ++a) {
        c[a] = rng.Uniform01();
        x[a] = x0[a] = c[a] + 2.0 * rng.Uniform01() - 1.0;
      }
      const double R = 0.3 + 0.5 * rng.Uniform01();
      auto gap = [&](const double* y) {
        double r2 = 0.0;
        for (int a = 0; a < k; ++a) r2 += (y[a] - c[a]) * (y[a] - c[a]);
        return std::sqrt(r2) - R;
      };
      const double before = gap(x);
      const double moved =
          k == 2 ? ProjectSphereExterior<2>(x, c, R) : ProjectSphereExterior<3>(x, c, R);
      EXPECT_GE(gap(x), -kTol);
      if (before >= 0.0) {
        EXPECT_EQ(moved, 0.0);
        for (int a = 0; a < k; ++a) EXPECT_EQ(x[a], x0[a]);
      } else {
        EXPECT_NEAR(moved, -before, kTol);
        double d2 = 0.0;
        for (int a = 0; a < k; ++a) d2 += (x[a] - x0[a]) * (x[a] - x0[a]);
        EXPECT_NEAR(std::sqrt(d2), -before, kTol);  // the distance to the set
      }
      double again[3] = {x[0], x[1], x[2]};
      if (k == 2)
        ProjectSphereExterior<2>(again, c, R);
      else
        ProjectSphereExterior<3>(again, c, R);
      for (int a = 0; a < k; ++a) EXPECT_NEAR(again[a], x[a], kTol);
    }
  }
  double centre[2] = {1.0, 2.0}, x[2] = {1.0, 2.0};  // the centre itself: a fixed choice
  ProjectSphereExterior<2>(x, centre, 0.5);
  EXPECT_EQ(x[0], 1.5);
  EXPECT_EQ(x[1], 2.0);
}

TEST(ParticleProjections, SegmentExteriorIsTheNearestPoint) {
  SplitMix64 rng(2);
  for (int trial = 0; trial < 60; ++trial) {
    const double a[2] = {rng.Uniform01(), rng.Uniform01()};
    const double b[2] = {a[0] + 2.0 * rng.Uniform01() - 1.0, a[1] + 2.0 * rng.Uniform01() - 1.0};
    const double R = 0.2 + 0.3 * rng.Uniform01();
    double x[2] = {a[0] + 2.0 * rng.Uniform01() - 1.0, a[1] + 2.0 * rng.Uniform01() - 1.0};
    const double x0[2] = {x[0], x[1]};
    auto gap = [&](const double* y) { return SegmentGap(y, a, b, R); };
    const double before = gap(x);
    const double moved = ProjectSegmentExterior(x, a, b, R);
    EXPECT_GE(gap(x), -kTol);
    const double dist = std::hypot(x[0] - x0[0], x[1] - x0[1]);
    EXPECT_NEAR(dist, moved, kTol);
    if (before >= 0.0) {
      EXPECT_EQ(dist, 0.0);
    } else {
      // Grid resolution of the brute-force search: 3/400 radially, 2π/2000 in angle.
      EXPECT_NEAR(dist, BruteForceDistance(x0, gap), 0.01);
      EXPECT_LE(dist, BruteForceDistance(x0, gap) + kTol);
    }
    double again[2] = {x[0], x[1]};
    ProjectSegmentExterior(again, a, b, R);
    EXPECT_NEAR(again[0], x[0], kTol);
    EXPECT_NEAR(again[1], x[1], kTol);
  }
  // A point on the segment goes along the left normal of b − a.
  const double a[2] = {0, 0}, b[2] = {2, 0};
  double x[2] = {0.5, 0.0};
  ProjectSegmentExterior(x, a, b, 0.25);
  EXPECT_DOUBLE_EQ(x[0], 0.5);
  EXPECT_DOUBLE_EQ(x[1], 0.25);
}

TEST(ParticleProjections, Wall) {
  SplitMix64 rng(3);
  for (int trial = 0; trial < 200; ++trial) {
    double n[3] = {rng.Uniform01() - 0.5, rng.Uniform01() - 0.5, rng.Uniform01() - 0.5};
    const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    for (double& v : n) v /= len;
    const double bound = rng.Uniform01() - 0.5;
    double x[3] = {rng.Uniform01() - 0.5, rng.Uniform01() - 0.5, rng.Uniform01() - 0.5};
    const double x0[3] = {x[0], x[1], x[2]};
    auto g = [&](const double* y) { return n[0] * y[0] + n[1] * y[1] + n[2] * y[2] - bound; };
    const double before = g(x);
    ProjectWall<3>(x, n, bound);
    EXPECT_GE(g(x), -kTol);
    const double dist =
        std::sqrt((x[0] - x0[0]) * (x[0] - x0[0]) + (x[1] - x0[1]) * (x[1] - x0[1]) +
                  (x[2] - x0[2]) * (x[2] - x0[2]));
    EXPECT_NEAR(dist, std::max(0.0, -before), kTol);
    double again[3] = {x[0], x[1], x[2]};
    ProjectWall<3>(again, n, bound);
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(again[a], x[a], kTol);
  }
}

TEST(ParticleProjections, PeriodicPairUsesTheMinimumImage) {
  // Two disks across the boundary of a periodic axis of length L = 10: the projection acts on the
  // minimum-image displacement, separates them to contact, and a second application is the
  // identity.
  SplitMix64 rng(4);
  const double L = 10.0;
  for (int trial = 0; trial < 200; ++trial) {
    double xi[2] = {0.3 * rng.Uniform01(), 5.0 + rng.Uniform01() - 0.5};
    double xj[2] = {L - 0.3 * rng.Uniform01(), 5.0 + rng.Uniform01() - 0.5};
    const double c = 0.4 + 0.4 * rng.Uniform01();
    auto displacement = [&](double* u) {
      u[0] = MinimumImage(xi[0] - xj[0], L);
      u[1] = xi[1] - xj[1];
    };
    double u[2];
    displacement(u);
    const double before = std::hypot(u[0], u[1]);
    const double xi0[2] = {xi[0], xi[1]};
    const double xj0[2] = {xj[0], xj[1]};
    ProjectPair<2>(xi, xj, u, c);
    displacement(u);
    EXPECT_GE(std::hypot(u[0], u[1]), c - kTol);
    // Each particle moved by half the overlap (or not at all).
    const double half = 0.5 * std::max(0.0, c - before);
    EXPECT_NEAR(std::hypot(xi[0] - xi0[0], xi[1] - xi0[1]), half, kTol);
    EXPECT_NEAR(std::hypot(xj[0] - xj0[0], xj[1] - xj0[1]), half, kTol);
    const double xi1[2] = {xi[0], xi[1]};
    displacement(u);
    ProjectPair<2>(xi, xj, u, c);
    EXPECT_NEAR(xi[0], xi1[0], kTol);
    EXPECT_NEAR(xi[1], xi1[1], kTol);
  }
}

TEST(ParticleProjections, WrapLandsInTheDomain) {
  for (const double v : {-25.0, -10.0, -1e-300, -0.0, 0.0, 3.0, 9.999999999999998, 10.0, 31.5}) {
    const double w = Wrap(v, 0.0, 10.0);
    EXPECT_GE(w, 0.0) << v;
    EXPECT_LT(w, 10.0) << v;
    EXPECT_NEAR(std::remainder(w - v, 10.0), 0.0, 1e-12) << v;
  }
}

}  // namespace
}  // namespace moreau::particles::internal
