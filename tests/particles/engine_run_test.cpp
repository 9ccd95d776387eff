// The engine's run loop: an observer that returns false stops the run and leaves the engine
// usable; the stage profile times the parts of every step.
#include <gtest/gtest.h>

#include <vector>

#include "moreau/common/random.h"
#include "moreau/particles/engine.h"

namespace moreau::particles {
namespace {

// n disks of radii in [0.3, 0.5] in a periodic square of side L, with noise.
struct NoisySoup {
  ParticleModel model;
  Forces forces;
  EngineOptions options;
  std::vector<double> x0;
};

NoisySoup NoisyPeriodicSoup(int n, double L, std::uint64_t seed) {
  NoisySoup s;
  s.model.dimension = 2;
  SplitMix64 rng(seed);
  for (int i = 0; i < n; ++i) s.model.radius.push_back(0.3 + 0.2 * rng.Uniform01());
  s.model.periodic = {true, true, false};
  s.model.domain_lo = {0.0, 0.0, 0.0};
  s.model.domain_hi = {L, L, 1.0};
  s.forces.diffusion = 0.02;
  s.options.h = 0.01;
  s.options.seed = seed;
  s.x0 = RandomSequentialAddition(s.model, s.model.domain_lo, s.model.domain_hi, seed);
  return s;
}

TEST(EngineRun, AnObserverReturningFalseStopsTheRunAndTheEngineGoesOn) {
  const NoisySoup s = NoisyPeriodicSoup(200, 16.0, 3);
  Engine stopped(s.model, s.forces, s.options, s.x0);
  std::vector<std::int64_t> seen;
  const EngineSummary summary = stopped.Run(20 * s.options.h, [&](const Engine& e) {
    seen.push_back(e.step());
    return e.step() < 7;
  });
  EXPECT_EQ(summary.termination, Termination::kInterrupted);
  EXPECT_EQ(summary.message, "stopped by the observer");
  EXPECT_FALSE(summary.ok());
  EXPECT_EQ(summary.stats.steps, 7);
  EXPECT_EQ(seen, (std::vector<std::int64_t>{0, 1, 2, 3, 4, 5, 6, 7}));
  EXPECT_EQ(stopped.step(), 7);
  // The engine carries on from step 7 to the same bits as a run that was never stopped.
  EXPECT_TRUE(stopped.Step());
  const EngineSummary rest = stopped.Continue(20 * s.options.h, [](const Engine&) { return true; });
  ASSERT_TRUE(rest.ok()) << rest.message;
  Engine whole(s.model, s.forces, s.options, s.x0);
  ASSERT_TRUE(whole.Run(20 * s.options.h).ok());
  EXPECT_EQ(stopped.step(), 20);
  EXPECT_TRUE(stopped.Positions() == whole.Positions());
  // Stopped at step 0: no step is taken.
  Engine first(s.model, s.forces, s.options, s.x0);
  EXPECT_EQ(first.Run(1.0, [](const Engine&) { return false; }).termination,
            Termination::kInterrupted);
  EXPECT_EQ(first.step(), 0);
}

// Every stage of a step is timed, inside the steps' total; the setup's list build is the
// setup's. A checkpoint carries the timings on.
TEST(EngineRun, TheStageProfileTimesEveryStageWithinTheSteps) {
  const NoisySoup s = NoisyPeriodicSoup(3000, 60.0, 4);
  Engine e(s.model, s.forces, s.options, s.x0);
  const EngineStats setup = e.summary().stats;
  EXPECT_GT(setup.setup_seconds, 0.0);
  EXPECT_EQ(setup.neighbour_seconds, 0.0);
  EXPECT_EQ(setup.total_seconds, 0.0);
  ASSERT_TRUE(e.Run(40 * s.options.h).ok());
  const EngineStats st = e.summary().stats;
  EXPECT_GT(st.neighbour_list_builds, 1);
  for (const double seconds :
       {st.force_seconds, st.neighbour_seconds, st.sweep_seconds, st.monitor_seconds}) {
    EXPECT_GT(seconds, 0.0);
  }
  const double parts =
      st.force_seconds + st.neighbour_seconds + st.sweep_seconds + st.monitor_seconds;
  EXPECT_LE(parts, st.total_seconds * (1.0 + 1e-9));
  EXPECT_EQ(st.setup_seconds, setup.setup_seconds);
  Engine resumed(s.model, s.forces, s.options, s.x0);
  resumed.RestoreState(e.SaveState());
  const EngineStats carried = resumed.summary().stats;
  EXPECT_EQ(carried.sweep_seconds, st.sweep_seconds);
  EXPECT_EQ(carried.total_seconds, st.total_seconds);
}

}  // namespace
}  // namespace moreau::particles
