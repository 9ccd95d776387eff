// The cell grid and CellList's geometry: the fit, the blocks in Morton order and the cell ranks.
// The sort into cells is cell_sort.cpp's.
#include "particles/cell_list.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

#include "moreau/common/error.h"
#include "particles/parallel.h"

namespace moreau::particles::internal {

std::uint64_t Morton(const int* c, int k) {
  std::uint64_t code = 0;
  for (int bit = 0; bit < 21; ++bit) {
    for (int a = 0; a < k; ++a) {
      code |= ((static_cast<std::uint64_t>(c[a]) >> bit) & 1u) << (k * bit + a);
    }
  }
  return code;
}

void CellGrid::Fit(int dimension, const double* lo_in, const double* hi_in, const PeriodicBox& box,
                   double min_edge, std::int64_t max_cells) {
  k = dimension;
  std::int64_t total = 1;
  for (int a = 0; a < k; ++a) {
    periodic[a] = box.periodic[a];
    const double span = hi_in[a] - lo_in[a];
    int count = static_cast<int>(std::clamp(std::floor(span / min_edge), 1.0, 1.0e6));
    while (count > 1 && span / count < min_edge) --count;
    nc[a] = count;
    lo[a] = lo_in[a];
    total *= count;
  }
  while (total > max_cells) {
    total = 1;
    for (int a = 0; a < k; ++a) {
      nc[a] = std::max(1, nc[a] / 2);
      total *= nc[a];
    }
  }
  for (int a = 0; a < k; ++a) {
    const double span = periodic[a] ? box.len[a] : hi_in[a] - lo_in[a];
    edge[a] = span / nc[a];
    inv[a] = nc[a] / span;
  }
  for (int a = k; a < 3; ++a) {
    nc[a] = 1;
    lo[a] = 0.0;
    edge[a] = 1.0;
    inv[a] = 0.0;
    periodic[a] = false;
  }
}

namespace {

// The smallest and largest coordinate on each of the K axes of the n points x, in one pass.
template <int K>
void AxisRanges(const double* x, int n, int threads, double* lo, double* hi) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  std::vector<double> mn(static_cast<std::size_t>(threads) * K, kInf);
  std::vector<double> mx(static_cast<std::size_t>(threads) * K, -kInf);
  ParallelFor(threads, 0, threads, [&](std::int64_t t) {
    double low[K], high[K];
    for (int a = 0; a < K; ++a) {
      low[a] = kInf;
      high[a] = -kInf;
    }
    for (std::int64_t s = t * n / threads; s < (t + 1) * n / threads; ++s) {
      for (int a = 0; a < K; ++a) {
        low[a] = std::min(low[a], x[K * s + a]);
        high[a] = std::max(high[a], x[K * s + a]);
      }
    }
    std::copy(low, low + K, mn.begin() + t * K);
    std::copy(high, high + K, mx.begin() + t * K);
  });
  for (int a = 0; a < K; ++a) {
    lo[a] = kInf;
    hi[a] = -kInf;
    for (int t = 0; t < threads; ++t) {
      lo[a] = std::min(lo[a], mn[static_cast<std::size_t>(t * K + a)]);
      hi[a] = std::max(hi[a], mx[static_cast<std::size_t>(t * K + a)]);
    }
  }
}

}  // namespace

bool CellList::KeepsGeometry(const double* lo, const double* hi, double reach) const {
  if (!have_geometry_ || reach_ != reach) return false;
  for (int a = 0; a < grid_.k; ++a) {
    if (grid_.periodic[a]) continue;
    const double ghi = grid_.lo[a] + grid_.nc[a] * grid_.edge[a];
    const double span = hi[a] - lo[a];
    if (!(lo[a] >= grid_.lo[a] && hi[a] <= ghi &&
          (ghi - grid_.lo[a]) <= 1.5 * span + 8.0 * reach)) {
      return false;
    }
  }
  return true;
}

bool CellList::Fit(const double* x, int n, const PeriodicBox& box, double reach, int block_cells,
                   int threads) {
  const int k = box.k;
  double lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
  if (!std::all_of(box.periodic, box.periodic + k, [](bool p) { return p; })) {
    DispatchDimension(k, [&](auto kk) { AxisRanges<kk>(x, n, threads, lo, hi); });
  }
  return RefitUnlessKept(lo, hi, n, box, reach, block_cells);
}

