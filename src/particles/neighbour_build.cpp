// The neighbour list's build (neighbour_list.h): the candidates of every slot from the cell list
// (or all slots), each pair within reach kept with its image code, rows filled in parallel chunks
// and concatenated in slot order.
#include "particles/neighbour_list.h"

#include <algorithm>
#include <limits>
#include <type_traits>

#include <fmt/format.h>

#include "moreau/common/error.h"
#include "particles/list_fill.h"
#include "particles/parallel.h"
#include "particles/step_context.h"

namespace moreau::particles::internal {

namespace {

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
    const int code = list_fill::MinimumImage<K, P>(xs, x + K * t, box, u);
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
                              const int* members, ListRows rows, int threads) {
  const bool sort_rows = rows != ListRows::kAsVisited;
  const bool brute_force = rows == ListRows::kBruteForce;
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

using list_fill::CellCandidates;
using list_fill::CellRanges;
using list_fill::kSlack;
using list_fill::MinimumImage;
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
  // A row of `found` entries written at buf[used]: counted, and the next row starts after it.
  auto keep = [&](int found) {
    used += static_cast<std::size_t>(found);
    active += found > 0 ? 1 : 0;
  };
  const std::int32_t* rank_of_slot = cells.sorted_ranks();
  // The rows of the slots of the cell of rank r (with all its neighbours in its block: inside).
  auto cell = [&](std::int64_t r, bool inside, const int* w) {
    const int b = start[r], e = start[r + 1];
    if (b == e) return;
    CellCandidates<K>(cells, x + static_cast<std::ptrdiff_t>(K) * b, r, b, inside, w, &run);
    reserve(static_cast<std::size_t>(run.most) * static_cast<std::size_t>(e - b) + kSlack);
    for (int s = b; s < e; ++s) {
      keep(writer.Row(s, run, n_, buf.data() + used, P ? img.data() + used : nullptr));
    }
  };
  // The slots of the cells r + 1 … r + wx − 2 of one block row, consecutive: each slot's
  // candidates are [s + 1, start[c + 2]) and (Above) the three cells at rank offset d − 1 … d + 1
  // (the row above: d = wx inside the block; the first row of the block above, at a block's top),
  // c being its cell's rank (from the sort): no branch per cell, empty or not. Every candidate lies
  // in [s + 1, start[r + wx]) or [start[r + d], start[r + wx + d]): one reservation for the row,
  // and no window reaches past slot n − 1 when both ends + 4 ≤ n (the windows are at most 4 wide).
  auto row = [&](std::int64_t r, std::int64_t wx, auto above, std::int64_t d) {
    const int sb = start[r + 1], se = start[r + wx - 1];
    std::size_t span = static_cast<std::size_t>(start[r + wx] - sb);
    int reach_end = start[r + wx];
    if constexpr (above()) {
      span += static_cast<std::size_t>(start[r + wx + d] - start[r + d]);
      reach_end = std::max(reach_end, start[r + wx + d]);
    }
    reserve(static_cast<std::size_t>(se - sb) * span + kSlack);
    auto slots = [&](auto checked) {
      // Local copies of the captured state: the row writer's vector stores may alias any memory
      // for the compiler, which would otherwise reload and store it around every store.
      int* const out = buf.data();
      std::uint8_t* const out_img = P ? img.data() : nullptr;
      const std::int32_t* const st = start;
      const std::int32_t* const rk = rank_of_slot;
      const RowWriter<K, P, U> w = writer;
      const int n = n_;
      std::size_t at = used;
      std::int64_t nonempty = active;
      for (int s = sb; s < se; ++s) {
        const std::int64_t c = rk[s];
        const int own = st[c + 2] - s - 1;
        int found;
        if constexpr (above()) {
          const int lo = st[c + d - 1], hi = st[c + d + 2];
          found = w.template Runs<checked(), 2, 4>(s, {s + 1, lo}, {own, hi - lo}, n, out + at,
                                                   P ? out_img + at : nullptr);
        } else {
          found = w.template Runs<checked(), 2>(s, {s + 1}, {own}, n, out + at,
                                                P ? out_img + at : nullptr);
        }
        at += static_cast<std::size_t>(found);
        nonempty += found > 0 ? 1 : 0;
      }
      used = at;
      active = nonempty;
    };
    if (reach_end + 4 <= n_) {
      slots(std::false_type());
    } else {
      slots(std::true_type());
    }
  };
  for (std::int64_t blk = first; blk < last; ++blk) {
    int origin[3], w[3];
    cells.BlockShape(blk, origin, w);
    const std::int64_t wx = w[0];
    std::int64_t r = cells.block_cell_begin(blk);
    // 2D without periodic axes, a block of at least 3 × 3 cells: every cell but the four corners
    // takes its candidates at rank offsets fixed for its row or column. Morton order is monotone
    // in each coordinate, so the blocks above and to the right rank after this one (their cells'
    // slots are candidates) and those below and to the left before it (checked: else the cells
    // go one by one). Blocks in one block row have the same height, in one column the same width.
    const std::int64_t above_block = K == 2 && !P ? cells.AdjacentBlock(blk, 1, 1) : -1;
    const std::int64_t right_block = K == 2 && !P ? cells.AdjacentBlock(blk, 0, 1) : -1;
    if (K == 2 && !P && w[0] >= 3 && w[1] >= 3 && cells.AdjacentBlock(blk, 1, -1) < blk &&
        cells.AdjacentBlock(blk, 0, -1) < blk && (above_block < 0 || above_block > blk) &&
        (right_block < 0 || right_block > blk)) {
      const std::int64_t wy = w[1];
      // At the top, the row above is the first of the block above: offset d_above.
      const std::int64_t d_above =
          above_block < 0 ? 0 : cells.block_cell_begin(above_block) - r - (wy - 1) * wx;
      std::int64_t right_begin = 0, right_width = 0;
      if (right_block >= 0) {
        int o[3], rw[3];
        cells.BlockShape(right_block, o, rw);
        right_begin = cells.block_cell_begin(right_block);
        right_width = rw[0];
      }
      // The cell of rank c in the first (left) or last column, on row ly (not the first or last
      // row): its own runs, and on the right the block to the right's cells on rows ly − 1 …
      // ly + 1 (VisitPartners' order: row by row, left to right).
      auto column = [&](std::int64_t c, std::int64_t ly, bool left) {
        const bool side = !left && right_block >= 0;
        auto side_cell = [&](std::int64_t y) { return right_begin + y * right_width; };
        if (side) {
          // The block to the right lies far from this row in memory: its offsets are fetched 8
          // rows ahead and its positions 3 rows ahead (the misses otherwise dominate).
          __builtin_prefetch(start + side_cell(std::min(ly + 8, wy - 1)));
          __builtin_prefetch(x + static_cast<std::ptrdiff_t>(K) *
                                     start[side_cell(std::min(ly + 3, wy - 1))]);
        }
        const int b = start[c], e = start[c + 1];
        if (b == e) return;
        // Own cell (and the next on the left), then the row above's two cells.
        const std::int64_t own_end = left ? c + 2 : c + 1;
        const int ab = start[left ? c + wx : c + wx - 1], ae = start[c + wx + (left ? 2 : 1)];
        int lo[3] = {0, 0, 0}, len[3] = {0, 0, 0};
        if (side) {
          for (int j = 0; j < 3; ++j) {
            lo[j] = start[side_cell(ly - 1 + j)];
            len[j] = start[side_cell(ly - 1 + j) + 1] - lo[j];
          }
        }
        reserve(
            static_cast<std::size_t>(e - b) *
                static_cast<std::size_t>(start[own_end] - b + ae - ab + len[0] + len[1] + len[2]) +
            kSlack);
        int* out = buf.data();
        for (int s = b; s < e; ++s) {
          const int own = start[own_end] - s - 1;
          std::uint8_t* out_img = P ? img.data() + used : nullptr;
          const int found =
              side ? writer.template Runs<true, 2, 2, 2, 4, 2>(
                         s, {lo[0], s + 1, lo[1], ab, lo[2]},
                         {len[0], own, len[1], ae - ab, len[2]}, n_, out + used, out_img)
                   : writer.template Runs<true, 2, 4>(s, {s + 1, ab}, {own, ae - ab}, n_,
                                                      out + used, out_img);
          keep(found);
        }
      };
      for (std::int64_t ly = 0; ly < wy; ++ly, r += wx) {
        const bool edge = ly == 0 || ly == wy - 1;
        if (edge) {
          cell(r, false, w);
        } else {
          column(r, ly, true);
        }
        if (ly < wy - 1) {
          row(r, wx, std::true_type(), wx);
        } else if (above_block >= 0) {
          row(r, wx, std::true_type(), d_above);
        } else {
          row(r, wx, std::false_type(), 0);
        }
        if (edge) {
          cell(r + wx - 1, false, w);
        } else {
          column(r + wx - 1, ly, false);
        }
      }
      continue;
    }
    for (int lz = 0; lz < w[2]; ++lz) {
      const bool plane_inside = K < 3 || (lz >= 1 && lz + 2 <= w[2]);
      for (int ly = 0; ly < w[1]; ++ly) {
        const bool row_inside = plane_inside && (K < 2 || (ly >= 1 && ly + 2 <= w[1]));
        if (K == 2 && row_inside && wx >= 3) {
          cell(r, false, w);
          row(r, wx, std::true_type(), wx);
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
                          const int* members, ListRows rows, std::int64_t step, int threads) {
  if (box_.k == 1 && box_.any) {
    BuildRows<1, true>(x, radius, cells, members, rows, threads);
  } else if (box_.k == 1) {
    BuildRows<1, false>(x, radius, cells, members, rows, threads);
  } else {
    DispatchDimensionPeriodic(box_.k, box_.any, [&](auto k, auto p) {
      BuildRows<k, p>(x, radius, cells, members, rows, threads);
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
  built_extra_ = extra();
  drift_bound_ = 0.0;
}

void NeighbourList::Build(const StepContext& context, const double* at, std::int64_t step) {
  Build(at, context.store->radius.data(), context.cells, context.members(), context.rows(), step,
        context.threads);
}

}  // namespace moreau::particles::internal
