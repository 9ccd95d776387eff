// The neighbour list's per-particle acceptance (NeighbourList::AcceptEach): it accepts a sweep in
// which a few slots moved far, and whenever it accepts, every pair that came into contact during
// the sweep is in the list (the invariant that makes leaving pairs out exact); and the build rule
// that lets a few slots go beyond skin/4.
#include <gtest/gtest.h>

#include <cmath>
#include <numeric>
#include <vector>

#include "moreau/common/random.h"
#include "particles/neighbour_list.h"
#include "particles/part_fixtures.h"

namespace moreau::particles::internal {
namespace {

using testing::RandomConfiguration;

constexpr double kSkin = 0.4;

// A list built at x0 (slots = ids, rows sorted) with skin kSkin and no attraction.
struct BuiltList {
  PeriodicBox box;
  CellList cells;
  NeighbourList list;
  BuiltList(const ParticleModel& model, const std::vector<double>& x0) {
    const int n = model.count();
    box = PeriodicBox::Of(model);
    cells.Fit(x0.data(), n, box, 2.0 * model.max_radius() + kSkin, 0, 1);
    std::vector<int> id(static_cast<std::size_t>(n));
    std::iota(id.begin(), id.end(), 0);
    cells.Sort(x0.data(), id.data(), n, 1);
    list.Configure(box, n, kSkin, std::numeric_limits<double>::infinity(), 0.0);
    list.Build(x0.data(), model.radius.data(), cells, cells.permutation().data(), ListRows::kSorted,
               0, 1);
  }
  bool Listed(int s, int t) const {
    for (int p = list.row_start()[s]; p < list.row_start()[s + 1]; ++p) {
      if (list.neighbours()[p] == t) return true;
    }
    return false;
  }
};

// Straight moves from start to x: is every pair that touches at one of 9 points along the way
// (the same fraction for both) in the list?
bool EveryContactListed(const BuiltList& built, const ParticleModel& model,
                        const std::vector<double>& start, const std::vector<double>& x) {
  const int n = model.count();
  const int k = model.dimension;
  for (int s = 0; s < n; ++s) {
    for (int t = s + 1; t < n; ++t) {
      for (int q = 0; q <= 8; ++q) {
        const double f = q / 8.0;
        double d2 = 0.0;
        for (int a = 0; a < k; ++a) {
          const auto us = static_cast<std::size_t>(k * s + a);
          const auto ut = static_cast<std::size_t>(k * t + a);
          const double u =
              (start[us] + f * (x[us] - start[us])) - (start[ut] + f * (x[ut] - start[ut]));
          d2 += u * u;
        }
        const double contact =
            model.radius[static_cast<std::size_t>(s)] + model.radius[static_cast<std::size_t>(t)];
        if (d2 <= contact * contact && !built.Listed(s, t)) return false;
      }
    }
  }
  return true;
}

// The straight path lengths ‖x_s − start_s‖.
std::vector<double> Paths(int k, const std::vector<double>& start, const std::vector<double>& x) {
  std::vector<double> path(start.size() / static_cast<std::size_t>(k), 0.0);
  for (std::size_t s = 0; s < path.size(); ++s) {
    double d2 = 0.0;
    for (std::size_t a = 0; a < static_cast<std::size_t>(k); ++a) {
      const double d =
          x[static_cast<std::size_t>(k) * s + a] - start[static_cast<std::size_t>(k) * s + a];
      d2 += d * d;
    }
    path[s] = std::sqrt(d2);
  }
  return path;
}

TEST(ListAcceptance, AFewFarMovesAreAcceptedAndEveryContactIsListed) {
  const RandomConfiguration c(2, {false, false, false}, 400, 30.0, 21);
  const BuiltList built(c.model, c.x);
  NeighbourList list = built.list;
  // Every slot drifts by ≤ 0.05, then 5 slots move 0.25 more: beyond the global bound
  // (0.05 + 0.25 ≥ skin/2), so the plain Accept refuses.
  SplitMix64 rng(5);
  std::vector<double> start = c.x;
  for (double& v : start) v += 0.035 * (2.0 * rng.Uniform01() - 1.0);
  std::vector<double> x = start;
  for (int s : {3, 77, 150, 222, 391}) {
    const double angle = 6.283185307179586 * rng.Uniform01();
    x[static_cast<std::size_t>(2 * s)] += 0.25 * std::cos(angle);
    x[static_cast<std::size_t>(2 * s + 1)] += 0.25 * std::sin(angle);
  }
  const std::vector<double> path = Paths(2, start, x);
  EXPECT_FALSE(list.Accept(0.05 + 0.25));
  ASSERT_TRUE(list.AcceptEach(start.data(), x.data(), c.model.radius.data(), path, built.cells,
                              built.cells.permutation().data(), 1));
  EXPECT_TRUE(EveryContactListed(built, c.model, start, x));
  // The next step's bound is the exact largest distance from the build positions (≤ 0.3 here).
  const double bound = list.BoundAfterPrediction(0.0, x.data(), 1);
  EXPECT_LE(bound, 0.05 + 0.25);
  EXPECT_GE(bound, 0.25 - 0.05);
}

TEST(ListAcceptance, TwoFastSlotsThatCouldMeetAreRefused) {
  ParticleModel model;
  model.dimension = 2;
  model.radius = {0.5, 0.5, 0.5};
  // 0 and 1 are 1.45 apart (≥ r + r + skin: not listed); 2 is far away.
  const std::vector<double> x0{0.0, 0.0, 1.45, 0.0, 10.0, 10.0};
  const BuiltList built(model, x0);
  ASSERT_FALSE(built.Listed(0, 1));
  // 0 and 1 move 0.25 toward each other: they overlap at the end, a contact the list misses.
  const std::vector<double> meet{0.25, 0.0, 1.2, 0.0, 10.0, 10.0};
  NeighbourList list = built.list;
  EXPECT_FALSE(list.AcceptEach(x0.data(), meet.data(), model.radius.data(), Paths(2, x0, meet),
                               built.cells, built.cells.permutation().data(), 1));
  EXPECT_FALSE(EveryContactListed(built, model, x0, meet));
  // 0 and 2 move 0.25 each, far apart: accepted, and nothing was missed.
  const std::vector<double> apart{-0.25, 0.0, 1.45, 0.0, 10.25, 10.0};
  list = built.list;
  EXPECT_TRUE(list.AcceptEach(x0.data(), apart.data(), model.radius.data(), Paths(2, x0, apart),
                              built.cells, built.cells.permutation().data(), 1));
  EXPECT_TRUE(EveryContactListed(built, model, x0, apart));
}

TEST(ListAcceptance, ManyFastSlotsAreRefused) {
  const RandomConfiguration c(2, {false, false, false}, 400, 30.0, 22);
  const BuiltList built(c.model, c.x);
  NeighbourList list = built.list;
  std::vector<double> x = c.x;
  for (int s = 0; s <= NeighbourList::kMaxFastSlots; ++s)
    x[static_cast<std::size_t>(2 * s)] += 0.25;
  EXPECT_FALSE(list.AcceptEach(c.x.data(), x.data(), c.model.radius.data(), Paths(2, c.x, x),
                               built.cells, built.cells.permutation().data(), 1));
}

TEST(ListAcceptance, AFewSlotsBeyondAQuarterSkinNeedNoBuild) {
  const RandomConfiguration c(2, {false, false, false}, 400, 30.0, 23);
  const BuiltList built(c.model, c.x);
  NeighbourList list = built.list;
  std::vector<double> y = c.x;
  for (int s = 0; s < 10; ++s) y[static_cast<std::size_t>(2 * s)] += 0.15;  // > skin/4, < skin/2
  const double few = list.BoundAfterPrediction(0.15, y.data(), 1);
  EXPECT_NEAR(few, 0.15, 1e-12);
  EXPECT_FALSE(list.NeedsBuild(few, true));
  EXPECT_TRUE(list.NeedsBuild(few, false));  // several sweeps per step: the rule as before
  // Beyond skin/2, or more than the cap of slots beyond skin/4: a build.
  y[0] += 0.1;
  EXPECT_TRUE(list.NeedsBuild(list.BoundAfterPrediction(0.25, y.data(), 1), true));
  y = c.x;
  for (int s = 0; s <= NeighbourList::kMaxFastSlots; ++s)
    y[static_cast<std::size_t>(2 * s)] += 0.15;
  EXPECT_TRUE(list.NeedsBuild(list.BoundAfterPrediction(0.15, y.data(), 1), true));
}

}  // namespace
}  // namespace moreau::particles::internal
