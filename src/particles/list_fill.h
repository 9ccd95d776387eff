// The neighbour-list fill's row writers (neighbour_build.cpp): the candidate slot ranges of a cell
// in cell-ordered storage, and the tests that keep the candidates within reach and write a slot's
// row, in SSE2 windows for 2D uniform radii without periodic axes.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "particles/cell_list.h"
#include "particles/kernels.h"

namespace moreau::particles::internal {

// Used by NeighbourList::FillBlocks and BuildRows only (neighbour_build.cpp).
namespace list_fill {

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

  // The row of s over the candidate runs [lo[i], lo[i] + len[i]) in order, every candidate after
  // s, run i in windows of W_i (SSE2 path). Writes up to kSlack entries past the row (the caller
  // reserves the runs' total + kSlack). Checked false: the caller knows that no window reaches
  // past slot n − 1.
  template <bool Checked, int... W>
  [[gnu::always_inline]] int Runs(int s, const int (&lo)[sizeof...(W)],
                                  const int (&len)[sizeof...(W)], int n, int* out,
                                  std::uint8_t* out_img) const {
#if defined(__SSE2__)
    if constexpr (K == 2 && !P && U) {
      const double* xs = x + 2 * static_cast<std::ptrdiff_t>(s);
      int found = 0;
      int i = 0;
      ((found += Run<W, Checked>(xs, lo[i], len[i], n, out + found), ++i), ...);
      count[s] = found;
      return found;
    }
#endif
    CellRanges runs;  // every run after s: Row skips nothing
    for (std::size_t i = 0; i < sizeof...(W); ++i) runs.Add(lo[i], lo[i] + len[i]);
    return Row(s, runs, n, out, out_img);
  }
#if defined(__SSE2__)
  // K = 2, no periodic axis, uniform radii: the candidates [lo, lo + len) (len ≥ 0) in windows of
  // W (2 or 4), two candidates a SSE2 vector of ‖u‖² (Test's u0² + u1², so the same rows); the
  // window's kept candidates are written by one 4-entry store (CompressStore). The first window
  // goes without a branch on len; the loop runs again only for longer runs. A window reaching past
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
        const __m128d r2 = SquaredDistances2(xs, p, p + 2);
        hit |= _mm_movemask_pd(_mm_cmplt_pd(r2, reach2)) << j;
      }
      hit &= (1 << std::min(len - c, W)) - 1;  // len ≥ 0, and len − c > 0 after the first window
      found += CompressStore(hit, t, out + found);
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
        found += Run<2>(xs, lo, std::max(run.hi[i] - lo, 0), n, out + found);
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

}  // namespace moreau::particles::internal
