// The neighbour list's build (neighbour_list.h): the candidates of every slot from the cell list
// (or all slots), each pair within reach kept with its image code, rows filled in parallel chunks
// and concatenated in slot order.
#include "particles/neighbour_list.h"

#include <algorithm>
#include <limits>
#include <type_traits>

#include <fmt/format.h>

#include "moreau/common/error.h"
#include "particles/block_rows.h"
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

// The rows of the slots of blocks [first, last) into chunk q's buffers; returns the entries used.
// The buffers only grow (their entries past the rows are scratch).
template <int K, bool P, bool U>
std::size_t NeighbourList::FillBlocks(const double* x, const double* radius, const CellList& cells,
                                      std::int64_t first, std::int64_t last, int q) {
  const double reach = (uniform_radius_ + uniform_radius_) + extra();
  const list_fill::RowWriter<K, P, U> writer{
      x, radius, extra(), &box_, row_start_.data() + 1, reach * reach};
  list_fill::BlockRows<K, P, U> rows(cells, x, writer, n_, &chunk_nbr_[static_cast<std::size_t>(q)],
                                     &chunk_image_[static_cast<std::size_t>(q)]);
  for (std::int64_t blk = first; blk < last; ++blk) rows.Block(blk);
  chunk_active_[static_cast<std::size_t>(q)] = rows.active();
  return rows.used();
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
