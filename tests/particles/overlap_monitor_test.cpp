// The overlap monitor after each step: the same value as the pass over every pair, for any thread
// count, with noise, polydisperse radii, periodic axes and several sweeps per step; and from the
// recorded rows alone when the margin covers the sweep's paths.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "moreau/common/random.h"
#include "moreau/particles/engine.h"
#include "particles/cell_list.h"
#include "particles/colouring.h"
#include "particles/neighbour_list.h"
#include "particles/overlap_monitor.h"
#include "particles/part_fixtures.h"
#include "particles/sweep.h"
#include "particles/test_util.h"

namespace moreau::particles {
namespace {

// A dense periodic soup: n disks of radii in [0.4, 0.6] by random sequential addition.
ParticleModel Soup(int n, double side) {
  ParticleModel m;
  m.dimension = 2;
  SplitMix64 rng(3);
  for (int i = 0; i < n; ++i) m.radius.push_back(0.4 + 0.2 * rng.Uniform01());
  m.periodic = {true, true, false};
  m.domain_lo = {0.0, 0.0, 0.0};
  m.domain_hi = {side, side, 1.0};
  return m;
}

TEST(OverlapMonitor, EveryStepEqualsThePassOverAllPairs) {
  const ParticleModel m = Soup(1000, 44.0);
  const std::vector<double> x0 = RandomSequentialAddition(m, m.domain_lo, m.domain_hi, 5);
  Forces f;
  f.diffusion = 0.05;
  f.constant_force = {0.5, 0.0, 0.0};
  for (const int sweeps : {1, 3}) {
    std::vector<double> overlaps[2];
    for (const int threads : {1, 2}) {
      EngineOptions o;
      o.h = 0.01;
      o.seed = 8;
      o.threads = threads;
      o.sweeps = sweeps;
      o.block_cells = 2;
      Engine e(m, f, o, x0);
      for (int step = 0; step < 20; ++step) {
        ASSERT_TRUE(e.Step());
        const double monitored = e.summary().stats.last_overlap;
        EXPECT_EQ(monitored, e.MaxPairOverlap()) << "step " << step;
        overlaps[threads - 1].push_back(monitored);
      }
      EXPECT_GT(e.summary().stats.max_overlap, 0.0);
      EXPECT_NEAR(e.summary().stats.last_overlap, testing::BruteForceMaxOverlap(m, e.Positions()),
                  1e-12);
    }
    EXPECT_EQ(overlaps[0], overlaps[1]) << "sweeps " << sweeps;
  }
}

// The parts alone: sweeps of the same soup pushed together, each followed by the monitor. The
// first measurement has no margin yet (a pass over every row); later ones use the recorded rows
// whenever the margin covers twice the sweep's longest path, and agree with the full pass.
TEST(OverlapMonitor, RecordedRowsGiveTheExactMaximum) {
  const ParticleModel m = Soup(800, 38.0);
  const std::vector<double> x0 = RandomSequentialAddition(m, m.domain_lo, m.domain_hi, 9);
  const int n = m.count();
  internal::StepContext c;  // sweeps in id order, the list's skin 0.6
  testing::LexicographicContext(m, x0, 2.0 * 0.6 + 0.6, 0.6, 2, &c);
  c.rmax = 0.6;
  std::vector<double>& x = c.store->predicted;
  internal::ProjectionSweep sweep(m, false);
  internal::OverlapMonitor monitor;
  SplitMix64 rng(4);
  for (int round = 0; round < 6; ++round) {
    // Every disk moves 0.02 toward the centre of the box along x: pairs close in.
    double extent = 0.0;
    for (int i = 0; i < n; ++i) {
      double& xi = x[static_cast<std::size_t>(2 * i)];
      xi += xi < 19.0 ? 0.02 * rng.Uniform01() : -0.02 * rng.Uniform01();
      extent = std::max({extent, std::abs(xi), std::abs(x[static_cast<std::size_t>(2 * i + 1)])});
    }
    std::int64_t projections = 0;
    sweep.Sweep(c, &projections, monitor.Prepare(1));
    ASSERT_GT(projections, 0);
    c.store->current = x;  // the step's end: the swept positions are the current ones
    const double monitored = monitor.Measure(c, extent);
    EXPECT_EQ(monitored, internal::MaxPairOverlap(c.list, x.data(), m.radius.data(), n, 1));
    EXPECT_GT(monitored, 0.0);
  }
  EXPECT_EQ(monitor.full_steps() + monitor.screened_steps(), 6);
  EXPECT_GE(monitor.screened_steps(), 3);
}

// Equal radii in 2D without periodic axes (the sweep then tests short rows whole): with no
// overlap nothing moves, and the recorded rows are exactly those with a pair closer than
// 2r + margin. A row test that drops a pair, or a near-contact test that drops a row, fails here.
TEST(OverlapMonitor, UniformDisksRecordExactlyTheRowsWithinTheMargin) {
  ParticleModel m;
  m.dimension = 2;
  m.radius.assign(900, 0.5);
  m.domain_lo = {0.0, 0.0, 0.0};
  m.domain_hi = {40.0, 40.0, 1.0};
  const std::vector<double> x0 = RandomSequentialAddition(m, m.domain_lo, m.domain_hi, 21);
  const int n = m.count();
  internal::StepContext c;
  testing::LexicographicContext(m, x0, 1.0 + 0.6, 0.6, 0, &c);
  const internal::NeighbourList& list = c.list;
  internal::ProjectionSweep sweep(m, true);
  const double margin = 0.1;
  internal::NearContactRows near;
  near.margin = margin;
  near.rows.resize(1);
  std::int64_t projections = 0;
  sweep.Sweep(c, &projections, &near);
  const std::vector<double>& x = c.store->predicted;
  EXPECT_EQ(projections, 0);
  EXPECT_EQ(x, x0);
  std::vector<int> expected;
  int longest = 0, rows = 0;
  for (int s = 0; s < n; ++s) {
    const int b = list.row_start()[s], e = list.row_start()[s + 1];
    longest = std::max(longest, e - b);
    rows += e > b ? 1 : 0;
    bool close = false;
    for (int p = b; p < e; ++p) {
      const int t = list.neighbours()[p];
      const double dx = x[2 * static_cast<std::size_t>(s)] - x[2 * static_cast<std::size_t>(t)];
      const double dy =
          x[2 * static_cast<std::size_t>(s) + 1] - x[2 * static_cast<std::size_t>(t) + 1];
      close = close || dx * dx + dy * dy < (1.0 + margin) * (1.0 + margin);
    }
    if (close) expected.push_back(s);
  }
  EXPECT_EQ(near.rows[0], expected);
  EXPECT_GT(expected.size(), 50u);  // some rows near contact, and some rows not
  EXPECT_LT(expected.size(), static_cast<std::size_t>(rows) - 50);
  EXPECT_GT(longest, 4);  // rows too long for the whole-row test take the pair loop
}

}  // namespace
}  // namespace moreau::particles
