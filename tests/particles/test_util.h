// Shared helpers for the particle engine tests.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <string>

#include "moreau/common/error.h"
#include "moreau/particles/engine.h"
#include "moreau/particles/room.h"

namespace moreau::particles::testing {

// Runs f, expects an InputError whose message contains `needle`.
inline void ExpectInputError(const std::function<void()>& f, const std::string& needle) {
  try {
    f();
    ADD_FAILURE() << "no InputError; expected one mentioning '" << needle << "'";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(needle), std::string::npos)
        << "message '" << e.what() << "' does not mention '" << needle << "'";
  }
}

// O(N²) largest pair overlap with minimum images: an independent check of the engine's.
inline double BruteForceMaxOverlap(const ParticleModel& m, const std::vector<double>& x) {
  const int k = m.dimension;
  double worst = 0.0;
  for (int i = 0; i < m.count(); ++i) {
    for (int j = i + 1; j < m.count(); ++j) {
      double r2 = 0.0;
      for (int a = 0; a < k; ++a) {
        double d = x[static_cast<std::size_t>(k * i + a)] - x[static_cast<std::size_t>(k * j + a)];
        if (m.periodic[static_cast<std::size_t>(a)]) {
          const double L =
              m.domain_hi[static_cast<std::size_t>(a)] - m.domain_lo[static_cast<std::size_t>(a)];
          d -= L * std::round(d / L);
        }
        r2 += d * d;
      }
      const double c =
          m.radius[static_cast<std::size_t>(i)] + m.radius[static_cast<std::size_t>(j)];
      worst = std::max(worst, c - std::sqrt(r2));
    }
  }
  return worst;
}

// 120 people of radius `radius` placed at random (seed 3) in an 8 m × 8 m room, walking to its
// door at desired speeds 1.34 ± 0.26 m/s with the walking law and noise `walk` sets; 300 steps
// of 0.01 s (seed 8) on 1 and on 2 threads. Returns the start and the two runs' final positions;
// `check` sees each run's summary.
struct RoomCrowdRuns {
  std::vector<double> start;
  std::vector<std::vector<double>> final;  // [0]: 1 thread, [1]: 2 threads
};
inline RoomCrowdRuns RunRoomCrowdOnOneAndTwoThreads(
    double radius, const std::function<void(Forces&)>& walk,
    const std::function<void(const EngineSummary&)>& check) {
  Room room;
  room.width = 8.0;
  room.height = 8.0;
  ParticleModel m;
  m.radius.assign(120, radius);
  AddRoom(room, &m);
  RoomCrowdRuns runs;
  runs.start = RandomSequentialAddition(m, {0.3, 0.3, 0}, {7.7, 7.7, 0}, 3);
  Forces f;
  f.propulsion = room.WalkToTheDoor(1.34);
  f.walking.speed_sd = 0.26;
  walk(f);
  for (int threads : {1, 2}) {
    EngineOptions o;
    o.h = 0.01;
    o.seed = 8;
    o.threads = threads;
    o.block_cells = 1;
    Engine e(m, f, o, runs.start);
    const EngineSummary summary = e.Run(300 * o.h);
    EXPECT_TRUE(summary.ok()) << summary.message;
    check(summary);
    runs.final.push_back(e.Positions());
  }
  return runs;
}

}  // namespace moreau::particles::testing
