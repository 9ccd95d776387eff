// CellList's sort (cell_list.h): slots into cells by a parallel counting sort, then by id within
// each cell, deterministic for any thread count; FitAndSort, which finds the bounding box in the
// same pass. The grid, its blocks and the cell ranks are cell_list.cpp's.
#include <omp.h>

#include <algorithm>
#include <limits>
#include <vector>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "particles/cell_list.h"
#include "particles/parallel.h"

namespace moreau::particles::internal {

// One thread's part of Sort, run by each thread of the team: the team's shared state by
// reference (as a lambda capturing it would). cell_start_ holds each cell's count, then its end,
// then (after the scatter) its start.
struct CellList::SortTeam {
  const int& T;
  const int& n;
  std::vector<std::int64_t>& bound;
  CellList& list;
  const int& k;
  const double* const& x;
  std::vector<double>& range_lo;
  std::vector<double>& range_hi;
  std::vector<std::int64_t>& partial;
  const std::int64_t& cells;
  const int* const& id;

  void operator()() const {
    const int t = T > 1 ? omp_get_thread_num() : 0;
    const int sb = static_cast<int>(static_cast<std::int64_t>(t) * n / T);
    const int se = static_cast<int>(static_cast<std::int64_t>(t + 1) * n / T);
    const std::int64_t cb = bound[static_cast<std::size_t>(t)];
    const std::int64_t ce = bound[static_cast<std::size_t>(t) + 1];
    std::int32_t* cnt = list.cell_start_.data();
    std::fill(cnt + cb, cnt + ce, 0);
    std::vector<int>& mine = list.foreign_[static_cast<std::size_t>(t)];
    mine.clear();
    std::int64_t total = DispatchDimension(k, [&](auto kk) {
      return list.template CountKeys<kk>(x, sb, se, cb, ce, &mine,
                                         &range_lo[3 * static_cast<std::size_t>(t)],
                                         &range_hi[3 * static_cast<std::size_t>(t)]);
    });
#pragma omp barrier
    auto for_foreign = [&](auto&& f) {  // the other chunks' slots in this thread's cells
      for (int u = 0; u < T; ++u) {
        if (u == t) continue;
        for (const int s : list.foreign_[static_cast<std::size_t>(u)]) {
          const int key = list.key_[static_cast<std::size_t>(s)];
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
    if (t == T - 1) list.cell_start_[static_cast<std::size_t>(cells)] = n;
    // The scatter fills each cell from its end, in the reverse of the order own slots, then the
    // other chunks' (in chunk order): the cells' slots end up in that order and their ends turn
    // into their starts.
    int* perm = list.perm_.data();
    std::int32_t* sorted_rank = list.sorted_rank_.data();
    auto place = [&](int s, int key) {
      const int at = --cnt[key];
      perm[at] = s;
      sorted_rank[at] = key;
    };
    for (int u = T - 1; u >= 0; --u) {
      if (u == t) continue;
      const std::vector<int>& other = list.foreign_[static_cast<std::size_t>(u)];
      for (auto it = other.rbegin(); it != other.rend(); ++it) {
        const int key = list.key_[static_cast<std::size_t>(*it)];
        if (key >= cb && key < ce) place(*it, key);
      }
    }
    for (int s = se - 1; s >= sb; --s) {
      const int key = list.key_[static_cast<std::size_t>(s)];
      if (key >= cb && key < ce) place(s, key);
    }
#pragma omp barrier
    list.SortCellsById(id, cb, ce);
  }
};

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
  InTeam(T, SortTeam{T, n, bound, *this, k, x, range_lo, range_hi, partial, cells, id});
  for (int a = 0; a < k; ++a) {  // the axis ranges, as Fit finds them (cell_list.cpp)
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
