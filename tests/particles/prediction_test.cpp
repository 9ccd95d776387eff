// The prediction against the drift formulas of forces.h, its noise, and the projection sweep on
// a configuration with a known answer.
#include "particles/prediction.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "moreau/common/random.h"

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

// The plain prediction (trap and noise only: a vectorised loop) gives the general loop's bits:
// positions, largest move and coordinate, the smallest bad id, and the fused exact skin bound
// (against a direct count). The general loop is taken by passing a zero active velocity (the
// positions are random, so no drift component is −0, where adding +0 would flip the sign bit).
TEST(ParticlePrediction, PlainLoopMatchesTheGeneralLoopBitForBit) {
  for (const int k : {2, 3}) {
    for (const bool trap : {false, true}) {
      for (const bool noise : {false, true}) {
        const int n = 1000;  // several noise batches, the last one partial
        ParticleModel m;
        m.dimension = k;
        m.radius.assign(n, 0.5);
        Forces f;
        if (trap) f.trap = HarmonicTrap{0.7, {1.0, -2.0, 0.5}};
        f.diffusion = noise ? 0.3 : 0.0;
        const Prediction prediction(f, PeriodicBox::Of(m), n, 0.01, 5, true);
        SplitMix64 rng(k * 4 + trap * 2 + noise);
        std::vector<double> x(static_cast<std::size_t>(k * n)), ref(x.size());
        for (double& v : x) v = 40.0 * rng.Uniform01() - 20.0;
        for (std::size_t i = 0; i < x.size(); ++i) ref[i] = x[i] + 0.2 * rng.Uniform01() - 0.1;
        std::vector<int> id(static_cast<std::size_t>(n));
        for (int s = 0; s < n; ++s) id[static_cast<std::size_t>(s)] = (7 * s + 3) % n;
        const std::vector<double> zero(x.size(), 0.0);
        for (const bool poisoned : {false, true}) {
          if (poisoned) {  // two non-finite rows in different batches
            x[static_cast<std::size_t>(k * 300 + 1)] = std::numeric_limits<double>::infinity();
            x[static_cast<std::size_t>(k * 700)] = std::numeric_limits<double>::quiet_NaN();
          }
          std::vector<double> y_plain(x.size()), y_general(x.size());
          double move_plain = 0, move_general = 0, far_plain = 0, far_general = 0;
          std::int64_t bad_plain = 0, bad_general = 0;
          ExactBound b_plain{ref.data(), 0.0025}, b_general{ref.data(), 0.0025};
          prediction.Predict(x.data(), y_plain.data(), id.data(), nullptr, nullptr, nullptr, 4, 2,
                             &move_plain, &bad_plain, &far_plain, &b_plain);
          prediction.Predict(x.data(), y_general.data(), id.data(), nullptr, zero.data(), nullptr,
                             4, 2, &move_general, &bad_general, &far_general, &b_general);
          const std::string what =
              fmt::format("k {} trap {} noise {} poisoned {}", k, trap, noise, poisoned);
          EXPECT_EQ(std::memcmp(y_plain.data(), y_general.data(), 8 * x.size()), 0) << what;
          EXPECT_EQ(move_plain, move_general) << what;
          EXPECT_EQ(far_plain, far_general) << what;
          EXPECT_EQ(bad_plain, bad_general) << what;
          EXPECT_EQ(bad_plain, poisoned ? std::min(id[300], id[700]) : -1) << what;
          if (poisoned) continue;
          double worst2 = 0.0;
          std::int64_t count = 0;
          for (int s = 0; s < n; ++s) {
            double e2 = 0.0;
            for (int a = 0; a < k; ++a) {
              const double d = y_plain[static_cast<std::size_t>(k * s + a)] -
                               ref[static_cast<std::size_t>(k * s + a)];
              e2 += d * d;
            }
            worst2 = std::max(worst2, e2);
            count += e2 > 0.0025 ? 1 : 0;
          }
          EXPECT_EQ(b_plain.worst2, worst2) << what;
          EXPECT_EQ(b_general.worst2, worst2) << what;
          EXPECT_EQ(b_plain.far, count) << what;
          EXPECT_EQ(b_general.far, count) << what;
          EXPECT_GT(count, 0) << what;
          EXPECT_LT(count, n) << what;
        }
      }
    }
  }
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