// The bounding box lo, hi of the non-periodic axes (periodic ones are the box's): refits unless
// the geometry is kept; true when refitted.
bool CellList::RefitUnlessKept(double* lo, double* hi, int n, const PeriodicBox& box, double reach,
                               int block_cells) {
  for (int a = 0; a < box.k; ++a) {
    if (box.periodic[a]) {
      lo[a] = box.lo[a];
      hi[a] = box.lo[a] + box.len[a];
    }
  }
  if (KeepsGeometry(lo, hi, reach)) return false;
  FitRecord fit;
  std::copy(lo, lo + 3, fit.lo);
  std::copy(hi, hi + 3, fit.hi);
  fit.reach = reach;
  Refit(fit, n, box, block_cells);
  return true;
}

void CellList::Refit(const FitRecord& fit, int n, const PeriodicBox& box, int block_cells) {
  const int k = box.k;
  fit_ = fit;
  have_geometry_ = true;
  reach_ = fit.reach;
  double lo[3], hi[3];
  for (int a = 0; a < 3; ++a) {
    const bool widen = a < k && !box.periodic[a];
    lo[a] = widen ? fit.lo[a] - 2.0 * fit.reach : fit.lo[a];
    hi[a] = widen ? fit.hi[a] + 2.0 * fit.reach : fit.hi[a];
  }
  // At most max(64, 4n) cells, and fewer than 2^31 (32-bit ranks and offsets).
  grid_.Fit(k, lo, hi, box, fit.reach,
            std::min<std::int64_t>(std::max<std::int64_t>(64, 4 * static_cast<std::int64_t>(n)),
                                   std::numeric_limits<std::int32_t>::max() - 1));
  ChooseBlocks(block_cells);
  RankBlocks();
  RankCells();
  cell_start_.assign(static_cast<std::size_t>(grid_.cells()) + 1, 0);
}

// Block edge: as given, or automatic from the cell count alone (never from the thread count): as
// large as possible (long runs of consecutive memory per block; up to 64 cells in 2D, 16 in 3D)
// while keeping ≥ 8 blocks per colour for load balance. On a periodic axis 1, 2 or a multiple of
// 3 blocks, so that the colouring b mod 3 separates same-colour blocks across the boundary too.
void CellList::ChooseBlocks(int block_cells) {
  const auto total = static_cast<double>(grid_.cells());
  if (block_cells > 0) {
    block_edge_ = block_cells;
  } else if (grid_.k == 2) {
    block_edge_ = static_cast<int>(std::clamp(std::floor(std::sqrt(total / 72.0)), 2.0, 64.0));
  } else {
    block_edge_ = static_cast<int>(std::clamp(std::floor(std::cbrt(total / 216.0)), 2.0, 16.0));
  }
  for (int a = 0; a < 3; ++a) {
    int b = (grid_.nc[a] + block_edge_ - 1) / block_edge_;
    if (a < grid_.k && grid_.periodic[a] && b >= 3) b = 3 * (b / 3);
    nb_[a] = std::max(1, b);
  }
}

namespace {

void BlockCoords(std::int64_t b, const int* nb, int* c) {
  c[0] = static_cast<int>(b % nb[0]);
  c[1] = static_cast<int>((b / nb[0]) % nb[1]);
  c[2] = static_cast<int>(b / (static_cast<std::int64_t>(nb[0]) * nb[1]));
}

// Block b covers cells [BlockLo(b), BlockLo(b + 1)) of an axis with nc cells and nb blocks.
int BlockLo(int nc, int nb, int b) {
  return static_cast<int>(static_cast<std::int64_t>(b) * nc / nb);
}

}  // namespace

