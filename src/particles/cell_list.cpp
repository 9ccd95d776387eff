#include "particles/cell_list.h"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

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

// Counting sort by cell rank, then each cell's slots by id; the order (cell rank, then id) is
// unique, so the permutation does not depend on the thread count, nor on the order in which a
// cell's slots are scattered. Thread t has the contiguous chunk of slots [sb, se) and the cells
// [bound[t], bound[t + 1]) from the cell of its chunk's first slot on: with storage in the previous
// build's cell order most of a chunk's slots lie in its own cells. Each thread counts its chunk's
// keys in its own cells (one count per cell in all: no threads × cells array to clear) and lists
// the other (foreign) slots; then it adds the foreign slots of the other chunks in its cells,
// turns counts into offsets, scatters its own and those foreign slots, and sorts its cells by id.
void CellList::Sort(const double* x, const int* id, int n, int threads) {
  const std::int64_t cells = this->cells();
  const int k = grid_.k;
  const int T = threads;
  key_.resize(static_cast<std::size_t>(n));
  perm_.resize(static_cast<std::size_t>(n));
  sorted_rank_.resize(static_cast<std::size_t>(n));
  if (foreign_.size() < static_cast<std::size_t>(T)) foreign_.resize(static_cast<std::size_t>(T));
  std::vector<std::int64_t> bound(static_cast<std::size_t>(T) + 1, cells);
  std::vector<std::int64_t> partial(static_cast<std::size_t>(T) + 1, 0);
  std::vector<double> range_lo(3 * static_cast<std::size_t>(T), 0.0);
  std::vector<double> range_hi(3 * static_cast<std::size_t>(T), 0.0);
  bound[0] = 0;
  for (int t = 1; t < T; ++t) {
    const std::int64_t sb = static_cast<std::int64_t>(t) * n / T;
    const std::int64_t first = sb < n ? rank(grid_.CellOf(x + k * sb)) : cells;
    bound[static_cast<std::size_t>(t)] = std::max(bound[static_cast<std::size_t>(t) - 1], first);
  }
  InTeam(T, [&] {
    const int t = T > 1 ? omp_get_thread_num() : 0;
    const int sb = static_cast<int>(static_cast<std::int64_t>(t) * n / T);
    const int se = static_cast<int>(static_cast<std::int64_t>(t + 1) * n / T);
    const std::int64_t cb = bound[static_cast<std::size_t>(t)];
    const std::int64_t ce = bound[static_cast<std::size_t>(t) + 1];
    // cell_start_ holds each cell's count, then its end, then (after the scatter) its start.
    std::int32_t* cnt = cell_start_.data();
    std::fill(cnt + cb, cnt + ce, 0);
    std::vector<int>& mine = foreign_[static_cast<std::size_t>(t)];
    mine.clear();
    std::int64_t total = DispatchDimension(k, [&](auto kk) {
      return CountKeys<kk>(x, sb, se, cb, ce, &mine, &range_lo[3 * static_cast<std::size_t>(t)],
                           &range_hi[3 * static_cast<std::size_t>(t)]);
    });
#pragma omp barrier
    auto for_foreign = [&](auto&& f) {  // the other chunks' slots in this thread's cells
      for (int u = 0; u < T; ++u) {
        if (u == t) continue;
        for (const int s : foreign_[static_cast<std::size_t>(u)]) {
          const int key = key_[static_cast<std::size_t>(s)];
          if (key >= cb && key < ce) f(s, key);
        }
      }
    };
    for_foreign([&](int, int key) {
      ++cnt[key];
      ++total;
    });
    partial[static_cast<std::size_t>(t) + 1] = total;
#pragma omp barrier
#pragma omp single
    for (int u = 0; u < T; ++u)
      partial[static_cast<std::size_t>(u) + 1] += partial[static_cast<std::size_t>(u)];
    std::int64_t run = partial[static_cast<std::size_t>(t)];
    std::int64_t c = cb;  // in place: each cell's end
#if defined(__SSE2__)
    // Four cells a step, in 32-bit lanes (the ends are at most n < 2^31): the vector's prefix sums
    // by two shifted adds, plus the end before it.
    __m128i carry = _mm_set1_epi32(static_cast<std::int32_t>(run));
    for (; c + 4 <= ce; c += 4) {
      __m128i v = _mm_loadu_si128(reinterpret_cast<const __m128i*>(cnt + c));
      v = _mm_add_epi32(v, _mm_slli_si128(v, 4));
      v = _mm_add_epi32(v, _mm_slli_si128(v, 8));
      v = _mm_add_epi32(v, carry);
      _mm_storeu_si128(reinterpret_cast<__m128i*>(cnt + c), v);
      carry = _mm_shuffle_epi32(v, 0xff);
    }
    run = _mm_cvtsi128_si32(carry);
#endif
    for (; c < ce; ++c) {
      run += cnt[c];
      cnt[c] = static_cast<std::int32_t>(run);
    }
    if (t == T - 1) cell_start_[static_cast<std::size_t>(cells)] = n;
    // The scatter fills each cell from its end, in the reverse of the order own slots, then the
    // other chunks' (in chunk order): the cells' slots end up in that order and their ends turn
    // into their starts.
    int* perm = perm_.data();
    std::int32_t* sorted_rank = sorted_rank_.data();
    auto place = [&](int s, int key) {
      const int at = --cnt[key];
      perm[at] = s;
      sorted_rank[at] = key;
    };
    for (int u = T - 1; u >= 0; --u) {
      if (u == t) continue;
      const std::vector<int>& other = foreign_[static_cast<std::size_t>(u)];
      for (auto it = other.rbegin(); it != other.rend(); ++it) {
        const int key = key_[static_cast<std::size_t>(*it)];
        if (key >= cb && key < ce) place(*it, key);
      }
    }
    for (int s = se - 1; s >= sb; --s) {
      const int key = key_[static_cast<std::size_t>(s)];
      if (key >= cb && key < ce) place(s, key);
    }
#pragma omp barrier
    SortCellsById(id, cb, ce);
  });
  for (int a = 0; a < k; ++a) {  // the axis ranges, as AxisRanges finds them
    sorted_lo_[a] = std::numeric_limits<double>::infinity();
    sorted_hi_[a] = -std::numeric_limits<double>::infinity();
    for (int t = 0; t < T; ++t) {
      sorted_lo_[a] = std::min(sorted_lo_[a], range_lo[3 * static_cast<std::size_t>(t) + a]);
      sorted_hi_[a] = std::max(sorted_hi_[a], range_hi[3 * static_cast<std::size_t>(t) + a]);
    }
  }
}

