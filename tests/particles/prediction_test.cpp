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
#include "particles/part_fixtures.h"
#include "particles/sweep.h"

namespace moreau::particles::internal {
namespace {

// *c: a context holding the store of m at x with the given active velocities (the prediction
// reads nothing else), on `threads` threads.
void StoreContext(const ParticleModel& m, const std::vector<double>& x,
                  const std::vector<double>& active, int threads, StepContext* c) {
  c->k = m.dimension;
  c->n = m.count();
  c->threads = threads;
  c->store.emplace(m, x, active);
}

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
  m.mobility = {1.0, 0.5, 2.0};
  const std::vector<double> x{4.0, 2.0, 7.0, 8.0, 11.0, 1.0};
  StepContext c;
  StoreContext(m, x, {}, 1, &c);
  const PredictionOutcome out = prediction.Predict(c, 0);
  const std::vector<double>& y = c.store->predicted;
  const std::vector<double>& mobility = m.mobility;
  EXPECT_EQ(out.bad_id, -1);
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
  EXPECT_NEAR(out.max_move, worst, 1e-15);
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
  const std::vector<double> x{0, 0, 0, 5, 5, 5};
  StepContext c;
  StoreContext(m, x, {}, 1, &c);
  c.store->id = {7, 3};  // slots hold ids 7 and 3
  prediction.Predict(c, 12);
  const double sigma = std::sqrt(2.0 * 0.3 * h);
  for (int s = 0; s < 2; ++s) {
    double xi[3];
    GaussianNoise(99, c.store->id[static_cast<std::size_t>(s)], 12, 3, xi);
    for (int a = 0; a < 3; ++a) {
      EXPECT_EQ(c.store->predicted[static_cast<std::size_t>(3 * s + a)],
                x[static_cast<std::size_t>(3 * s + a)] + sigma * xi[a]);
    }
  }
  c.store->current[3] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(prediction.Predict(c, 12).bad_id, 3);
}

// The plain prediction (trap, active velocities and noise only: a vectorised loop) gives the
// general loop's bits: positions, largest move and coordinate, the smallest bad id, and the fused
// exact skin bound (against a direct count). The general loop is taken by a prediction told that
// the mobilities differ (they are all 1, so μ F = F).
TEST(ParticlePrediction, PlainLoopMatchesTheGeneralLoopBitForBit) {
  for (const int k : {2, 3}) {
    for (const bool trap : {false, true}) {
      for (const bool noise : {false, true}) {
        for (const bool active : {false, true}) {
          const int n = 1000;  // several noise batches, the last one partial
          ParticleModel m;
          m.dimension = k;
          m.radius.assign(n, 0.5);
          Forces f;
          if (trap) f.trap = HarmonicTrap{0.7, {1.0, -2.0, 0.5}};
          f.diffusion = noise ? 0.3 : 0.0;
          const Prediction prediction(f, PeriodicBox::Of(m), n, 0.01, 5, true);
          const Prediction general_prediction(f, PeriodicBox::Of(m), n, 0.01, 5, false);
          SplitMix64 rng(k * 8 + trap * 4 + noise * 2 + active);
          std::vector<double> x(static_cast<std::size_t>(k * n)), ref(x.size());
          for (double& v : x) v = 40.0 * rng.Uniform01() - 20.0;
          for (std::size_t i = 0; i < x.size(); ++i) ref[i] = x[i] + 0.2 * rng.Uniform01() - 0.1;
          std::vector<int> id(static_cast<std::size_t>(n));
          for (int s = 0; s < n; ++s) id[static_cast<std::size_t>(s)] = (7 * s + 3) % n;
          std::vector<double> velocity;
          if (active) {
            for (std::size_t i = 0; i < x.size(); ++i) velocity.push_back(rng.Uniform01() - 0.5);
          }
          StepContext plain, general;
          StoreContext(m, x, velocity, 2, &plain);
          StoreContext(m, x, velocity, 2, &general);
          plain.store->id = general.store->id = id;
          for (const bool poisoned : {false, true}) {
            if (poisoned) {  // two non-finite rows in different batches
              x[static_cast<std::size_t>(k * 300 + 1)] = std::numeric_limits<double>::infinity();
              x[static_cast<std::size_t>(k * 700)] = std::numeric_limits<double>::quiet_NaN();
            }
            plain.store->current = general.store->current = x;
            ExactBound b_plain{ref.data(), 0.0025}, b_general{ref.data(), 0.0025};
            const PredictionOutcome o_plain = prediction.Predict(plain, 4, &b_plain);
            const PredictionOutcome o_general = general_prediction.Predict(general, 4, &b_general);
            const std::vector<double>& y_plain = plain.store->predicted;
            const std::vector<double>& y_general = general.store->predicted;
            const std::string what = fmt::format("k {} trap {} noise {} active {} poisoned {}", k,
                                                 trap, noise, active, poisoned);
            EXPECT_EQ(std::memcmp(y_plain.data(), y_general.data(), 8 * x.size()), 0) << what;
            EXPECT_EQ(o_plain.max_move, o_general.max_move) << what;
            EXPECT_EQ(o_plain.max_coordinate, o_general.max_coordinate) << what;
            EXPECT_EQ(o_plain.bad_id, o_general.bad_id) << what;
            EXPECT_EQ(o_plain.bad_id, poisoned ? std::min(id[300], id[700]) : -1) << what;
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
}

// Two overlapping disks on a wall: one sweep separates the pair exactly (each moves half the
// overlap) and pushes the lower one out of the wall; the longest path is the sum of its moves.
TEST(ParticleSweep, PairThenWallWithPathBound) {
  ParticleModel m;
  m.dimension = 2;
  m.radius = {1.0, 1.0};
  m.walls.push_back(Wall{{0.0, 1.0, 0.0}, 0.0});  // y ≥ r
  ProjectionSweep sweep(m, true);
  StepContext c;
  // distance 1.5, overlap 0.5; particle 0 is 0.5 deep
  testing::LexicographicContext(m, {0.0, 0.5, 0.0, 2.0}, 3.0, 1.0, 0, &c);
  ASSERT_EQ(c.list.pairs(), 1);
  std::int64_t projections = 0;
  const double path = sweep.Sweep(c, &projections);
  const std::vector<double>& x = c.store->predicted;
  EXPECT_NEAR(x[1], 1.0, 1e-15);  // 0.25 down by the pair, then 0.75 up by the wall
  EXPECT_NEAR(x[3], 2.25, 1e-15);
  EXPECT_EQ(x[0], 0.0);
  EXPECT_EQ(x[2], 0.0);
  EXPECT_EQ(projections, 2);
  EXPECT_NEAR(path, 1.0, 1e-15);
  EXPECT_EQ(sweep.MaxFixedViolation(x.data(), m.radius.data()), 0.0);
}

}  // namespace
}  // namespace moreau::particles::internal
