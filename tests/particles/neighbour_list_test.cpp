// The neighbour list against brute force, its skin bookkeeping and statistics.
#include "particles/neighbour_list.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <set>
#include <utility>

#include "particles/part_fixtures.h"

namespace moreau::particles::internal {
namespace {

using testing::RandomConfiguration;
using PairSet = std::set<std::pair<int, int>>;

// Every pair (i < j) closer than r_i + r_j + extra, minimum image, by an O(N²) loop.
PairSet BruteForcePairs(const RandomConfiguration& c, double extra) {
  const int k = c.model.dimension;
  PairSet pairs;
  for (int i = 0; i < c.model.count(); ++i) {
    for (int j = i + 1; j < c.model.count(); ++j) {
      double r2 = 0.0;
      for (int a = 0; a < k; ++a) {
        const auto ua = static_cast<std::size_t>(a);
        double d =
            c.x[static_cast<std::size_t>(k * i + a)] - c.x[static_cast<std::size_t>(k * j + a)];
        if (c.model.periodic[ua]) {
          const double L = c.model.domain_hi[ua] - c.model.domain_lo[ua];
          d -= L * std::round(d / L);
        }
        r2 += d * d;
      }
      const double reach = c.model.radius[static_cast<std::size_t>(i)] +
                           c.model.radius[static_cast<std::size_t>(j)] + extra;
      if (r2 < reach * reach) pairs.insert({i, j});
    }
  }
  return pairs;
}

// The list's pairs as (id, id), smaller first; rows must hold partners t > s.
PairSet ListPairs(const NeighbourList& list, const std::vector<int>& id) {
  PairSet pairs;
  const int n = static_cast<int>(id.size());
  for (int s = 0; s < n; ++s) {
    for (int p = list.row_start()[s]; p < list.row_start()[s + 1]; ++p) {
      const int t = list.neighbours()[p];
      EXPECT_GT(t, s);
      const int a = id[static_cast<std::size_t>(s)], b = id[static_cast<std::size_t>(t)];
      EXPECT_TRUE(pairs.insert({std::min(a, b), std::max(a, b)}).second) << "pair listed twice";
    }
  }
  return pairs;
}

// The configuration stored in cell order, as the engine keeps it: slot s holds particle
// slot_id[s] of c.
struct CellOrdered {
  PeriodicBox box;
  CellList cells;
  std::vector<double> x, radius;
  std::vector<int> slot_id;

