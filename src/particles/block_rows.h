// The rows of one chunk's blocks of cells, written into the chunk's buffers (used by
// NeighbourList::FillBlocks only, neighbour_build.cpp). A block's cells go one by one (Cell), or,
// in 2D without periodic axes, by whole block rows (Row) with the first and last columns apart
// (Column): no branch per cell inside a block.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <type_traits>
#include <vector>

#include "particles/cell_list.h"
#include "particles/list_fill.h"

namespace moreau::particles::internal::list_fill {

template <int K, bool P, bool U>
class BlockRows {
 public:
  // Rows are written from buf[0] on; the buffers only grow (their entries past the rows are
  // scratch).
  BlockRows(const CellList& cells, const double* x, const RowWriter<K, P, U>& writer, int n,
            std::vector<int>* buf, std::vector<std::uint8_t>* img)
      : cells_(cells),
        x_(x),
        writer_(writer),
        n_(n),
        buf_(*buf),
        img_(*img),
        start_(cells.cell_starts()),
        rank_of_slot_(cells.sorted_ranks()) {}

  // The rows of the slots of block blk.
  void Block(std::int64_t blk) {
    int origin[3], w[3];
    cells_.BlockShape(blk, origin, w);
    if (Interior(blk, w)) return;
    const std::int64_t wx = w[0];
    std::int64_t r = cells_.block_cell_begin(blk);
    for (int lz = 0; lz < w[2]; ++lz) {
      const bool plane_inside = K < 3 || (lz >= 1 && lz + 2 <= w[2]);
      for (int ly = 0; ly < w[1]; ++ly) {
        const bool row_inside = plane_inside && (K < 2 || (ly >= 1 && ly + 2 <= w[1]));
        if (K == 2 && row_inside && wx >= 3) {
          Cell(r, false, w);
          Row(r, wx, std::true_type(), wx);
          Cell(r + wx - 1, false, w);
          r += wx;
          continue;
        }
        for (int lx = 0; lx < w[0]; ++lx, ++r) {
          Cell(r, row_inside && lx >= 1 && lx + 2 <= w[0], w);
        }
      }
    }
  }

  std::size_t used() const { return used_; }       // entries written
  std::int64_t active() const { return active_; }  // non-empty rows

 private:
  // The block to the right of an interior block: its first cell's rank and its width (0 when
  // there is none).
  struct Side {
    std::int64_t block = -1, begin = 0, width = 0;
  };

  void Reserve(std::size_t most) {
    if (buf_.size() < used_ + most) [[unlikely]] {
      buf_.resize(2 * (used_ + most));
      if constexpr (P) img_.resize(buf_.size());
    }
  }
  // A row of `found` entries written at buf[used]: counted, and the next row starts after it.
  void Keep(int found) {
    used_ += static_cast<std::size_t>(found);
    active_ += found > 0 ? 1 : 0;
  }

  // The rows of the slots of the cell of rank r (with all its neighbours in its block: inside).
  void Cell(std::int64_t r, bool inside, const int* w) {
    const int b = start_[r], e = start_[r + 1];
    if (b == e) return;
    CellRanges run;
    CellCandidates<K>(cells_, x_ + static_cast<std::ptrdiff_t>(K) * b, r, b, inside, w, &run);
    Reserve(static_cast<std::size_t>(run.most) * static_cast<std::size_t>(e - b) + kSlack);
    // Local copies of the members, as in RowSlots.
    int* const out = buf_.data();
    std::uint8_t* const out_img = P ? img_.data() : nullptr;
    const RowWriter<K, P, U> writer = writer_;
    const int n = n_;
    std::size_t at = used_;
    std::int64_t nonempty = active_;
    for (int s = b; s < e; ++s) {
      const int found = writer.Row(s, run, n, out + at, P ? out_img + at : nullptr);
      at += static_cast<std::size_t>(found);
      nonempty += found > 0 ? 1 : 0;
    }
    used_ = at;
    active_ = nonempty;
  }

  // The slots of the cells r + 1 … r + wx − 2 of one block row, consecutive: each slot's
  // candidates are [s + 1, start[c + 2]) and (Above) the three cells at rank offset d − 1 … d + 1
  // (the row above: d = wx inside the block; the first row of the block above, at a block's top),
  // c being its cell's rank (from the sort): no branch per cell, empty or not. Every candidate
  // lies in [s + 1, start[r + wx]) or [start[r + d], start[r + wx + d]): one reservation for the
  // row, and no window reaches past slot n − 1 when both ends + 4 ≤ n (the windows are at most 4
  // wide).
  template <typename Above>
  void Row(std::int64_t r, std::int64_t wx, Above above, std::int64_t d) {
    const std::int32_t* const st = start_;
    const int sb = st[r + 1], se = st[r + wx - 1];
    std::size_t span = static_cast<std::size_t>(st[r + wx] - sb);
    int reach_end = st[r + wx];
    if constexpr (above()) {
      span += static_cast<std::size_t>(st[r + wx + d] - st[r + d]);
      reach_end = std::max(reach_end, st[r + wx + d]);
    }
    Reserve(static_cast<std::size_t>(se - sb) * span + kSlack);
    if (reach_end + 4 <= n_) {
      RowSlots<false>(sb, se, above, d);
    } else {
      RowSlots<true>(sb, se, above, d);
    }
  }
  template <bool Checked, typename Above>
  void RowSlots(int sb, int se, Above, std::int64_t d) {
    // Local copies of the members: the row writer's vector stores may alias any memory for the
    // compiler, which would otherwise reload and store them around every store.
    int* const out = buf_.data();
    std::uint8_t* const out_img = P ? img_.data() : nullptr;
    const std::int32_t* const st = start_;
    const std::int32_t* const rk = rank_of_slot_;
    const RowWriter<K, P, U> w = writer_;
    const int n = n_;
    std::size_t at = used_;
    std::int64_t nonempty = active_;
    for (int s = sb; s < se; ++s) {
      const std::int64_t c = rk[s];
      const int own = st[c + 2] - s - 1;
      int found;
      if constexpr (Above::value) {
        const int lo = st[c + d - 1], hi = st[c + d + 2];
        found = w.template Runs<Checked, 2, 4>(s, {s + 1, lo}, {own, hi - lo}, n, out + at,
                                               P ? out_img + at : nullptr);
      } else {
        found =
            w.template Runs<Checked, 2>(s, {s + 1}, {own}, n, out + at, P ? out_img + at : nullptr);
      }
      at += static_cast<std::size_t>(found);
      nonempty += found > 0 ? 1 : 0;
    }
    used_ = at;
    active_ = nonempty;
  }