// Blocks in Morton order; the cells of the block of rank r are block_cell_begin_[r] onwards.
void CellList::RankBlocks() {
  const std::int64_t blocks = static_cast<std::int64_t>(nb_[0]) * nb_[1] * nb_[2];
  std::vector<std::pair<std::uint64_t, std::int64_t>> order(static_cast<std::size_t>(blocks));
  for (std::int64_t b = 0; b < blocks; ++b) {
    int c[3];
    BlockCoords(b, nb_, c);
    order[static_cast<std::size_t>(b)] = {Morton(c, grid_.k), b};
  }
  std::sort(order.begin(), order.end());
  block_of_rank_.resize(static_cast<std::size_t>(blocks));
  rank_of_block_.resize(static_cast<std::size_t>(blocks));
  block_cell_begin_.assign(static_cast<std::size_t>(blocks) + 1, 0);
  for (std::int64_t r = 0; r < blocks; ++r) {
    const std::int64_t b = order[static_cast<std::size_t>(r)].second;
    block_of_rank_[static_cast<std::size_t>(r)] = b;
    rank_of_block_[static_cast<std::size_t>(b)] = r;
    int c[3];
    BlockCoords(b, nb_, c);
    std::int64_t cells = 1;
    for (int a = 0; a < 3; ++a) {
      cells *= BlockLo(grid_.nc[a], nb_[a], c[a] + 1) - BlockLo(grid_.nc[a], nb_[a], c[a]);
    }
    block_cell_begin_[static_cast<std::size_t>(r) + 1] =
        block_cell_begin_[static_cast<std::size_t>(r)] + cells;
  }
}

void CellList::BlockShape(std::int64_t r, int* origin, int* width) const {
  int c[3];
  BlockCoords(block_of_rank_[static_cast<std::size_t>(r)], nb_, c);
  for (int a = 0; a < 3; ++a) {
    origin[a] = BlockLo(grid_.nc[a], nb_[a], c[a]);
    width[a] = BlockLo(grid_.nc[a], nb_[a], c[a] + 1) - origin[a];
  }
}

std::int64_t CellList::AdjacentBlock(std::int64_t r, int a, int step) const {
  int c[3];
  BlockCoords(block_of_rank_[static_cast<std::size_t>(r)], nb_, c);
  c[a] += step;
  if (c[a] < 0 || c[a] >= nb_[a]) return -1;
  const std::int64_t b = (static_cast<std::int64_t>(c[2]) * nb_[1] + c[1]) * nb_[0] + c[0];
  return rank_of_block_[static_cast<std::size_t>(b)];
}

// Cell ranks: the blocks' ranks, cells row-major inside a block. Cell c of an axis lies in block
// ((c + 1) nb − 1) / nc, the largest b with BlockLo(b) ≤ c.
void CellList::RankCells() {
  const int* nc = grid_.nc;
  auto block_of = [&](int a, int c) {
    return static_cast<int>(((static_cast<std::int64_t>(c) + 1) * nb_[a] - 1) / nc[a]);
  };
  cell_rank_.assign(static_cast<std::size_t>(grid_.cells()), 0);
  for (int z = 0; z < nc[2]; ++z) {
    const int bz = block_of(2, z);
    for (int y = 0; y < nc[1]; ++y) {
      const int by = block_of(1, y);
      for (int xx = 0; xx < nc[0]; ++xx) {
        const int bx = block_of(0, xx);
        const int lx = xx - BlockLo(nc[0], nb_[0], bx);
        const int ly = y - BlockLo(nc[1], nb_[1], by);
        const int lz = z - BlockLo(nc[2], nb_[2], bz);
        const int wx = BlockLo(nc[0], nb_[0], bx + 1) - BlockLo(nc[0], nb_[0], bx);
        const int wy = BlockLo(nc[1], nb_[1], by + 1) - BlockLo(nc[1], nb_[1], by);
        const std::int64_t b = (static_cast<std::int64_t>(bz) * nb_[1] + by) * nb_[0] + bx;
        const std::int64_t r = rank_of_block_[static_cast<std::size_t>(b)];
        cell_rank_[static_cast<std::size_t>(grid_.Index(xx, y, z))] =
            static_cast<std::int32_t>(block_cell_begin_[static_cast<std::size_t>(r)] +
                                      (static_cast<std::int64_t>(lz) * wy + ly) * wx + lx);
      }
    }
  }
  // The ranks are a permutation of the cells (an internal invariant the colouring relies on).
  std::vector<char> seen(cell_rank_.size(), 0);
  for (const std::int64_t r : cell_rank_) {
    MOREAU_ASSERT(r >= 0 && r < grid_.cells() && !seen[static_cast<std::size_t>(r)]);
    seen[static_cast<std::size_t>(r)] = 1;
  }
}

}  // namespace moreau::particles::internal
