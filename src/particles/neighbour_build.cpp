// The neighbour list's build (neighbour_list.h): the candidates of every slot from the cell list
// (or all slots), each pair within reach kept with its image code, rows filled in parallel chunks
// and concatenated in slot order.
#include "particles/neighbour_list.h"

#include <algorithm>
#include <limits>
#include <type_traits>

#include <fmt/format.h>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "moreau/common/error.h"
#include "particles/parallel.h"

namespace moreau::particles::internal {

namespace {

// u = xs − xt, the minimum image on periodic axes (P); returns the image code (13: none).
template <int K, bool P>
inline int MinimumImage(const double* xs, const double* xt, const PeriodicBox& box, double* u) {
  int code = 13;
  int weight = 1;
  for (int a = 0; a < K; ++a) {
    u[a] = xs[a] - xt[a];
    if constexpr (P) {
      if (box.periodic[a]) {
        if (u[a] > 0.5 * box.len[a]) {
          u[a] -= box.len[a];
          code += weight;
        } else if (u[a] < -0.5 * box.len[a]) {
          u[a] += box.len[a];
          code -= weight;
        }
      }
    }
    weight *= 3;
  }
  return code;
}

// Calls f(t, image code) for the slots t > s within reach of slot s, in the list's order: the
// slots of the adjacent cells through `members`, or all slots (brute_force).
template <int K, bool P, typename F>
void VisitPartners(int s, const double* x, const double* radius, double extra,
                   const PeriodicBox& box, const CellList& cells, const int* members, int n,
                   bool brute_force, F&& f) {
  const double* xs = x + K * s;
  const double rs = radius[s];
  auto consider = [&](int t) {
    if (t <= s) return;
    double u[K];
    const int code = MinimumImage<K, P>(xs, x + K * t, box, u);
    const double r2 = SquaredNorm<K>(u);
    const double c = rs + radius[t] + extra;
    if (r2 < c * c) f(t, code);
  };
  if (brute_force) {
    for (int t = s + 1; t < n; ++t) consider(t);
    return;
  }
  cells.grid().ForEachAdjacentCell<K>(xs, [&](std::int64_t cell) {
    const std::int64_t rank = cells.rank(cell);
    const std::int64_t e = cells.cell_start(rank + 1);
    for (std::int64_t q = cells.cell_start(rank); q < e; ++q) consider(members[q]);
  });
}

// Insertion sort of buf[first …] by t, the image codes along (t is unique in a row).
template <bool P>
void SortRow(std::vector<int>& buf, std::vector<std::uint8_t>& img, std::size_t first) {
  for (std::size_t i = first + 1; i < buf.size(); ++i) {
    const int t = buf[i];
    const std::uint8_t c = P ? img[i] : 0;
    std::size_t j = i;
    while (j > first && buf[j - 1] > t) {
      buf[j] = buf[j - 1];
      if constexpr (P) img[j] = img[j - 1];
      --j;
    }
    buf[j] = t;
    if constexpr (P) img[j] = c;
  }
}

}  // namespace

// One pass: contiguous chunks of slots append their rows to reusable chunk buffers, then the
// buffers are concatenated in chunk order (the same list for any thread count).
template <int K, bool P>
void NeighbourList::BuildRows(const double* x, const double* radius, const CellList& cells,
                              const int* members, bool sort_rows, bool brute_force, int threads) {
  const int n = n_;
  const double extra = this->extra();
  const int chunks = std::max(1, std::min(n, 16 * threads));
  if (static_cast<int>(chunk_nbr_.size()) < chunks) {
    chunk_nbr_.resize(static_cast<std::size_t>(chunks));
    chunk_image_.resize(static_cast<std::size_t>(chunks));
  }
  if (members == nullptr && !brute_force) {
    MOREAU_ASSERT(!sort_rows);
    BuildCellRows<K, P>(x, radius, cells, threads);
    return;
  }
  chunk_slot_.resize(static_cast<std::size_t>(chunks) + 1);
  chunk_used_.resize(static_cast<std::size_t>(chunks));
  chunk_active_.resize(static_cast<std::size_t>(chunks));
  for (int q = 0; q <= chunks; ++q) {
    chunk_slot_[static_cast<std::size_t>(q)] =
        static_cast<int>(static_cast<std::int64_t>(q) * n / chunks);
  }
  ParallelFor<true>(threads, 0, chunks, [&](std::int64_t q) {
    const int begin = chunk_slot_[static_cast<std::size_t>(q)];
    const int end = chunk_slot_[static_cast<std::size_t>(q) + 1];
    std::vector<int>& buf = chunk_nbr_[static_cast<std::size_t>(q)];
    std::vector<std::uint8_t>& img = chunk_image_[static_cast<std::size_t>(q)];
    buf.clear();
    img.clear();
    std::int64_t active = 0;
    for (int s = begin; s < end; ++s) {
      const std::size_t first = buf.size();
      VisitPartners<K, P>(s, x, radius, extra, box_, cells, members, n, brute_force,
                          [&](int t, int code) {
                            buf.push_back(t);
                            if constexpr (P) img.push_back(static_cast<std::uint8_t>(code));
                          });
      row_start_[static_cast<std::size_t>(s) + 1] = static_cast<int>(buf.size() - first);
      active += buf.size() > first ? 1 : 0;
      if (sort_rows) SortRow<P>(buf, img, first);
    }
    chunk_used_[static_cast<std::size_t>(q)] = buf.size();
    chunk_active_[static_cast<std::size_t>(q)] = active;
  });
  Concatenate(x, K, P, chunks, threads);
}

// Named (not anonymous): FillBlocks, a member template, captures them in a lambda.
namespace list_fill {

// The candidate slot ranges [lo[i], hi[i]) of a cell's slots (at most one per adjacent cell) and
// the number of candidates they hold.
struct CellRanges {
  int lo[27];
  int hi[27];
  int count = 0;
  int most = 0;
  void Add(int from, int to) {
    lo[count] = from;
    hi[count] = to;
    ++count;
    most += to - from;
  }
};

// Storage in cell order, cells row-major inside a block of w cells per axis. The candidates
// t > s of the slots of a cell of rank r whose neighbours all lie in its block are at fixed rank
// offsets, and the cells before it in that order hold slots before its own: the rest of its own
// cell and the next (from b), then the three-cell rows above (2D: one row; 3D: one in its plane,
// three in the next). Any other cell looks its neighbours up, consecutive ranks merged, each range
// from after b. Each slot then skips the t ≤ s.
template <int K>
[[gnu::always_inline]] inline void CellCandidates(const CellList& cells, const double* xb,
                                                  std::int64_t r, int b, bool inside, const int* w,
                                                  CellRanges* run) {
  const std::int32_t* start = cells.cell_starts();
  run->count = 0;
  run->most = 0;
  if (inside) {
    const std::int64_t wx = w[0], plane = static_cast<std::int64_t>(w[0]) * w[1];
    run->Add(b, start[r + 2]);
    auto row = [&](std::int64_t o) { run->Add(start[r + o - 1], start[r + o + 2]); };
    if constexpr (K >= 2) row(wx);
    if constexpr (K == 3) {
      row(plane - wx);
      row(plane);
      row(plane + wx);
    }
    return;
  }
  std::int64_t run_b = -1, run_e = -1;
  auto flush = [&] {
    const int from = std::max(start[run_b], b + 1);
    if (from < start[run_e]) run->Add(from, start[run_e]);
  };
  cells.grid().ForEachAdjacentCell<K>(xb, [&](std::int64_t cell) {
    const std::int64_t rank = cells.rank(cell);
    if (rank == run_e) {
      run_e = rank + 1;
      return;
    }
    if (run_b >= 0) flush();
    run_b = rank;
    run_e = rank + 1;
  });
  flush();
}

// The entries a row writer may write past a row (RowWriter::Run's 4-entry stores).
constexpr std::size_t kSlack = 4;

#if defined(__SSE2__)
// For each 4-bit mask of kept candidates (bit i: candidate i of a window): their offsets in
// order, as one vector (the lanes past the count are scratch), and their count.
struct CompressTable {
  alignas(16) std::int32_t offset[16][4];
  int count[16];
};
constexpr CompressTable MakeCompressTable() {
  CompressTable t{};
  for (int m = 0; m < 16; ++m) {
    int c = 0;
    for (int b = 0; b < 4; ++b) {
      if ((m >> b) & 1) t.offset[m][c++] = b;
    }
    t.count[m] = c;
  }
  return t;
}
constexpr CompressTable kCompress = MakeCompressTable();
#endif

// Writes rows: slot s's candidates t, each written and kept only when within reach (no branch on
// it), the row's length into count[s]. U: every radius is `uniform` (the reach (r + r) + extra
// is then computed once, as each pair would compute it, and no radius is loaded).
template <int K, bool P, bool U>
struct RowWriter {
  const double* x;
  const double* radius;
  double extra;
  const PeriodicBox* box;
  int* count;                   // row lengths, by slot
  double uniform_reach2 = 0.0;  // U: ((r + r) + extra)²

