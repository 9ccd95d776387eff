// The particle core's one cell grid: a uniform grid of cells (edge ≥ the pair reach) over the
// particles' bounding box (periodic axes: the domain), its cells ranked along a Morton curve of
// blocks, and the particles counting-sorted into cells. It serves the engine (neighbour lists,
// storage order, colouring), the initial-state checks and pbd::ParticleConstraints.
//
// CellGrid is the geometry alone (cell coordinates, adjacent cells); CellList owns a grid fitted
// to positions, the blocks of block_edge^k cells in Morton order, the rank of every cell (blocks
// in Morton order, cells row-major inside a block) and, after Sort, the slots of every cell.
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include "particles/kernels.h"

namespace moreau::particles::internal {

// Cells of edge `edge[a]` over [lo, lo + nc·edge) on each axis; axes ≥ k have one cell.
struct CellGrid {
  int k = 2;
  int nc[3] = {1, 1, 1};
  double lo[3] = {0.0, 0.0, 0.0};
  double edge[3] = {1.0, 1.0, 1.0};
  double inv[3] = {0.0, 0.0, 0.0};  // nc / span
  bool periodic[3] = {false, false, false};

  // Fits nc[a] cells of edge ≥ min_edge to [lo[a], hi[a]] (span = len[a] on periodic axes),
  // halving every axis while there are more than max_cells cells.
  void Fit(int dimension, const double* lo_in, const double* hi_in, const PeriodicBox& box,
           double min_edge, std::int64_t max_cells);
  std::int64_t cells() const { return static_cast<std::int64_t>(nc[0]) * nc[1] * nc[2]; }
  // The cell coordinate of v on axis a, clamped into [0, nc[a]) (NaN: 0).
  int Coord(int a, double v) const {
    const double t = (v - lo[a]) * inv[a];
    return !(t >= 0.0) ? 0 : (t >= nc[a] ? nc[a] - 1 : static_cast<int>(t));
  }
  std::int64_t Index(int x, int y, int z) const {
    return (static_cast<std::int64_t>(z) * nc[1] + y) * nc[0] + x;
  }
  // The row-major index of the cell holding x (k coordinates).
  std::int64_t CellOf(const double* x) const {
    int c[3] = {0, 0, 0};
    for (int a = 0; a < k; ++a) c[a] = Coord(a, x[a]);
    return Index(c[0], c[1], c[2]);
  }
  // Calls f(row-major cell) for the cells adjacent to the cell holding x (itself included), each
  // once, z then y then x outermost to innermost; periodic axes wrap around. A pair closer than
  // the cell edge lies in adjacent cells.
  template <int K, typename F>
  void ForEachAdjacentCell(const double* x, F&& f) const {
    ForEachCellWithin<K>(x, 1, f);
  }
  // The same for the cells at most `ring` cells away on every axis (ring ≥ 1). A pair in cells
  // farther apart is at least ring · min edge apart.
  template <int K, typename F>
  void ForEachCellWithin(const double* x, int ring, F&& f) const {
    int lo_c[3] = {0, 0, 0}, hi_c[3] = {0, 0, 0};
    for (int a = 0; a < K; ++a) {
      const int c = Coord(a, x[a]);
      if (periodic[a] && nc[a] >= 2 * ring + 1) {
        lo_c[a] = c - ring;
        hi_c[a] = c + ring;
      } else if (periodic[a]) {
        lo_c[a] = 0;
        hi_c[a] = nc[a] - 1;
      } else {
        lo_c[a] = std::max(0, c - ring);
        hi_c[a] = std::min(nc[a] - 1, c + ring);
      }
    }
    for (int z = lo_c[2]; z <= hi_c[2]; ++z) {
      const int zz = z < 0 ? z + nc[2] : (z >= nc[2] ? z - nc[2] : z);
      for (int y = lo_c[1]; y <= hi_c[1]; ++y) {
        const int yy = y < 0 ? y + nc[1] : (y >= nc[1] ? y - nc[1] : y);
        const std::int64_t row = (static_cast<std::int64_t>(zz) * nc[1] + yy) * nc[0];
        for (int xx = lo_c[0]; xx <= hi_c[0]; ++xx) {
          f(row + (xx < 0 ? xx + nc[0] : (xx >= nc[0] ? xx - nc[0] : xx)));
        }
      }
    }
  }
};

class CellList {
 public:
  // Fits the grid to x (n points, box.k coordinates, wrapped) for pairs closer than `reach`:
  // non-periodic axes cover the bounding box widened by 2·reach on each side, at most
  // max(64, 4n) cells (and fewer than 2^31). The previous geometry is kept while it covers the box,
  // is not much larger (≤ 1.5 span + 8 reach) and was made for the same reach. block_cells > 0
  // fixes the block edge; 0 picks it from the cell count (EngineOptions::block_cells). Returns true
  // when the geometry (and so the block ranks) changed.
  bool Fit(const double* x, int n, const PeriodicBox& box, double reach, int block_cells,
           int threads);
  // The bounding box (before widening) and reach the current geometry was made for: with the
  // same n and block_cells, Refit(fit()) gives the same geometry (a resumed run's).
  struct FitRecord {
    double lo[3] = {0.0, 0.0, 0.0};
    double hi[3] = {0.0, 0.0, 0.0};
    double reach = 0.0;
  };
  const FitRecord& fit() const { return fit_; }
  void Refit(const FitRecord& fit, int n, const PeriodicBox& box, int block_cells);
  // Sorts the slots into cells: permutation()[q] for q in [cell_start(c), cell_start(c + 1)) are
  // the slots of the cell of rank c, by increasing id[slot]. Stable and the same for any thread
  // count.
  void Sort(const double* x, const int* id, int n, int threads);
  // Fit, then Sort, with one pass over x fewer when a geometry for this reach exists: the sort
  // also finds the bounding box, and sorts again only when the geometry changed. Returns Fit's
  // answer; the geometry and order are Fit's and Sort's.
  bool FitAndSort(const double* x, const int* id, int n, const PeriodicBox& box, double reach,
                  int block_cells, int threads);