  // 2D without periodic axes, a block of at least 3 × 3 cells: every cell but the four corners
  // takes its candidates at rank offsets fixed for its row or column. Morton order is monotone in
  // each coordinate, so the blocks above and to the right rank after this one (their cells' slots
  // are candidates) and those below and to the left before it (checked: else the cells go one by
  // one, and this returns false). Blocks in one block row have the same height, in one column the
  // same width.
  bool Interior(std::int64_t blk, const int* w) {
    if constexpr (K != 2 || P) {
      return false;
    } else {
      const std::int64_t above_block = cells_.AdjacentBlock(blk, 1, 1);
      Side right;
      right.block = cells_.AdjacentBlock(blk, 0, 1);
      if (w[0] < 3 || w[1] < 3 || cells_.AdjacentBlock(blk, 1, -1) >= blk ||
          cells_.AdjacentBlock(blk, 0, -1) >= blk || (above_block >= 0 && above_block <= blk) ||
          (right.block >= 0 && right.block <= blk)) {
        return false;
      }
      const std::int64_t wx = w[0], wy = w[1];
      std::int64_t r = cells_.block_cell_begin(blk);
      // At the top, the row above is the first of the block above: offset d_above.
      const std::int64_t d_above =
          above_block < 0 ? 0 : cells_.block_cell_begin(above_block) - r - (wy - 1) * wx;
      if (right.block >= 0) {
        int o[3], rw[3];
        cells_.BlockShape(right.block, o, rw);
        right.begin = cells_.block_cell_begin(right.block);
        right.width = rw[0];
      }
      for (std::int64_t ly = 0; ly < wy; ++ly, r += wx) {
        const bool edge = ly == 0 || ly == wy - 1;
        if (edge) {
          Cell(r, false, w);
        } else {
          Column(r, ly, true, wx, wy, right);
        }
        if (ly < wy - 1) {
          Row(r, wx, std::true_type(), wx);
        } else if (above_block >= 0) {
          Row(r, wx, std::true_type(), d_above);
        } else {
          Row(r, wx, std::false_type(), 0);
        }
        if (edge) {
          Cell(r + wx - 1, false, w);
        } else {
          Column(r + wx - 1, ly, false, wx, wy, right);
        }
      }
      return true;
    }
  }

  // The cell of rank c in the first (left) or last column of an interior block of wx × wy cells,
  // on row ly (not the first or last row): its own runs, and on the right the block to the
  // right's cells on rows ly − 1 … ly + 1 (VisitPartners' order: row by row, left to right).
  void Column(std::int64_t c, std::int64_t ly, bool left, std::int64_t wx, std::int64_t wy,
              const Side& right) {
    const std::int32_t* const start = start_;
    const bool side = !left && right.block >= 0;
    auto side_cell = [&](std::int64_t y) { return right.begin + y * right.width; };
    if (side) {
      // The block to the right lies far from this row in memory: its offsets are fetched 8 rows
      // ahead and its positions 3 rows ahead (the misses otherwise dominate).
      __builtin_prefetch(start + side_cell(std::min(ly + 8, wy - 1)));
      __builtin_prefetch(x_ + static_cast<std::ptrdiff_t>(K) *
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
    Reserve(static_cast<std::size_t>(e - b) *
                static_cast<std::size_t>(start[own_end] - b + ae - ab + len[0] + len[1] + len[2]) +
            kSlack);
    int* out = buf_.data();
    for (int s = b; s < e; ++s) {
      const int own = start[own_end] - s - 1;
      std::uint8_t* out_img = P ? img_.data() + used_ : nullptr;
      const int found = side ? writer_.template Runs<true, 2, 2, 2, 4, 2>(
                                   s, {lo[0], s + 1, lo[1], ab, lo[2]},
                                   {len[0], own, len[1], ae - ab, len[2]}, n_, out + used_, out_img)
                             : writer_.template Runs<true, 2, 4>(s, {s + 1, ab}, {own, ae - ab}, n_,
                                                                 out + used_, out_img);
      Keep(found);
    }
  }

  const CellList& cells_;
  const double* x_;
  const RowWriter<K, P, U> writer_;
  const int n_;
  std::vector<int>& buf_;
  std::vector<std::uint8_t>& img_;
  const std::int32_t* start_;
  const std::int32_t* rank_of_slot_;
  std::size_t used_ = 0;
  std::int64_t active_ = 0;
};

}  // namespace moreau::particles::internal::list_fill