  // The row of s over the candidates t = first + c (c < n0), then t = jump + c (n0 ≤ c < m): two
  // ranges walked as one loop. Returns its length.
  [[gnu::always_inline]] int Row2(int s, int first, int n0, int jump, int m, int* out,
                                  std::uint8_t* out_img) const {
    const double* xs = x + static_cast<std::ptrdiff_t>(K) * s;
    const double rs = U ? 0.0 : radius[s];
    int found = 0;
    for (int c = 0; c < m; ++c) {
      const int t = (c < n0 ? first : jump) + c;
      found += Test(xs, rs, t, out + found, P ? out_img + found : nullptr);
    }
    count[s] = found;
    return found;
  }
  // The row of s over the candidates [lo0, lo0 + len0), then [lo1, lo1 + len1). Writes up to
  // kSlack entries past the row (the caller reserves len0 + len1 + kSlack).
  // Checked false: the caller knows that no window reaches past slot n − 1.
  template <bool Checked = true>
  [[gnu::always_inline]] int Row2(int s, int lo0, int len0, int lo1, int len1, int n, int* out,
                                  std::uint8_t* out_img) const {
#if defined(__SSE2__)
    if constexpr (K == 2 && !P && U) {
      const double* xs = x + 2 * static_cast<std::ptrdiff_t>(s);
      int found = Run<2, Checked>(xs, lo0, len0, n, out);
      found += Run<4, Checked>(xs, lo1, len1, n, out + found);
      count[s] = found;
      return found;
    }
#endif
    return Row2(s, lo0, len0, lo1 - len0, len0 + len1, out, out_img);
  }
#if defined(__SSE2__)
  // K = 2, no periodic axis, uniform radii: the candidates [lo, lo + len) in windows of W (2 or
  // 4), two candidates a SSE2 vector of ‖u‖² (Test's u0² + u1², so the same rows); the window's
  // kept candidates are written by one 4-entry store from kCompress. The first window goes
  // without a branch on len; the loop runs again only for longer runs. A window reaching past
  // slot n − 1 is finished by Test.
  template <int W, bool Checked = true>
  [[gnu::always_inline]] int Run(const double* xs_at, int lo, int len, int n, int* out) const {
    const __m128d xs = _mm_loadu_pd(xs_at);
    const __m128d reach2 = _mm_set1_pd(uniform_reach2);
    int found = 0;
    int c = 0;
    do {
      const int t = lo + c;
      if (Checked && t + W > n) [[unlikely]] {
        for (; c < len; ++c) found += Test(xs_at, 0.0, lo + c, out + found, nullptr);
        return found;
      }
      int hit = 0;
      for (int j = 0; j < W; j += 2) {
        const double* p = x + 2 * static_cast<std::ptrdiff_t>(t + j);
        const __m128d u0 = _mm_sub_pd(xs, _mm_loadu_pd(p));
        const __m128d u1 = _mm_sub_pd(xs, _mm_loadu_pd(p + 2));
        const __m128d q0 = _mm_mul_pd(u0, u0);
        const __m128d q1 = _mm_mul_pd(u1, u1);
        const __m128d r2 = _mm_add_pd(_mm_unpacklo_pd(q0, q1), _mm_unpackhi_pd(q0, q1));
        hit |= _mm_movemask_pd(_mm_cmplt_pd(r2, reach2)) << j;
      }
      hit &= (1 << std::clamp(len - c, 0, W)) - 1;
      const __m128i offsets =
          _mm_load_si128(reinterpret_cast<const __m128i*>(kCompress.offset[hit]));
      _mm_storeu_si128(reinterpret_cast<__m128i*>(out + found),
                       _mm_add_epi32(_mm_set1_epi32(t), offsets));
      found += kCompress.count[hit];
      c += W;
    } while (c < len);
    return found;
  }
#endif
  // The row of s over the candidates t > s of the ranges (writing up to kSlack entries past it, as
  // Row2 does).
  [[gnu::always_inline]] int Row(int s, const CellRanges& run, int n, int* out,
                                 std::uint8_t* out_img) const {
#if defined(__SSE2__)
    if constexpr (K == 2 && !P && U) {
      const double* xs = x + 2 * static_cast<std::ptrdiff_t>(s);
      int found = 0;
      for (int i = 0; i < run.count; ++i) {
        const int lo = std::max(run.lo[i], s + 1);
        found += Run<2>(xs, lo, run.hi[i] - lo, n, out + found);
      }
      count[s] = found;
      return found;
    }
#endif
    const double* xs = x + static_cast<std::ptrdiff_t>(K) * s;
    const double rs = U ? 0.0 : radius[s];
    int found = 0;
    for (int i = 0; i < run.count; ++i) {
      for (int t = std::max(run.lo[i], s + 1); t < run.hi[i]; ++t) {
        found += Test(xs, rs, t, out + found, P ? out_img + found : nullptr);
      }
    }
    count[s] = found;
    return found;
  }
  // Writes t (and its image code); 1 when within reach.
  [[gnu::always_inline]] int Test(const double* xs, double rs, int t, int* out,
                                  std::uint8_t* out_img) const {
    double u[K];
    const int code = MinimumImage<K, P>(xs, x + static_cast<std::ptrdiff_t>(K) * t, *box, u);
    *out = t;
    if constexpr (P) *out_img = static_cast<std::uint8_t>(code);
    if constexpr (U) return static_cast<int>(SquaredNorm<K>(u) < uniform_reach2);
    const double c = rs + radius[t] + extra;
    return static_cast<int>(SquaredNorm<K>(u) < c * c);
  }
};

}  // namespace list_fill

using list_fill::CellCandidates;
using list_fill::CellRanges;
using list_fill::kSlack;
using list_fill::RowWriter;

// The rows of the slots of blocks [first, last) into chunk q's buffers; returns the entries used.
// The buffers only grow (their entries past the rows are scratch).
template <int K, bool P, bool U>
std::size_t NeighbourList::FillBlocks(const double* x, const double* radius, const CellList& cells,
                                      std::int64_t first, std::int64_t last, int q) {
  std::vector<int>& buf = chunk_nbr_[static_cast<std::size_t>(q)];
  std::vector<std::uint8_t>& img = chunk_image_[static_cast<std::size_t>(q)];
  const double reach = (uniform_radius_ + uniform_radius_) + extra();
  const RowWriter<K, P, U> writer{x, radius, extra(), &box_, row_start_.data() + 1, reach * reach};
  const std::int32_t* start = cells.cell_starts();
  CellRanges run;
  std::size_t used = 0;
  std::int64_t active = 0;  // non-empty rows
  auto reserve = [&](std::size_t most) {
    if (buf.size() < used + most) [[unlikely]] {
      buf.resize(2 * (used + most));
      if constexpr (P) img.resize(buf.size());
    }
  };
  const std::int32_t* rank_of_slot = cells.sorted_ranks();
  // The rows of the slots of the cell of rank r (with all its neighbours in its block: inside).
  auto cell = [&](std::int64_t r, bool inside, const int* w) {
    const int b = start[r], e = start[r + 1];
    if (b == e) return;
    CellCandidates<K>(cells, x + static_cast<std::ptrdiff_t>(K) * b, r, b, inside, w, &run);
    reserve(static_cast<std::size_t>(run.most) * static_cast<std::size_t>(e - b) + kSlack);
    for (int s = b; s < e; ++s) {
      const int found = writer.Row(s, run, n_, buf.data() + used, P ? img.data() + used : nullptr);
      used += static_cast<std::size_t>(found);
      active += found > 0 ? 1 : 0;
    }
  };
  for (std::int64_t blk = first; blk < last; ++blk) {
    int origin[3], w[3];
    cells.BlockShape(blk, origin, w);
    const std::int64_t wx = w[0];
    std::int64_t r = cells.block_cell_begin(blk);
    for (int lz = 0; lz < w[2]; ++lz) {
      const bool plane_inside = K < 3 || (lz >= 1 && lz + 2 <= w[2]);
      for (int ly = 0; ly < w[1]; ++ly) {
        const bool row_inside = plane_inside && (K < 2 || (ly >= 1 && ly + 2 <= w[1]));
        if (K == 2 && row_inside && wx >= 3) {
          // The cells lx = 1 … wx − 2 of a row inside the block hold consecutive slots; each
          // slot's candidates are [s + 1, start[r + 2]) and the three cells above, r being its
          // cell's rank (from the sort): no branch per cell, empty or not.
          // Every candidate of these slots lies in [s + 1, start[r + 2 wx]) (the next row and
          // the one above it end there): one reservation for the row, and no window reaches
          // past slot n − 1 when start[r + 2 wx] + 4 ≤ n (the windows are at most 4 wide).
          cell(r, false, w);
          const int sb = start[r + 1], se = start[r + wx - 1];
          const int reach_end = start[r + 2 * wx];
          reserve(static_cast<std::size_t>(se - sb) * static_cast<std::size_t>(reach_end - sb) +
                  kSlack);
          auto slots = [&](auto checked) {
            int* out = buf.data();
            for (int s = sb; s < se; ++s) {
              const std::int64_t c = rank_of_slot[s];
              const int hi0 = start[c + 2], lo1 = start[c + wx - 1], hi1 = start[c + wx + 2];
              const int found =
                  writer.template Row2<checked()>(s, s + 1, hi0 - s - 1, lo1, hi1 - lo1, n_,
                                                  out + used, P ? img.data() + used : nullptr);
              used += static_cast<std::size_t>(found);
              active += found > 0 ? 1 : 0;
            }
          };
          if (reach_end + 4 <= n_) {
            slots(std::false_type());
          } else {
            slots(std::true_type());
          }
          cell(r + wx - 1, false, w);
          r += wx;
          continue;
        }
        for (int lx = 0; lx < w[0]; ++lx, ++r) {
          cell(r, row_inside && lx >= 1 && lx + 2 <= w[0], w);
        }
      }
    }
  }
  chunk_active_[static_cast<std::size_t>(q)] = active;
  return used;
}

// Storage in cell order: every slot of a cell has the same candidates (CellCandidates, the slot
// ranges of its adjacent cells in VisitPartners' order), gathered once per cell; each slot of the
// cell tests those after it. Chunks are runs of whole blocks of about n/chunks slots. The rows are
// VisitPartners' (with members = identity), entry by entry.
template <int K, bool P>
void NeighbourList::BuildCellRows(const double* x, const double* radius, const CellList& cells,
                                  int threads) {
  const int chunks = std::max(1, std::min(n_, 16 * threads));
  const std::int64_t blocks = cells.blocks();
  std::vector<std::int64_t> chunk_block(static_cast<std::size_t>(chunks) + 1, blocks);
  for (int q = 0; q < chunks; ++q) {  // the first block starting at or after slot q·n/chunks
    const std::int64_t slot = static_cast<std::int64_t>(q) * n_ / chunks;
    std::int64_t lo = 0, hi = blocks;
    while (lo < hi) {
      const std::int64_t mid = (lo + hi) / 2;
      if (cells.BlockSlotBegin(mid) < slot) {
        lo = mid + 1;
      } else {
        hi = mid;
      }
    }
    chunk_block[static_cast<std::size_t>(q)] = lo;
  }
  chunk_slot_.resize(static_cast<std::size_t>(chunks) + 1);
  chunk_used_.resize(static_cast<std::size_t>(chunks));
  chunk_active_.resize(static_cast<std::size_t>(chunks));
  for (int q = 0; q <= chunks; ++q) {
    chunk_slot_[static_cast<std::size_t>(q)] =
        cells.BlockSlotBegin(chunk_block[static_cast<std::size_t>(q)]);
  }
  ParallelFor<true>(threads, 0, chunks, [&](std::int64_t q) {
    const std::int64_t first = chunk_block[static_cast<std::size_t>(q)];
    const std::int64_t last = chunk_block[static_cast<std::size_t>(q) + 1];
    chunk_used_[static_cast<std::size_t>(q)] =
        uniform_radius_ > 0.0
            ? FillBlocks<K, P, true>(x, radius, cells, first, last, static_cast<int>(q))
            : FillBlocks<K, P, false>(x, radius, cells, first, last, static_cast<int>(q));
  });
  Concatenate(x, K, P, chunks, threads);
}

// Row offsets: the chunks' totals (pairs and non-empty rows) are summed in chunk order, then every
// chunk turns its row counts into offsets from its first row on, indexes its non-empty rows, copies
// its rows and its build positions (unless the reorder wrote them: BuildPositionsTarget), all in
// one parallel pass (the same list for any thread count).
void NeighbourList::Concatenate(const double* x, int k, bool periodic, int chunks, int threads) {
  std::vector<std::int64_t> chunk_first(static_cast<std::size_t>(chunks) + 1, 0);
  std::vector<std::int64_t> active_first(static_cast<std::size_t>(chunks) + 1, 0);
  for (int q = 0; q < chunks; ++q) {
    const auto u = static_cast<std::size_t>(q);
    chunk_first[u + 1] = chunk_first[u] + static_cast<std::int64_t>(chunk_used_[u]);
    active_first[u + 1] = active_first[u] + chunk_active_[u];
  }
  const std::int64_t total = chunk_first[static_cast<std::size_t>(chunks)];
  if (total > std::numeric_limits<int>::max()) {
    throw NumericalError(fmt::format("neighbour list with more than {} pairs is too large",
                                     std::numeric_limits<int>::max()));
  }
  nbr_.resize(static_cast<std::size_t>(total));
  if (periodic) image_.resize(static_cast<std::size_t>(total));
  active_rows_.resize(static_cast<std::size_t>(active_first[static_cast<std::size_t>(chunks)]));
  row_start_[0] = 0;
  ParallelFor(threads, 0, chunks, [&](std::int64_t q) {
    const auto u = static_cast<std::size_t>(q);
    const int begin = chunk_slot_[u];
    const int end = chunk_slot_[u + 1];
    auto run = static_cast<int>(chunk_first[u]);
    // Every slot is written to the index and kept only when its row is non-empty (no branch on
    // it); the loop stops writing once the chunk's count is reached (only empty rows are left).
    int* active = active_rows_.data();
    std::int64_t at = active_first[u];
    const std::int64_t stop = active_first[u + 1];
    for (int s = begin; s < end; ++s) {
      const int count = row_start_[static_cast<std::size_t>(s) + 1];
      if (at < stop) active[at] = s;
      at += count > 0 ? 1 : 0;
      run += count;
      row_start_[static_cast<std::size_t>(s) + 1] = run;
    }
    const auto from = static_cast<std::size_t>(chunk_first[u]);
    const auto used = static_cast<std::ptrdiff_t>(chunk_used_[u]);
    const std::vector<int>& buf = chunk_nbr_[u];
    std::copy(buf.begin(), buf.begin() + used, nbr_.begin() + static_cast<std::ptrdiff_t>(from));
    if (periodic) {
      const std::vector<std::uint8_t>& img = chunk_image_[u];
      std::copy(img.begin(), img.begin() + used,
                image_.begin() + static_cast<std::ptrdiff_t>(from));
    }
    if (!build_positions_written_) {
      std::copy(x + static_cast<std::ptrdiff_t>(k) * begin,
                x + static_cast<std::ptrdiff_t>(k) * end,
                reference_.data() + static_cast<std::ptrdiff_t>(k) * begin);
    }
  });
  build_positions_written_ = false;
}

void NeighbourList::Build(const double* x, const double* radius, const CellList& cells,
                          const int* members, bool sort_rows, bool brute_force, std::int64_t step,
                          int threads) {
  if (box_.k == 1 && box_.any) {
    BuildRows<1, true>(x, radius, cells, members, sort_rows, brute_force, threads);
  } else if (box_.k == 1) {
    BuildRows<1, false>(x, radius, cells, members, sort_rows, brute_force, threads);
  } else {
    DispatchDimensionPeriodic(box_.k, box_.any, [&](auto k, auto p) {
      BuildRows<k, p>(x, radius, cells, members, sort_rows, brute_force, threads);
    });
  }
  ++stats_.builds;
  stats_.candidate_pairs = pairs();
  if (last_build_step_ >= 0) {
    const std::int64_t interval = step - last_build_step_;
    if (stats_.shortest_rebuild_interval < 0 || interval < stats_.shortest_rebuild_interval) {
      stats_.shortest_rebuild_interval = interval;
    }
  }
  last_build_step_ = step;
  built_here_ = true;
  drift_bound_ = 0.0;
}

}  // namespace moreau::particles::internal
