// The cell grid + Verlet lists against brute force, and the no-missed-contact guarantee.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <set>
#include <string>

#include "moreau/common/random.h"
#include "moreau/pbd/cases.h"
#include "particles/test_util.h"

namespace moreau::particles {
namespace {

struct Case {
  const char* name;
  int dimension;
  std::array<bool, 3> periodic;
  double attraction_range;
};

// Polydisperse particles in [0, L]^k; periodic axes as given.
void CheckGridEqualsBruteForce(const Case& c) {
  ParticleModel m;
  m.dimension = c.dimension;
  SplitMix64 rng(17);
  const int n = c.dimension == 2 ? 1500 : 1200;
  for (int i = 0; i < n; ++i) m.radius.push_back(0.2 + 0.4 * rng.Uniform01());
  const double L = c.dimension == 2 ? 60.0 : 14.0;
  m.periodic = c.periodic;
  m.domain_lo = {0, 0, 0};
  m.domain_hi = {L, L, L};
  const std::vector<double> x0 = RandomSequentialAddition(m, {0, 0, 0}, {L, L, L}, 5);
  Forces f;
  f.diffusion = 0.2;
  if (c.attraction_range > 0) f.attraction = PairAttraction{1.0, c.attraction_range, {}};
  for (const SweepOrder order : {SweepOrder::kColoured, SweepOrder::kLexicographic}) {
    EngineOptions o;
    o.h = 0.01;
    o.order = order;
    Engine grid(m, f, o, x0);
    o.search = NeighbourSearch::kBruteForce;
    Engine brute(m, f, o, x0);
    for (int step = 0; step < 40; ++step) {
      ASSERT_TRUE(grid.Step());
      ASSERT_TRUE(brute.Step());
    }
    // Same candidate pairs whenever both lists were built at the same positions: compare the
    // sets at construction-time builds of two fresh engines at the current state.
    const std::vector<double> x = grid.Positions();
    EngineOptions fresh = o;
    fresh.check_initial_state = false;
    fresh.search = NeighbourSearch::kCellGrid;
    Engine g2(m, f, fresh, x);
    fresh.search = NeighbourSearch::kBruteForce;
    Engine b2(m, f, fresh, x);
    const auto pg = g2.CandidatePairs();
    const auto pb = b2.CandidatePairs();
    EXPECT_EQ(pg.size(), pb.size()) << c.name;
    {
      std::vector<std::pair<int, int>> only_g, only_b;
      std::set_difference(pg.begin(), pg.end(), pb.begin(), pb.end(), std::back_inserter(only_g));
      std::set_difference(pb.begin(), pb.end(), pg.begin(), pg.end(), std::back_inserter(only_b));
      EXPECT_TRUE(only_g.empty() && only_b.empty())
          << c.name << ": " << only_g.size() << " pairs only in the grid's list, " << only_b.size()
          << " only in brute force's"
          << (only_g.empty() ? ""
                             : " e.g. (" + std::to_string(only_g[0].first) + ", " +
                                   std::to_string(only_g[0].second) + ")")
          << (only_b.empty() ? ""
                             : " e.g. (" + std::to_string(only_b[0].first) + ", " +
                                   std::to_string(only_b[0].second) + ")");
    }
    EXPECT_GT(pg.size(), static_cast<std::size_t>(n / 4));
    // Independent check: every pair closer than r_i + r_j + ℓ (minimum image) is a candidate.
    const std::set<std::pair<int, int>> candidates(pg.begin(), pg.end());
    int close = 0;
    for (int i = 0; i < n; ++i) {
      for (int j = i + 1; j < n; ++j) {
        double r2 = 0.0;
        for (int a = 0; a < c.dimension; ++a) {
          double d = x[static_cast<std::size_t>(c.dimension * i + a)] -
                     x[static_cast<std::size_t>(c.dimension * j + a)];
          if (c.periodic[static_cast<std::size_t>(a)]) d -= L * std::round(d / L);
          r2 += d * d;
        }
        const double reach = m.radius[static_cast<std::size_t>(i)] +
                             m.radius[static_cast<std::size_t>(j)] + c.attraction_range;
        if (r2 < reach * reach) {
          ++close;
          EXPECT_TRUE(candidates.count({i, j})) << c.name << " missing " << i << " " << j;
        }
      }
    }
    EXPECT_GT(close, 0);
    // The evolved lists (grid vs brute force) give the same dynamics in the lexicographic order,
    // bit for bit: a list only ever omits pairs that cannot touch.
    if (order == SweepOrder::kLexicographic) {
      EXPECT_TRUE(grid.Positions() == brute.Positions()) << c.name;
    }
    EXPECT_DOUBLE_EQ(grid.MaxPairOverlap(), testing::BruteForceMaxOverlap(m, grid.Positions()));
  }
}

TEST(ParticleNeighbours, GridEqualsBruteForce2d) {
  CheckGridEqualsBruteForce({"2d open", 2, {false, false, false}, 0.0});
}
TEST(ParticleNeighbours, GridEqualsBruteForce2dPeriodic) {
  CheckGridEqualsBruteForce({"2d periodic", 2, {true, true, false}, 0.0});
}
TEST(ParticleNeighbours, GridEqualsBruteForce2dOnePeriodicAxisWithAttraction) {
  CheckGridEqualsBruteForce({"2d periodic x, attraction", 2, {true, false, false}, 0.3});
}
TEST(ParticleNeighbours, GridEqualsBruteForce3dPeriodic) {
  CheckGridEqualsBruteForce({"3d periodic", 3, {true, true, true}, 0.0});
}

TEST(ParticleNeighbours, SmallPeriodicBoxWithFewCells) {
  // Two or one cells per periodic axis: the neighbour cells must not be visited twice.
  ParticleModel m;
  m.radius.assign(4, 0.5);
  m.periodic = {true, true, false};
  m.domain_lo = {0, 0, 0};
  m.domain_hi = {4.5, 2.5, 0};
  const std::vector<double> x = RandomSequentialAddition(m, {0, 0, 0}, {4.5, 2.5, 0}, 3);
  EngineOptions o;
  Engine g(m, Forces{}, o, x);
  o.search = NeighbourSearch::kBruteForce;
  Engine b(m, Forces{}, o, x);
  EXPECT_EQ(g.CandidatePairs(), b.CandidatePairs());
}

}  // namespace
}  // namespace moreau::particles
