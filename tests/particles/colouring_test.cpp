// The colouring: no particle is touched by two blocks of one colour (the sweep's parallel
// safety), every block has one colour, and blocks of different colours that touch one particle
// are ordered by the dependency lists.
#include "particles/colouring.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>

#include "particles/neighbour_list.h"
#include "particles/part_fixtures.h"

namespace moreau::particles::internal {
namespace {

using testing::RandomConfiguration;

// The dependency order (ForEachBlockInDependencyOrder): two blocks that touch one slot are
// ordered, the one of larger colour listing the other; every dependency has a smaller colour.
void CheckDependencyOrder(const Colouring& colouring, const CellList& cells,
                          const NeighbourList& list, int n) {
  std::vector<int> colour_of_entry(static_cast<std::size_t>(colouring.blocks()));
  for (int colour = 0; colour < Colouring::kColours; ++colour) {
    for (int q = colouring.colour_begin(colour); q < colouring.colour_begin(colour + 1); ++q)
      colour_of_entry[static_cast<std::size_t>(q)] = colour;
  }
  auto depends = [&](int later, int earlier) {
    const int* d = colouring.dependencies();
    return std::find(d + colouring.dependency_begin(later),
                     d + colouring.dependency_begin(later + 1),
                     earlier) != d + colouring.dependency_begin(later + 1);
  };
  std::vector<std::vector<int>> touched_by(static_cast<std::size_t>(n));
  for (int q = 0; q < colouring.blocks(); ++q) {
    const int r = colouring.block_rank(q);
    for (int d = colouring.dependency_begin(q); d < colouring.dependency_begin(q + 1); ++d) {
      EXPECT_LT(colour_of_entry[static_cast<std::size_t>(colouring.dependencies()[d])],
                colour_of_entry[static_cast<std::size_t>(q)]);
    }
    for (int s = cells.BlockSlotBegin(r); s < cells.BlockSlotBegin(r + 1); ++s) {
      touched_by[static_cast<std::size_t>(s)].push_back(q);
      for (int p = list.row_start()[s]; p < list.row_start()[s + 1]; ++p)
        touched_by[static_cast<std::size_t>(list.neighbours()[p])].push_back(q);
    }
  }
  std::int64_t ordered_pairs = 0;
  for (const std::vector<int>& blocks : touched_by) {
    for (const int q1 : blocks) {
      for (const int q2 : blocks) {
        if (colour_of_entry[static_cast<std::size_t>(q1)] >=
            colour_of_entry[static_cast<std::size_t>(q2)]) {
          continue;
        }
        EXPECT_TRUE(depends(q2, q1)) << "entry " << q2 << " does not wait for entry " << q1;
        ++ordered_pairs;
      }
    }
  }
  EXPECT_GT(ordered_pairs, 0);
}

void CheckColouring(const RandomConfiguration& c, int block_cells) {
  const int n = c.model.count();
  const int k = c.model.dimension;
  const PeriodicBox box = PeriodicBox::Of(c.model);
  const double skin = 0.5 * c.model.max_radius();
  CellList cells;
  cells.Fit(c.x.data(), n, box, 2.0 * c.model.max_radius() + skin, block_cells, 1);
  std::vector<int> id(static_cast<std::size_t>(n));
  std::iota(id.begin(), id.end(), 0);
  cells.Sort(c.x.data(), id.data(), n, 1);
  std::vector<double> x(c.x.size()), radius(static_cast<std::size_t>(n));
  for (int s = 0; s < n; ++s) {
    const int o = cells.permutation()[static_cast<std::size_t>(s)];
    for (int a = 0; a < k; ++a)
      x[static_cast<std::size_t>(k * s + a)] = c.x[static_cast<std::size_t>(k * o + a)];
    radius[static_cast<std::size_t>(s)] = c.model.radius[static_cast<std::size_t>(o)];
  }
  NeighbourList list;
  list.Configure(box, n, skin, std::numeric_limits<double>::infinity(), 0.0);
  list.Build(x.data(), radius.data(), cells, nullptr, ListRows::kAsVisited, 0, 1);
  Colouring colouring;
  colouring.Assign(cells);
  // Every block once; per colour, the block (by rank) that touches each slot.
  std::vector<int> seen(static_cast<std::size_t>(cells.blocks()), 0);
  int colours_used = 0;
  for (int colour = 0; colour < Colouring::kColours; ++colour) {
    if (colouring.colour_begin(colour) < colouring.colour_begin(colour + 1)) ++colours_used;
    std::vector<int> owner(static_cast<std::size_t>(n), -1);
    auto touch = [&](int slot, int block) {
      int& o = owner[static_cast<std::size_t>(slot)];
      EXPECT_TRUE(o < 0 || o == block) << "slot " << slot << " touched by blocks " << o << " and "
                                       << block << " of colour " << colour;
      o = block;
    };
    for (int q = colouring.colour_begin(colour); q < colouring.colour_begin(colour + 1); ++q) {
      const int r = colouring.block_rank(q);
      ++seen[static_cast<std::size_t>(r)];
      for (int s = cells.BlockSlotBegin(r); s < cells.BlockSlotBegin(r + 1); ++s) {
        touch(s, r);
        for (int p = list.row_start()[s]; p < list.row_start()[s + 1]; ++p)
          touch(list.neighbours()[p], r);
      }
    }
  }
  for (const int count : seen) EXPECT_EQ(count, 1);
  CheckDependencyOrder(colouring, cells, list, n);
  EXPECT_EQ(colours_used, k == 2 ? 9 : 27);
  EXPECT_GT(list.pairs(), n / 2);
}

TEST(ParticleColouring, NoTwoBlocksOfOneColourShareAParticle) {
  CheckColouring(RandomConfiguration(2, {false, false, false}, 3000, 70.0, 21), 2);
  CheckColouring(RandomConfiguration(2, {true, true, false}, 3000, 70.0, 22), 3);
  CheckColouring(RandomConfiguration(3, {true, false, true}, 3000, 20.0, 23), 2);
  // Blocks one cell wide: blocks two apart touch the slots of the one between.
  CheckColouring(RandomConfiguration(2, {false, true, false}, 3000, 70.0, 24), 1);
}

}  // namespace
}  // namespace moreau::particles::internal
