// The prediction against the drift formulas of forces.h, its noise, and the projection sweep on
// a configuration with a known answer.
#include "particles/prediction.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "particles/sweep.h"

namespace moreau::particles::internal {
namespace {

// One particle per case, far from everything; Y against u = μ F + v_prop by hand.
TEST(ParticlePrediction, DriftMatchesTheFormulas) {
  ParticleModel m;
  m.dimension = 2;
  m.radius = {0.5, 0.5, 0.5};
  Forces f;
  f.trap = HarmonicTrap{2.0, {1.0, -1.0, 0.0}};
  f.constant_force = {0.25, -0.5, 0.0};
  SelfPropulsion walk;
  walk.speed = 1.5;
  walk.target = {10.0, 0.0, 0.0};
  walk.target_end = Vec3{10.0, 4.0, 0.0};
  walk.exit_direction = Vec3{3.0, 0.0, 0.0};
  f.propulsion = walk;
  const double h = 0.01;
  const Prediction prediction(f, PeriodicBox::Of(m), 3, h, 1, false);
  // Particle 0 heads for the segment's nearest point (10, 2); particle 1 for its end (10, 4);
  // particle 2 is past the door line and walks along e_0.
  const double x[6] = {4.0, 2.0, 7.0, 8.0, 11.0, 1.0};
  const int id[3] = {0, 1, 2};
  const double mobility[3] = {1.0, 0.5, 2.0};
  double y[6];
  double max_move = 0.0;
  std::int64_t bad = 0;
  prediction.Predict(x, y, id, nullptr, nullptr, mobility, 0, 1, &max_move, &bad);
  EXPECT_EQ(bad, -1);
  const double towards[3][2] = {{1.0, 0.0}, {3.0 / 5.0, -4.0 / 5.0}, {1.0, 0.0}};
  double worst = 0.0;
  for (int i = 0; i < 3; ++i) {
    double d2 = 0.0;
    for (int a = 0; a < 2; ++a) {
      const double F = -2.0 * (x[2 * i + a] - (a == 0 ? 1.0 : -1.0)) + (a == 0 ? 0.25 : -0.5);
      const double u = mobility[i] * F + 1.5 * towards[i][a];
      EXPECT_NEAR(y[2 * i + a], x[2 * i + a] + h * u, 1e-14) << i << " " << a;
      d2 += (y[2 * i + a] - x[2 * i + a]) * (y[2 * i + a] - x[2 * i + a]);
    }
    worst = std::max(worst, std::sqrt(d2));
  }
  EXPECT_NEAR(max_move, worst, 1e-15);
}

// With noise only: Y − X = √(2Dh) ξ(seed, id, step) exactly, whatever the slot; a non-finite
// position is reported by the smallest id.
TEST(ParticlePrediction, NoiseIsKeyedByIdAndStep) {
  ParticleModel m;
  m.dimension = 3;
  m.radius = {0.5, 0.5};
  Forces f;
  f.diffusion = 0.3;
  const double h = 0.02;
  const Prediction prediction(f, PeriodicBox::Of(m), 2, h, 99, true);
  const double x[6] = {0, 0, 0, 5, 5, 5};
  const int id[2] = {7, 3};  // slots hold ids 7 and 3
  double y[6];
  double max_move = 0.0;
  std::int64_t bad = 0;
  prediction.Predict(x, y, id, nullptr, nullptr, nullptr, 12, 1, &max_move, &bad);
  const double sigma = std::sqrt(2.0 * 0.3 * h);
  for (int s = 0; s < 2; ++s) {
    double xi[3];
    GaussianNoise(99, id[s], 12, 3, xi);
    for (int a = 0; a < 3; ++a) EXPECT_EQ(y[3 * s + a], x[3 * s + a] + sigma * xi[a]);
  }
  const double nan_x[6] = {0, 0, 0, std::numeric_limits<double>::quiet_NaN(), 5, 5};
  prediction.Predict(nan_x, y, id, nullptr, nullptr, nullptr, 12, 1, &max_move, &bad);
  EXPECT_EQ(bad, 3);
}

// Two overlapping disks on a wall: one sweep separates the pair exactly (each moves half the
// overlap) and pushes the lower one out of the wall; the longest path is the sum of its moves.
TEST(ParticleSweep, PairThenWallWithPathBound) {
  ParticleModel m;
  m.dimension = 2;
  m.radius = {1.0, 1.0};
  m.walls.push_back(Wall{{0.0, 1.0, 0.0}, 0.0});  // y ≥ r
  ProjectionSweep sweep(m, true);
  const PeriodicBox box = PeriodicBox::Of(m);
  double x[4] = {0.0, 0.5, 0.0, 2.0};  // distance 1.5, overlap 0.5; particle 0 is 0.5 deep
  CellList cells;
  cells.Fit(x, 2, box, 3.0, 0, 1);
  const int id[2] = {0, 1};
  cells.Sort(x, id, 2, 1);
  NeighbourList list;
  list.Configure(box, 2, 1.0, 1e300, 0.0);
  list.Build(x, m.radius.data(), cells, cells.permutation().data(), true, false, 0, 1);
  ASSERT_EQ(list.pairs(), 1);
  Colouring colouring;
  colouring.Assign(cells);
  std::int64_t projections = 0;
  const double path =
      sweep.Sweep(x, m.radius.data(), list, colouring, cells, true, 1, &projections);
  EXPECT_NEAR(x[1], 1.0, 1e-15);  // 0.25 down by the pair, then 0.75 up by the wall
  EXPECT_NEAR(x[3], 2.25, 1e-15);
  EXPECT_EQ(x[0], 0.0);
  EXPECT_EQ(x[2], 0.0);
  EXPECT_EQ(projections, 2);
  EXPECT_NEAR(path, 1.0, 1e-15);
  EXPECT_EQ(sweep.MaxFixedViolation(x, m.radius.data()), 0.0);
}

}  // namespace
}  // namespace moreau::particles::internal