  const CellGrid& grid() const { return grid_; }
  std::int64_t cells() const { return static_cast<std::int64_t>(cell_rank_.size()); }
  // Rank of the row-major cell index.
  std::int64_t rank(std::int64_t cell) const { return cell_rank_[static_cast<std::size_t>(cell)]; }
  std::int64_t cell_start(std::int64_t rank) const {
    return cell_start_[static_cast<std::size_t>(rank)];
  }
  // cell_starts()[c] = cell_start(c), for c in [0, cells()].
  const std::int32_t* cell_starts() const { return cell_start_.data(); }
  const std::vector<int>& permutation() const { return perm_; }
  // The cell rank of each entry of permutation() (of each slot, once storage is in cell order).
  const std::int32_t* sorted_ranks() const { return sorted_rank_.data(); }
  // Blocks: nb per axis; the block of rank r has row-major index block_of_rank()[r] and covers
  // the cells of ranks [block_cell_begin(r), block_cell_begin(r + 1)).
  const int* blocks_per_axis() const { return nb_; }
  std::int64_t blocks() const { return static_cast<std::int64_t>(block_of_rank_.size()); }
  const std::vector<std::int64_t>& block_of_rank() const { return block_of_rank_; }
  std::int64_t block_cell_begin(std::int64_t r) const {
    return block_cell_begin_[static_cast<std::size_t>(r)];
  }
  // The block of rank r covers the cells origin[a] + [0, width[a]) on each axis (1 on axes ≥ k);
  // its cell (lx, ly, lz) has rank block_cell_begin(r) + (lz·width[1] + ly)·width[0] + lx.
  void BlockShape(std::int64_t r, int* origin, int* width) const;
  // The rank of the block next to the block of rank r on axis a (step ±1), or −1 past the grid's
  // end (periodic axes are not wrapped around).
  std::int64_t AdjacentBlock(std::int64_t r, int a, int step) const;
  // The slots [begin, end) of the block of rank r once storage is in cell order.
  int BlockSlotBegin(std::int64_t r) const {
    return static_cast<int>(cell_start(block_cell_begin(r)));
  }

 private:
  struct SortTeam;  // cell_sort.cpp
  bool KeepsGeometry(const double* lo, const double* hi, double reach) const;
  bool RefitUnlessKept(double* lo, double* hi, int n, const PeriodicBox& box, double reach,
                       int block_cells);
  void ChooseBlocks(int block_cells);
  void RankBlocks();
  void RankCells();
  template <int K>
  std::int64_t CountKeys(const double* x, int sb, int se, std::int64_t cb, std::int64_t ce,
                         std::vector<int>* foreign, double* lo, double* hi);
  void SortCellsById(const int* id, std::int64_t begin, std::int64_t end);

  CellGrid grid_;
  bool have_geometry_ = false;
  double reach_ = 0.0;  // the reach the geometry was made for
  FitRecord fit_;
  double sorted_lo_[3] = {0, 0, 0};  // the last Sort's smallest and largest coordinates per axis
  double sorted_hi_[3] = {0, 0, 0};
  int nb_[3] = {1, 1, 1};
  int block_edge_ = 8;
  std::vector<std::int64_t> block_of_rank_;
  std::vector<std::int64_t> rank_of_block_;
  std::vector<std::int64_t> block_cell_begin_;  // size blocks + 1
  // 32-bit: fewer than 2^31 cells (Refit) and slots; half the memory of 64-bit entries.
  std::vector<std::int32_t> cell_rank_;   // row-major cell → rank
  std::vector<std::int32_t> cell_start_;  // rank → first entry of perm_; size cells + 1
  std::vector<int> key_;                  // per slot: the rank of its cell
  std::vector<int> perm_;
  std::vector<std::int32_t> sorted_rank_;  // per entry of perm_: its cell's rank
  std::vector<std::vector<int>> foreign_;  // per thread: slots outside its cells (Sort)
};

// Morton code of the cell/block coordinates c (k of them, < 2^21 each).
std::uint64_t Morton(const int* c, int k);

}  // namespace moreau::particles::internal