  CellOrdered(const RandomConfiguration& c, double skin, int threads, int block_cells = 0)
      : box(PeriodicBox::Of(c.model)) {
    const int n = c.model.count();
    const int k = c.model.dimension;
    std::vector<int> id(static_cast<std::size_t>(n));
    std::iota(id.begin(), id.end(), 0);
    cells.Fit(c.x.data(), n, box, 2.0 * c.model.max_radius() + skin, block_cells, threads);
    cells.Sort(c.x.data(), id.data(), n, threads);
    x.resize(c.x.size());
    radius.resize(static_cast<std::size_t>(n));
    slot_id.resize(static_cast<std::size_t>(n));
    for (int s = 0; s < n; ++s) {
      const int o = cells.permutation()[static_cast<std::size_t>(s)];
      for (int a = 0; a < k; ++a)
        x[static_cast<std::size_t>(k * s + a)] = c.x[static_cast<std::size_t>(k * o + a)];
      radius[static_cast<std::size_t>(s)] = c.model.radius[static_cast<std::size_t>(o)];
      slot_id[static_cast<std::size_t>(s)] = o;
    }
  }
};

void CheckAgainstBruteForce(const RandomConfiguration& c, double skin) {
  const int n = c.model.count();
  const PairSet expected = BruteForcePairs(c, skin);
  ASSERT_GT(expected.size(), static_cast<std::size_t>(n / 4));
  // The lexicographic list (initial-state checks, pbd adapter): rows sorted by j.
  LexicographicPairList lexicographic(PeriodicBox::Of(c.model), n, c.model.max_radius(), skin);
  lexicographic.Build(c.x.data(), c.model.radius.data());
  std::vector<int> id(static_cast<std::size_t>(n));
  std::iota(id.begin(), id.end(), 0);
  EXPECT_EQ(ListPairs(lexicographic.list(), id), expected);
  const NeighbourList& list = lexicographic.list();
  for (int s = 0; s < n; ++s) {
    for (int p = list.row_start()[s] + 1; p < list.row_start()[s + 1]; ++p) {
      EXPECT_LT(list.neighbours()[p - 1], list.neighbours()[p]);
    }
  }
  // The engine's way: storage reordered into cell order, the list over slot ranges.
  const CellOrdered o(c, skin, 2);
  NeighbourList ordered;
  ordered.Configure(o.box, n, skin, std::numeric_limits<double>::infinity(), 0.0);
  ordered.Build(o.x.data(), o.radius.data(), o.cells, nullptr, ListRows::kAsVisited, 0, 2);
  EXPECT_EQ(ListPairs(ordered, o.slot_id), expected);
  EXPECT_EQ(ordered.stats().candidate_pairs, static_cast<std::int64_t>(expected.size()));
}

TEST(ParticleNeighbourList, ContainsEveryPairWithinContactPlusSkin) {
  CheckAgainstBruteForce(RandomConfiguration(2, {false, false, false}, 900, 40.0, 11), 0.3);
  CheckAgainstBruteForce(RandomConfiguration(2, {true, false, false}, 900, 40.0, 12), 0.5);
  CheckAgainstBruteForce(RandomConfiguration(3, {true, true, true}, 700, 12.0, 13), 0.4);
  CheckAgainstBruteForce(RandomConfiguration(1, {false, false, false}, 60, 80.0, 14), 0.6);
}

TEST(ParticleNeighbourList, SkinBoundAndStatistics) {
  const RandomConfiguration c(2, {false, false, false}, 200, 20.0, 15);
  const int n = c.model.count();
  const PeriodicBox box = PeriodicBox::Of(c.model);
  CellList cells;
  cells.Fit(c.x.data(), n, box, 2.0 * c.model.max_radius() + 0.4, 0, 1);
  std::vector<int> id(static_cast<std::size_t>(n));
  std::iota(id.begin(), id.end(), 0);
  cells.Sort(c.x.data(), id.data(), n, 1);
  NeighbourList list;
  list.Configure(box, n, 0.4, 0.5, 0.0);
  EXPECT_EQ(list.stats().shortest_rebuild_interval, -1);
  list.Build(c.x.data(), c.model.radius.data(), cells, cells.permutation().data(),
             ListRows::kSorted, 0, 1);
  // Moves below skin/4 need no build; the bound adds up.
  EXPECT_DOUBLE_EQ(list.BoundAfterPrediction(0.05, c.x.data(), 1), 0.05);
  EXPECT_FALSE(list.NeedsBuild(0.05));
  EXPECT_TRUE(list.NeedsBuild(0.11));
  // Above skin/4 the bound is computed exactly from the positions: here 0 (nothing moved).
  EXPECT_TRUE(list.Accept(0.09));
  EXPECT_EQ(list.BoundAfterPrediction(0.02, c.x.data(), 1), 0.0);
  // A step whose paths reach skin/2 is not accepted; the redo doubles a fresh list's skin up to
  // the limit, then refuses.
  EXPECT_FALSE(list.Accept(0.2));
  list.MarkPredicted();
  EXPECT_TRUE(list.PrepareRedo());
  EXPECT_EQ(list.skin(), 0.4);  // not fresh: the skin stays
  list.Build(c.x.data(), c.model.radius.data(), cells, cells.permutation().data(),
             ListRows::kSorted, 7, 1);
  EXPECT_TRUE(list.PrepareRedo());
  EXPECT_EQ(list.skin(), 0.5);
  EXPECT_FALSE(list.PrepareRedo());
  list.RelaxSkin();
  EXPECT_EQ(list.skin(), 0.4);
  list.Build(c.x.data(), c.model.radius.data(), cells, cells.permutation().data(),
             ListRows::kSorted, 9, 1);
  EXPECT_EQ(list.stats().builds, 3);
  EXPECT_EQ(list.stats().shortest_rebuild_interval, 2);
}

// The engine's build (storage in cell order, cell ranges found once per cell or per slot from
// the sort's ranks, chunks of slots on the threads, with and without the uniform-radius reach)
// gives the same rows in the same order for 1, 2 and 3 threads, and the same as visiting every
// slot's adjacent cells one by one (the members path with members[q] = q). Blocks of the
// automatic edge and of 3 to 5 cells (2D without periodic axes: the rows and columns at a block's
// edge take their candidates at fixed offsets, the next blocks' cells included, blocks of 3 the
// narrowest such).
TEST(ParticleNeighbourList, ParallelBuildEqualsSerialBuildEntryByEntry) {
  std::vector<RandomConfiguration> configs = {
      RandomConfiguration(2, {false, false, false}, 3000, 70.0, 21),
      RandomConfiguration(2, {true, true, false}, 3000, 70.0, 22),
      RandomConfiguration(3, {true, false, true}, 2000, 18.0, 23)};
  for (std::size_t i = 0; i < 3; ++i) {  // the same with every radius the largest
    configs.push_back(configs[i]);
    std::vector<double>& r = configs.back().model.radius;
    r.assign(r.size(), configs[i].model.max_radius());
  }
  for (const RandomConfiguration& c : configs) {
    for (const int block_cells : {0, 3, 4, 5}) {
      const int n = c.model.count();
      const double skin = 0.35;
      const CellOrdered o(c, skin, 1, block_cells);
      const bool uniform = std::all_of(o.radius.begin(), o.radius.end(),
                                       [&](double r) { return r == o.radius.front(); });
      std::vector<int> identity(static_cast<std::size_t>(n));
      std::iota(identity.begin(), identity.end(), 0);
      auto build = [&](const int* members, int threads) {
        NeighbourList list;
        list.Configure(o.box, n, skin, std::numeric_limits<double>::infinity(), 0.0);
        if (members == nullptr && uniform) list.AssumeUniformRadius(o.radius.front());
        list.Build(o.x.data(), o.radius.data(), o.cells, members, ListRows::kAsVisited, 0, threads);
        return list;
      };
      const NeighbourList serial = build(identity.data(), 1);
      const std::vector<int> rows(serial.row_start(), serial.row_start() + n + 1);
      const std::vector<int> nbr(serial.neighbours(), serial.neighbours() + serial.pairs());
      ASSERT_GT(serial.pairs(), n / 2);
      for (int threads : {1, 2, 3}) {
        const NeighbourList list = build(nullptr, threads);
        EXPECT_EQ(std::vector<int>(list.row_start(), list.row_start() + n + 1), rows) << threads;
        EXPECT_EQ(std::vector<int>(list.neighbours(), list.neighbours() + list.pairs()), nbr)
            << threads;
        if (o.box.any) {
          EXPECT_TRUE(std::equal(list.images(), list.images() + list.pairs(), serial.images()))
              << threads;
        }
        // The sweep's index of non-empty rows: exactly those slots, increasing.
        std::vector<int> active;
        for (int s = 0; s < n; ++s) {
          if (rows[static_cast<std::size_t>(s) + 1] > rows[static_cast<std::size_t>(s)]) {
            active.push_back(s);
          }
        }
        ASSERT_GT(active.size(), 0u);
        ASSERT_LT(active.size(), static_cast<std::size_t>(n));  // some rows are empty
        EXPECT_EQ(std::vector<int>(list.active_rows(), list.active_rows_end()), active) << threads;
      }
    }
  }
}

}  // namespace
}  // namespace moreau::particles::internal