bool CellList::FitAndSort(const double* x, const int* id, int n, const PeriodicBox& box,
                          double reach, int block_cells, int threads) {
  const int k = box.k;
  const bool all_periodic = std::all_of(box.periodic, box.periodic + k, [](bool p) { return p; });
  if (!have_geometry_ || reach_ != reach || all_periodic) {
    const bool changed = Fit(x, n, box, reach, block_cells, threads);
    Sort(x, id, n, threads);
    return changed;
  }
  // A sort with the old geometry is valid for any positions (those outside the grid are clamped
  // into its edge cells) and finds the bounding box Fit would; only when that box calls for a new
  // geometry is the grid refitted and sorted again.
  Sort(x, id, n, threads);
  double lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
  std::copy(sorted_lo_, sorted_lo_ + k, lo);
  std::copy(sorted_hi_, sorted_hi_ + k, hi);
  if (!RefitUnlessKept(lo, hi, n, box, reach, block_cells)) return false;
  Sort(x, id, n, threads);
  return true;
}

// Slots [sb, se): their keys (cell ranks) into key_, counted in cell_start_ when in the cells
// [cb, ce), else listed in *foreign. Returns the number counted.
template <int K>
std::int64_t CellList::CountKeys(const double* x, int sb, int se, std::int64_t cb, std::int64_t ce,
                                 std::vector<int>* foreign, double* lo, double* hi) {
  const CellGrid grid = grid_;
  const std::int32_t* rank = cell_rank_.data();
  std::int32_t* cnt = cell_start_.data();
  int* key = key_.data();
  std::int64_t counted = 0;
  double low[K], high[K];
  for (int a = 0; a < K; ++a) {
    low[a] = std::numeric_limits<double>::infinity();
    high[a] = -std::numeric_limits<double>::infinity();
  }
  auto count = [&](int s, int r) {
    key[s] = r;
    if (r >= cb && r < ce) [[likely]] {
      ++cnt[r];
      ++counted;
    } else {
      foreign->push_back(s);
    }
  };
  int first = sb;
#if defined(__SSE2__)
  if constexpr (K == 2) {
    // A 2D position is one SSE2 vector: the same operations as the loop below, lane by lane
    // (std::min(m, v) is minpd(v, m), NaN included; Coord's clamps are a max with 0, NaN giving
    // 0, and a min with nc − 1, whose truncation is Coord's nc − 1 from t ≥ nc − 1 on).
    const __m128d origin = _mm_loadu_pd(grid.lo);
    const __m128d inv = _mm_loadu_pd(grid.inv);
    const __m128d top = _mm_set_pd(grid.nc[1] - 1, grid.nc[0] - 1);
    const __m128d zero = _mm_setzero_pd();
    __m128d low2 = _mm_set1_pd(std::numeric_limits<double>::infinity());
    __m128d high2 = _mm_set1_pd(-std::numeric_limits<double>::infinity());
    const std::int64_t row = grid.nc[0];
    for (int s = sb; s < se; ++s) {
      const __m128d v = _mm_loadu_pd(x + 2 * static_cast<std::ptrdiff_t>(s));
      low2 = _mm_min_pd(v, low2);
      high2 = _mm_max_pd(v, high2);
      const __m128d t = _mm_min_pd(_mm_max_pd(_mm_mul_pd(_mm_sub_pd(v, origin), inv), zero), top);
      const __m128i c = _mm_cvttpd_epi32(t);
      const int cx = _mm_cvtsi128_si32(c);
      const int cy = _mm_cvtsi128_si32(_mm_shuffle_epi32(c, 1));
      count(s, rank[cy * row + cx]);
    }
    _mm_storeu_pd(low, low2);
    _mm_storeu_pd(high, high2);
    first = se;
  }
#endif
  for (int s = first; s < se; ++s) {
    int c[3] = {0, 0, 0};
    for (int a = 0; a < K; ++a) {
      const double v = x[static_cast<std::ptrdiff_t>(K) * s + a];
      low[a] = std::min(low[a], v);
      high[a] = std::max(high[a], v);
      c[a] = grid.Coord(a, v);
    }
    count(s, rank[grid.Index(c[0], c[1], c[2])]);
  }
  std::copy(low, low + K, lo);
  std::copy(high, high + K, hi);
  return counted;
}

