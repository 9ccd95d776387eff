#include "particles/colouring.h"

#include <algorithm>
#include <limits>

namespace moreau::particles::internal {

void Colouring::Assign(const CellList& cells) {
  const int* nb = cells.blocks_per_axis();
  const auto blocks = static_cast<std::size_t>(cells.blocks());
  std::vector<int> colour_of(blocks);
  colour_begin_.assign(kColours + 1, 0);
  for (std::size_t r = 0; r < blocks; ++r) {
    const std::int64_t b = cells.block_of_rank()[r];
    const int c[3] = {static_cast<int>(b % nb[0]), static_cast<int>((b / nb[0]) % nb[1]),
                      static_cast<int>(b / (static_cast<std::int64_t>(nb[0]) * nb[1]))};
    colour_of[r] = c[0] % 3 + 3 * (c[1] % 3) + 9 * (c[2] % 3);
    ++colour_begin_[static_cast<std::size_t>(colour_of[r]) + 1];
  }
  for (int c = 0; c < kColours; ++c) {
    colour_begin_[static_cast<std::size_t>(c) + 1] += colour_begin_[static_cast<std::size_t>(c)];
  }
  blocks_.assign(blocks, 0);
  std::vector<int> fill(colour_begin_.begin(), colour_begin_.end() - 1);
  for (std::size_t r = 0; r < blocks; ++r) {
    blocks_[static_cast<std::size_t>(fill[static_cast<std::size_t>(colour_of[r])]++)] =
        static_cast<int>(r);
  }
  AssignDependencies(cells, colour_of);
}

namespace {

// Whether some cell is adjacent (or equal) to a cell of block rank r1 and to one of block rank r2:
// on every axis their cell ranges come within two cells (periodic axes wrapped).
bool ShareAdjacentCell(const CellList& cells, int r1, int r2) {
  int o1[3], w1[3], o2[3], w2[3];
  cells.BlockShape(r1, o1, w1);
  cells.BlockShape(r2, o2, w2);
  const CellGrid& grid = cells.grid();
  for (int a = 0; a < grid.k; ++a) {
    int gap = std::numeric_limits<int>::max();
    for (const int shift : {-grid.nc[a], 0, grid.nc[a]}) {
      if (shift != 0 && !grid.periodic[a]) continue;
      const int lo2 = o2[a] + shift;
      gap = std::min(gap, std::max({0, lo2 - (o1[a] + w1[a] - 1), o1[a] - (lo2 + w2[a] - 1)}));
    }
    if (gap > 2) return false;
  }
  return true;
}

}  // namespace

void Colouring::AssignDependencies(const CellList& cells, const std::vector<int>& colour_of) {
  const int* nb = cells.blocks_per_axis();
  const int k = cells.grid().k;
  const auto blocks = static_cast<std::size_t>(cells.blocks());
  std::vector<int> entry_of_rank(blocks), rank_of_block(blocks);
  for (std::size_t q = 0; q < blocks; ++q)
    entry_of_rank[static_cast<std::size_t>(blocks_[q])] = static_cast<int>(q);
  for (std::size_t r = 0; r < blocks; ++r) {
    rank_of_block[static_cast<std::size_t>(cells.block_of_rank()[r])] = static_cast<int>(r);
  }
  dependency_begin_.assign(blocks + 1, 0);
  dependencies_.clear();
  std::vector<int> found;
  for (std::size_t q = 0; q < blocks; ++q) {
    const int r = blocks_[q];
    const std::int64_t b = cells.block_of_rank()[static_cast<std::size_t>(r)];
    const int c[3] = {static_cast<int>(b % nb[0]), static_cast<int>((b / nb[0]) % nb[1]),
                      static_cast<int>(b / (static_cast<std::int64_t>(nb[0]) * nb[1]))};
    found.clear();
    const int reach[3] = {2, k >= 2 ? 2 : 0, k >= 3 ? 2 : 0};
    for (int dz = -reach[2]; dz <= reach[2]; ++dz) {
      for (int dy = -reach[1]; dy <= reach[1]; ++dy) {
        for (int dx = -reach[0]; dx <= reach[0]; ++dx) {
          int o[3] = {c[0] + dx, c[1] + dy, c[2] + dz};
          bool inside = true;
          for (int a = 0; a < 3; ++a) {
            if (o[a] >= 0 && o[a] < nb[a]) continue;
            if (a < k && cells.grid().periodic[a]) {
              o[a] = ((o[a] % nb[a]) + nb[a]) % nb[a];
            } else {
              inside = false;
            }
          }
          if (!inside) continue;
          const std::int64_t ob = (static_cast<std::int64_t>(o[2]) * nb[1] + o[1]) * nb[0] + o[0];
          const int oq =
              entry_of_rank[static_cast<std::size_t>(rank_of_block[static_cast<std::size_t>(ob)])];
          if (colour_of[static_cast<std::size_t>(blocks_[static_cast<std::size_t>(oq)])] <
                  colour_of[static_cast<std::size_t>(r)] &&
              ShareAdjacentCell(cells, r, blocks_[static_cast<std::size_t>(oq)])) {
            found.push_back(oq);
          }
        }
      }
    }
    std::sort(found.begin(), found.end());
    found.erase(std::unique(found.begin(), found.end()), found.end());
    dependencies_.insert(dependencies_.end(), found.begin(), found.end());
    dependency_begin_[q + 1] = static_cast<int>(dependencies_.size());
  }
}

}  // namespace moreau::particles::internal
