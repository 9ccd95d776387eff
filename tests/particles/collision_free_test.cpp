// The collision-free speed model (forces.h CollisionFreeSpeed): its speed law, the headway in the
// path, the single-file ring's exact stationary speed through the engine, bit-identity across
// thread counts, and bad parameters.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "moreau/particles/engine.h"
#include "moreau/particles/room.h"
#include "particles/test_util.h"

namespace moreau::particles {
namespace {

using testing::ExpectInputError;

TEST(CollisionFreeSpeed, SpeedLawIsTheOptimalVelocityFunction) {
  const CollisionFreeSpeed m;  // T = 1 s, ℓ = 0.3 m
  EXPECT_EQ(CollisionFreeSpeedAt(m, 1.34, 0.2), 0.0);
  EXPECT_EQ(CollisionFreeSpeedAt(m, 1.34, 0.3), 0.0);
  EXPECT_DOUBLE_EQ(CollisionFreeSpeedAt(m, 1.34, 1.0), 0.7);
  EXPECT_EQ(CollisionFreeSpeedAt(m, 1.34, 5.0), 1.34);
  EXPECT_EQ(CollisionFreeSpeedAt(m, 1.34, std::numeric_limits<double>::infinity()), 1.34);
  CollisionFreeSpeed slow = m;
  slow.time_gap = 2.0;
  EXPECT_DOUBLE_EQ(CollisionFreeSpeedAt(slow, 1.34, 1.3), 0.5);
  EXPECT_DOUBLE_EQ(CollisionFreeRange(m, 1.34), 0.3 + 1.34);
  EXPECT_DOUBLE_EQ(CollisionFreeRange(m, 0.5), 0.3 + 1.0);  // 10 D
}

Forces WalkRight(double v0, double repulsion) {
  Forces f;
  SelfPropulsion walk;
  walk.speed = v0;
  walk.direction = Vec3{1.0, 0.0, 0.0};
  f.propulsion = walk;
  CollisionFreeSpeed cfs;
  cfs.repulsion = repulsion;
  f.walking.collision_free = cfs;
  return f;
}

// Without repulsion everyone walks along e0 = +x; a person slows to V(s) = (s − ℓ)/T for a
// neighbour ahead within ℓ of the line of walking, and not for one further aside or behind.
TEST(CollisionFreeSpeed, HeadwayCountsOnlyNeighboursInThePath) {
  for (const double aside : {0.2, 0.4}) {
    ParticleModel m;
    m.radius.assign(2, 0.1);
    const std::vector<double> x0 = {0.0, 0.0, 0.5, aside};
    EngineOptions o;
    o.h = 0.01;
    Engine e(m, WalkRight(1.34, 0.0), o, x0);
    ASSERT_TRUE(e.Step());
    const std::vector<double> x = e.Positions();
    const double s = std::hypot(0.5, aside);
    const double expected = aside < 0.3 ? (s - 0.3) / 1.0 : 1.34;
    EXPECT_NEAR(x[0] - x0[0], o.h * expected, 1e-15) << aside;
    EXPECT_EQ(x[1], x0[1]);
    EXPECT_NEAR(x[2] - x0[2], o.h * 1.34, 1e-15) << "the one ahead walks freely";
  }
}

// Single file on a ring of length L = N/ρ, equally spaced: every headway is 1/ρ and the
// repulsions cancel, so every person walks at exactly V(1/ρ) = min(v0, max(0, (1/ρ − ℓ)/T)),
// step after step.
TEST(CollisionFreeSpeed, SingleFileRingWalksAtTheExactStationarySpeed) {
  for (const double rho : {0.5, 1.0, 2.0, 3.0}) {
    const int n = 12;
    ParticleModel m;
    m.radius.assign(n, 0.15);
    m.periodic = {true, false, false};
    m.domain_hi = {n / rho, 1.0, 1.0};
    std::vector<double> x0;
    for (int i = 0; i < n; ++i) {
      x0.push_back((i + 0.5) / rho);
      x0.push_back(0.5);
    }
    EngineOptions o;
    o.h = 0.01;
    Engine e(m, WalkRight(1.34, 5.0), o, x0);
    const EngineSummary summary = e.Run(100 * o.h);
    ASSERT_TRUE(summary.ok()) << summary.message;
    const std::vector<double> x = e.Positions();
    const double v = std::min(1.34, std::max(0.0, (1.0 / rho - 0.3) / 1.0));
    for (int i = 0; i < n; ++i) {
      double dx = x[2 * i] - x0[2 * i];
      dx -= (n / rho) * std::round(dx / (n / rho));
      EXPECT_NEAR(dx, 100 * o.h * v, 1e-11) << "ρ = " << rho << ", person " << i;
      EXPECT_EQ(x[2 * i + 1], 0.5);
    }
  }
}

// 120 people leaving a room through a door in the collision-free model with desired speeds and
// noise: the same bits on 1 and 2 threads, and they moved.
TEST(CollisionFreeSpeed, CrowdIsBitIdenticalOnOneAndTwoThreads) {
  const testing::RoomCrowdRuns runs = testing::RunRoomCrowdOnOneAndTwoThreads(
      0.2,
      [](Forces& f) {
        f.walking.collision_free = CollisionFreeSpeed{};
        f.diffusion = 0.001;
      },
      [](const EngineSummary&) {});
  EXPECT_TRUE(runs.final[1] == runs.final[0]);
  EXPECT_NE(runs.final[0], runs.start);
}

TEST(CollisionFreeSpeed, BadParametersAreInputErrors) {
  Forces f = WalkRight(1.34, 5.0);
  f.walking.collision_free->time_gap = 0.0;
  ExpectInputError([&] { f.Validate(); },
                   "forces.walking.collision_free.time_gap: must be > 0 (got 0)");
  f.walking.collision_free->time_gap = 1.0;
  f.walking.collision_free->repulsion = -1.0;
  ExpectInputError([&] { f.Validate(); }, "forces.walking.collision_free.repulsion");
  f.walking.collision_free->repulsion = 5.0;
  f.walking.density = DensitySpeed{};
  ExpectInputError([&] { f.Validate(); }, "does not go with forces.walking.density");
  f.walking.density.reset();
  f.propulsion->direction = Vec3{0.0, 0.0, 0.0};
  ExpectInputError([&] { f.Validate(); },
                   "forces.propulsion.direction must be finite and non-zero");
  f.propulsion->direction = Vec3{1.0, 0.0, 0.0};
  ParticleModel m3;
  m3.dimension = 3;
  m3.radius.assign(2, 0.1);
  const std::vector<double> x3 = {0, 0, 0, 1, 0, 0};
  ExpectInputError([&] { Engine(m3, f, EngineOptions{}, x3); }, "needs dimension 2 (got 3)");
}

}  // namespace
}  // namespace moreau::particles