// Insertion sort by id of the slots of each cell of rank in [cb, ce), walking the entries rather
// than the cells: an entry already after a smaller id of its cell (or first in it) stays, which is
// most entries, since the scatter keeps the storage order and storage is in the last build's
// (cell, id) order. No branch per cell, empty or not, and none per entry on the cell boundary.
void CellList::SortCellsById(const int* id, std::int64_t cb, std::int64_t ce) {
  const std::int64_t qb = cell_start_[static_cast<std::size_t>(cb)];
  const std::int64_t qe = cell_start_[static_cast<std::size_t>(ce)];
  int* perm = perm_.data();
  const std::int32_t* rank = sorted_rank_.data();
  // First the entries that share their cell with the one before (about one in seven at 10^6
  // disks), listed without a branch in key_'s entries [qb, qe), free once the slots are
  // scattered; then only those are compared. A branch on the cell boundary per entry would be
  // mispredicted at about every seventh.
  int* same = key_.data() + qb;
  std::int64_t count = 0;
  std::int64_t q = qb + 1;
#if defined(__SSE2__)
  // Four entries a step: their ranks against the ones before as a 4-bit mask, and the entries
  // with an equal rank written in order by one 4-entry store. That store reaches at most entry
  // q + 2 of key_, before qe: this thread's entries.
  for (; q + 4 <= qe; q += 4) {
    const __m128i before = _mm_loadu_si128(reinterpret_cast<const __m128i*>(rank + q - 1));
    const __m128i here = _mm_loadu_si128(reinterpret_cast<const __m128i*>(rank + q));
    const int equal = _mm_movemask_ps(_mm_castsi128_ps(_mm_cmpeq_epi32(before, here)));
    count += CompressStore(equal, static_cast<int>(q), same + count);
  }
#endif
  for (; q < qe; ++q) {
    same[count] = static_cast<int>(q);
    count += rank[q - 1] == rank[q] ? 1 : 0;
  }
  for (std::int64_t k = 0; k < count; ++k) {
    const std::int64_t i = same[k];
    const int v = perm[i];
    const std::int32_t r = rank[i];
    if (id[perm[i - 1]] < id[v]) continue;
    std::int64_t j = i;
    while (j > qb && rank[j - 1] == r && id[perm[j - 1]] > id[v]) {
      perm[j] = perm[j - 1];
      --j;
    }
    perm[j] = v;
  }
}

}  // namespace moreau::particles::internal
