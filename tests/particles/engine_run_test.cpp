// The engine's run loop and queries: an observer that returns false stops the run and leaves the
// engine usable; the stage profile times the parts of every step; the contacts (the engine's one
// definition of touching) include periodic images, equal a brute-force minimum-image count, and
// a pair touches across a periodic boundary as it does mid-box.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <utility>
#include <vector>

#include "moreau/common/random.h"
#include "moreau/particles/checkpoint.h"
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

// The pairs with ‖X_i − X_j‖ ≤ factor (r_i + r_j), minimum image on the periodic axes, by an
// O(N²) loop over the positions in id order.
std::set<std::pair<int, int>> MinimumImageContacts(const ParticleModel& m,
                                                   const std::vector<double>& x, double factor) {
  std::set<std::pair<int, int>> pairs;
  const int k = m.dimension;
  for (int i = 0; i < m.count(); ++i) {
    for (int j = i + 1; j < m.count(); ++j) {
      double d2 = 0.0;
      for (int a = 0; a < k; ++a) {
        const auto ua = static_cast<std::size_t>(a);
        double d = x[static_cast<std::size_t>(k * i + a)] - x[static_cast<std::size_t>(k * j + a)];
        if (m.periodic[ua]) {
          const double L = m.domain_hi[ua] - m.domain_lo[ua];
          d -= L * std::round(d / L);
        }
        d2 += d * d;
      }
      const double reach =
          factor * (m.radius[static_cast<std::size_t>(i)] + m.radius[static_cast<std::size_t>(j)]);
      if (d2 <= reach * reach) pairs.insert({i, j});
    }
  }
  return pairs;
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

// After steps of a periodic soup (pairs across both boundaries): Contacts is exactly the
// brute-force minimum-image set, sorted, and ContactCounts counts it per particle.
TEST(EngineRun, ContactsAreTheMinimumImagePairsWithinTheFactor) {
  const NoisySoup s = NoisyPeriodicSoup(400, 24.0, 5);
  Engine e(s.model, s.forces, s.options, s.x0);
  ASSERT_TRUE(e.Run(30 * s.options.h).ok());
  const std::vector<double> x = e.Positions();
  for (const double factor : {1.05, 1.2, 1.5}) {
    const std::vector<std::pair<int, int>> contacts = e.Contacts(factor);
    const std::set<std::pair<int, int>> expected = MinimumImageContacts(s.model, x, factor);
    EXPECT_EQ((std::set<std::pair<int, int>>(contacts.begin(), contacts.end())), expected)
        << factor;
    EXPECT_TRUE(std::is_sorted(contacts.begin(), contacts.end()));
    EXPECT_EQ(contacts.size(), expected.size());
    int across = 0;  // contacts across a periodic boundary
    std::vector<int> counts(static_cast<std::size_t>(e.count()), 0);
    for (const auto& [i, j] : contacts) {
      for (int a = 0; a < 2; ++a) {
        const double d =
            x[static_cast<std::size_t>(2 * i + a)] - x[static_cast<std::size_t>(2 * j + a)];
        across += std::abs(d) > 12.0 ? 1 : 0;
      }
      ++counts[static_cast<std::size_t>(i)];
      ++counts[static_cast<std::size_t>(j)];
    }
    EXPECT_TRUE(factor < 1.1 || across > 0) << factor;
    EXPECT_EQ(e.ContactCounts(factor), counts) << factor;
  }
  EXPECT_THROW(e.Contacts(0.9), InputError);
  EXPECT_THROW(e.Contacts(1.6), InputError);
}

// Two disks 1.02 (r_i + r_j) apart: touching at factor 1.05, mid-box and across each periodic
// boundary alike; apart at factor 1.
TEST(EngineRun, APairTouchesAcrossAPeriodicBoundaryAsItDoesMidBox) {
  ParticleModel m;
  m.dimension = 2;
  m.radius = {0.5, 0.5};
  m.periodic = {true, true, false};
  m.domain_lo = {0.0, 0.0, 0.0};
  m.domain_hi = {10.0, 8.0, 1.0};
  for (const std::vector<double>& x0 :
       {std::vector<double>{4.49, 4.0, 5.51, 4.0}, std::vector<double>{9.49, 4.0, 0.51, 4.0},
        std::vector<double>{3.0, 0.31, 3.0, 7.29}}) {
    const Engine e(m, Forces{}, EngineOptions{}, x0);
    EXPECT_EQ(e.Contacts(1.05), (std::vector<std::pair<int, int>>{{0, 1}})) << x0[0];
    EXPECT_EQ(e.ContactCounts(1.05), (std::vector<int>{1, 1})) << x0[0];
    EXPECT_TRUE(e.Contacts(1.0).empty()) << x0[0];
  }
}

}  // namespace
}  // namespace moreau::particles
