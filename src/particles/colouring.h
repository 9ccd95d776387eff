// The colouring of the cell list's blocks for the parallel sweep: block b with coordinates
// (b_0, b_1, b_2) has colour Σ_a (b_a mod 3) 3^a (27 colours, 9 in 2D used). Two blocks of one
// colour are at least two blocks apart on some axis (a periodic axis has 1, 2 or a multiple of
// 3 blocks), and a block edge is at least one cell edge ≥ the neighbour-list reach, so no pair of
// the list touches two blocks of one colour: the blocks of a colour can be swept in parallel.
//
// Dependencies: the sweep of a block moves its own slots and their partners in the adjacent
// cells, so two blocks whose cells come within two cells of each other on every axis (periodic
// axes wrapped; at most two blocks apart, two only across a block one cell wide) may touch the
// same slot. Sweeping each block once every such block of a smaller colour is done, and
// before any of a larger colour starts, gives the same result as sweeping the colours in turn.
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <thread>
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
  int blocks() const { return static_cast<int>(blocks_.size()); }
  // Entries [dependency_begin(q), dependency_begin(q + 1)) of dependencies() are the entries q' of
  // block_rank() with a smaller colour than entry q's that may touch a slot it touches.
  int dependency_begin(int q) const { return dependency_begin_[static_cast<std::size_t>(q)]; }
  const int* dependencies() const { return dependencies_.data(); }

 private:
  void AssignDependencies(const CellList& cells, const std::vector<int>& colour_of);

  std::vector<int> colour_begin_;
  std::vector<int> blocks_;
  std::vector<int> dependency_begin_;
  std::vector<int> dependencies_;
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

// The shared state of one ForEachBlockInDependencyOrder pass: a done mark per block (the pass's
// epoch, so that nothing is cleared between passes) and the next block entry to take.
class BlockProgress {
 public:
  // Before the parallel region of a pass over `blocks` blocks.
  void Start(int blocks) {
    if (static_cast<int>(size_) != blocks || epoch_ == UINT32_MAX) {
      done_ = std::make_unique<std::atomic<std::uint32_t>[]>(static_cast<std::size_t>(blocks));
      for (int q = 0; q < blocks; ++q) done_[static_cast<std::size_t>(q)].store(0);
      size_ = static_cast<std::size_t>(blocks);
      epoch_ = 0;
    }
    ++epoch_;
    next_.store(0);
  }
  int Take() { return next_.fetch_add(1, std::memory_order_relaxed); }
  void WaitFor(int q) const {
    for (int spins = 0;
         done_[static_cast<std::size_t>(q)].load(std::memory_order_acquire) != epoch_; ++spins) {
      if (spins >= 64) std::this_thread::yield();
    }
  }
  void MarkDone(int q) {
    done_[static_cast<std::size_t>(q)].store(epoch_, std::memory_order_release);
  }

 private:
  std::unique_ptr<std::atomic<std::uint32_t>[]> done_;
  std::size_t size_ = 0;
  std::uint32_t epoch_ = 0;
  std::atomic<int> next_{0};
};

// Inside an OpenMP parallel region (progress.Start(colouring.blocks()) called before it): the
// threads take the blocks in ForEachBlockByColour's order and sweep each once its dependencies
// are done, without a barrier between colours; f(slot_begin, slot_end) per block. The result is
// ForEachBlockByColour's. No barrier at the end.
template <typename F>
void ForEachBlockInDependencyOrder(const Colouring& colouring, const CellList& cells,
                                   BlockProgress& progress, F&& f) {
  const int* deps = colouring.dependencies();
  for (int q = progress.Take(); q < colouring.blocks(); q = progress.Take()) {
    for (int d = colouring.dependency_begin(q); d < colouring.dependency_begin(q + 1); ++d) {
      progress.WaitFor(deps[d]);
    }
    const int r = colouring.block_rank(q);
    f(cells.BlockSlotBegin(r), cells.BlockSlotBegin(r + 1));
    progress.MarkDone(q);
  }
}

}  // namespace moreau::particles::internal
