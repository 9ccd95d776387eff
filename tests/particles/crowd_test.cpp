// A pedestrian crowd's walking speeds (forces.h): the desired-speed distribution, Weidmann's
// speed–density law, both through the engine, and their bit-identity across thread counts.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "moreau/particles/engine.h"
#include "moreau/particles/room.h"
#include "particles/test_util.h"

namespace moreau::particles {
namespace {

using testing::ExpectInputError;

// Helbing & Molnár's desired speeds: over 20000 persons the sample mean and standard deviation
// match the truncated normal's (mean v0, sd σ √(1 − 6 φ(3)/(2Φ(3) − 1))) within 4 standard
// errors; every speed lies in [v0 − 3σ, v0 + 3σ]; a speed is a pure function of (seed, id).
TEST(CrowdSpeed, DesiredSpeedsHaveTheTruncatedNormalMoments) {
  const double v0 = 1.34, sigma = 0.26;
  const int n = 20000;
  double sum = 0.0, sum2 = 0.0;
  for (int id = 0; id < n; ++id) {
    const double v = DesiredSpeed(2024, id, v0, sigma);
    ASSERT_GE(v, v0 - 3.0 * sigma);
    ASSERT_LE(v, v0 + 3.0 * sigma);
    sum += v;
    sum2 += v * v;
  }
  const double mean = sum / n;
  const double sd = std::sqrt((sum2 - n * mean * mean) / (n - 1));
  const double phi3 = std::exp(-4.5) / std::sqrt(2.0 * std::numbers::pi);
  const double mass = std::erf(3.0 / std::sqrt(2.0));  // 2Φ(3) − 1
  const double sd_exact = sigma * std::sqrt(1.0 - 6.0 * phi3 / mass);
  EXPECT_NEAR(mean, v0, 4.0 * sd_exact / std::sqrt(n));
  EXPECT_NEAR(sd, sd_exact, 4.0 * sd_exact / std::sqrt(2.0 * n));
  EXPECT_EQ(DesiredSpeed(2024, 17, v0, sigma), DesiredSpeed(2024, 17, v0, sigma));
  EXPECT_NE(DesiredSpeed(2024, 17, v0, sigma), DesiredSpeed(2025, 17, v0, sigma));
  EXPECT_EQ(DesiredSpeed(2024, 17, v0, 0.0), v0);
}

// Weidmann's φ(ρ) = 1 − exp(−γ (1/ρ − 1/ρ_max)) at known densities; 0 at and beyond ρ_max.
TEST(CrowdSpeed, WeidmannFactorAtKnownDensities) {
  const DensitySpeed law;  // γ = 1.913, ρ_max = 5.4
  for (double rho : {0.5, 1.0, 2.0, 4.0, 5.0}) {
    EXPECT_NEAR(WeidmannSpeedFactor(law, rho), 1.0 - std::exp(-1.913 * (1.0 / rho - 1.0 / 5.4)),
                1e-15)
        << rho;
  }
  // At 1 person/m² Weidmann's pedestrians walk 1.34 · 0.7895… ≈ 1.058 m/s.
  EXPECT_NEAR(1.34 * WeidmannSpeedFactor(law, 1.0), 1.058, 1e-3);
  EXPECT_EQ(WeidmannSpeedFactor(law, 5.4), 0.0);
  EXPECT_EQ(WeidmannSpeedFactor(law, 9.0), 0.0);
  EXPECT_EQ(WeidmannSpeedFactor(law, 0.0), 1.0);
}

// People on a square lattice (spacing 0.5 m, radius 0.2 m: no contact), all walking to a far
// point: after one step without noise each has moved h v0,i φ(ρ_i), with ρ_i counted by brute
// force within R — the engine's neighbour lists reach far enough and the factor follows its
// person through the storage reordering.
TEST(CrowdSpeed, EngineWalksAtTheDesiredSpeedTimesWeidmannsFactor) {
  ParticleModel m;
  std::vector<double> x0;
  for (int i = 0; i < 12; ++i) {
    for (int j = 0; j < 9; ++j) {
      m.radius.push_back(0.2);
      x0.push_back(0.5 * i + 0.01 * j);  // sheared a little: no distance exactly R
      x0.push_back(0.5 * j);
    }
  }
  Forces f;
  SelfPropulsion walk;
  walk.speed = 1.34;
  walk.target = {500.0, 2.0, 0.0};
  f.propulsion = walk;
  f.walking.speed_sd = 0.26;
  f.walking.density = DensitySpeed{1.913, 5.4, 0.9};
  EngineOptions o;
  o.h = 0.01;
  o.seed = 5;
  Engine e(m, f, o, x0);
  ASSERT_TRUE(e.Step());
  const std::vector<double> x = e.Positions();
  const double area = std::numbers::pi * 0.81;
  for (int i = 0; i < m.count(); ++i) {
    int within = 1;
    for (int j = 0; j < m.count(); ++j) {
      const double dx = x0[2 * i] - x0[2 * j], dy = x0[2 * i + 1] - x0[2 * j + 1];
      within += (j != i && dx * dx + dy * dy < 0.81) ? 1 : 0;
    }
    const double v =
        DesiredSpeed(5, i, 1.34, 0.26) * WeidmannSpeedFactor(*f.walking.density, within / area);
    const double moved = std::hypot(x[2 * i] - x0[2 * i], x[2 * i + 1] - x0[2 * i + 1]);
    EXPECT_NEAR(moved, o.h * v, 1e-14) << "person " << i << ", " << within << " within R";
  }
}

// 120 people leaving a room through a 1.2 m door with desired speeds, Weidmann's law and noise:
// the same bits on 1 and 2 threads.
TEST(CrowdSpeed, WeidmannCrowdIsBitIdenticalOnOneAndTwoThreads) {
  const testing::RoomCrowdRuns runs = testing::RunRoomCrowdOnOneAndTwoThreads(
      0.25,
      [](Forces& f) {
        f.walking.density = DensitySpeed{};
        f.diffusion = 0.005;
      },
      [](const EngineSummary& summary) { EXPECT_GT(summary.stats.projections, 100); });
  EXPECT_TRUE(runs.final[1] == runs.final[0]);
}

TEST(CrowdSpeed, BadSpeedsAreInputErrors) {
  ParticleModel m;
  m.radius.assign(2, 0.25);
  Forces f;
  f.walking.speed_sd = 0.1;
  ExpectInputError([&] { f.Validate(); }, "forces.walking needs forces.propulsion");
  f.propulsion = SelfPropulsion{};
  f.walking.speed_sd = 0.5;  // > v0/3
  ExpectInputError([&] { f.Validate(); }, "forces.walking.speed_sd must be in [0, speed/3]");
  f.walking.speed_sd = 0.0;
  f.walking.density = DensitySpeed{1.913, 0.0, 1.0};
  ExpectInputError([&] { f.Validate(); }, "forces.walking.density.max_density must be > 0 (got 0)");
  f.walking.density = DensitySpeed{};
  ParticleModel m3 = m;
  m3.dimension = 3;
  const std::vector<double> x3 = {0, 0, 0, 1, 0, 0};
  ExpectInputError([&] { Engine(m3, f, EngineOptions{}, x3); }, "needs dimension 2 (got 3)");
}

}  // namespace
}  // namespace moreau::particles
