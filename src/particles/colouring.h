// The colouring of the cell list's blocks for the parallel sweep: block b with coordinates
// (b_0, b_1, b_2) has colour Σ_a (b_a mod 3) 3^a (27 colours, 9 in 2D used). Two blocks of one
// colour are at least two blocks apart on some axis (a periodic axis has 1, 2 or a multiple of
// 3 blocks), and a block edge is at least one cell edge ≥ the neighbour-list reach, so no pair of
// the list touches two blocks of one colour: the blocks of a colour can be swept in parallel.
#pragma once

#include <vector>

#include "particles/cell_list.h"

namespace moreau::particles::internal {

class Colouring {
 public:
  static constexpr int kColours = 27;

  // Colours the blocks of `cells` (after every change of its geometry).
  void Assign(const CellList& cells);
  // Entries [colour_begin(c), colour_begin(c + 1)) of block_rank() are the blocks of colour c,
  // by increasing rank.
  int colour_begin(int colour) const { return colour_begin_[static_cast<std::size_t>(colour)]; }
  int block_rank(int q) const { return blocks_[static_cast<std::size_t>(q)]; }

 private:
  std::vector<int> colour_begin_;
  std::vector<int> blocks_;
};

// Inside an OpenMP parallel region: for each colour in order, the blocks of that colour shared
// among the threads (omp for, static), f(slot_begin, slot_end) per block (storage in cell
// order). Colours without blocks are skipped without a barrier.
template <typename F>
void ForEachBlockByColour(const Colouring& colouring, const CellList& cells, F&& f) {
  for (int colour = 0; colour < Colouring::kColours; ++colour) {
    const int qb = colouring.colour_begin(colour);
    const int qe = colouring.colour_begin(colour + 1);
    if (qb == qe) continue;
#pragma omp for schedule(static)
    for (int q = qb; q < qe; ++q) {
      const int r = colouring.block_rank(q);
      f(cells.BlockSlotBegin(r), cells.BlockSlotBegin(r + 1));
    }
  }
}

}  // namespace moreau::particles::internal
