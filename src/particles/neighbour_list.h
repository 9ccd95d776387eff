// Verlet half-lists over the cell list, and the skin that keeps them exact.
//
// Build: for every slot s, the slots t > s with ‖X_s − X_t‖ < r_s + r_t + extra (minimum image on
// periodic axes, whose image code is kept per pair), visited in a fixed order: the adjacent
// cells z, y, x, each cell's slots in cell order (or, with sorted rows, by increasing t). The
// list is the same for any thread count.
//
// Skin: extra = attraction range + skin. A regular build happens when some position moved more
// than skin/4 from the last build; a step is accepted when the bound on every particle's distance
// from its build position stays below skin/2, else it is redone with a list built at its
// predicted positions (and, if that list was fresh already, a doubled skin that relaxes back by
// halves at later regular builds). A pair left out is then farther apart than contact
// throughout, so leaving it out changes no bit.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "particles/cell_list.h"
#include "particles/kernels.h"

namespace moreau::particles::internal {

struct StepContext;  // step_context.h

// How a build makes each slot's row: the partners as the cells are visited, the same sorted by
// increasing slot (the lexicographic order), or from an O(N²) loop over all pairs, sorted (the
// brute-force search, for tests of the grid).
enum class ListRows { kAsVisited, kSorted, kBruteForce };

// The exact skin bound: max_i ‖Y_i − reference_i‖² (worst2) over the slots and the count of
// slots with ‖Y_i − reference_i‖² > quarter2 (far), asked of a pass that reads Y anyway.
struct ExactBound {
  const double* reference = nullptr;  // k per slot, the build positions
  double quarter2 = 0.0;              // (skin/4)²
  double worst2 = 0.0;
  std::int64_t far = 0;
};

// Counters of one neighbour list; exact and independent of the thread count.
struct NeighbourListStats {
  std::int64_t builds = 0;
  std::int64_t candidate_pairs = 0;  // at the last build
  // The fewest steps between two builds (a redo's build counts at its step); −1 with one build.
  std::int64_t shortest_rebuild_interval = -1;
};

// What a resumed run needs besides the build positions to continue the list's decisions.
struct NeighbourListState {
  double skin = 0.0;
  double drift_bound = 0.0;
  std::int64_t last_build_step = -1;
  NeighbourListStats stats;
};

class NeighbourList {
 public:
  // n slots in `box`; skin > 0 (clamped to skin_limit, 0.99 of the room periodic axes leave);
  // attraction_range ≥ 0 widens every pair's reach.
  void Configure(const PeriodicBox& box, int n, double skin, double skin_limit,
                 double attraction_range);

  // Builds the list at x (slots in cell order when members is null, else the slots of cell rank
  // c are members[cell_start(c) …]), its rows made as `rows` says. Records x as the build
  // positions and the build at `step`.
  void Build(const double* x, const double* radius, const CellList& cells, const int* members,
             ListRows rows, std::int64_t step, int threads);
  // The engine's build at `at` (the store's current or predicted positions): the store's radii,
  // the context's cell list, members, rows and threads.
  void Build(const StepContext& context, const double* at, std::int64_t step);

  // The skin bound. BoundAfterPrediction: max_i ‖Y_i − X_i^build‖ from the bound of the last
  // accepted step plus step_move, or (when that reaches skin/4) exactly from y.
  // When computed exactly it also counts the slots beyond skin/4.
  // fused (optional): the exact bound already computed with the prediction (Prediction::Predict),
  // used instead of a pass over y when it is needed.
  double BoundAfterPrediction(double step_move, const double* y, int threads,
                              const ExactBound* fused = nullptr);
  // Whether the next BoundAfterPrediction will need the exact bound if the step moves slots by
  // about expected_move; the request for Prediction::Predict to compute it (with the build
  // positions and skin/4).
  bool ExactBoundLikely(double expected_move) const {
    return drift_bound_ + expected_move > 0.25 * skin_;
  }
  ExactBound ExactBoundRequest() const { return {reference_.data(), 0.0625 * skin_ * skin_}; }
  // A build is needed beyond skin/4, unless `few_may_pass` (one sweep per step: AcceptEach can
  // take the sweep) and only a few slots (≤ max(kMaxFastSlots, n/16), counted by the exact bound)
  // are there and none reached skin/2.
  bool NeedsBuild(double moved, bool few_may_pass = false) const {
    return moved > 0.25 * skin_ && !(few_may_pass && moved < 0.5 * skin_ &&
                                     far_slots_ <= std::max<std::int64_t>(kMaxFastSlots, n_ / 16));
  }
  // A regular build: a skin widened by redos relaxes back toward the nominal one.
  void RelaxSkin() { skin_ = std::max(std::min(nominal_skin_, skin_limit_), 0.5 * skin_); }
  // Accepts a step whose particles are within `moved` of their build positions (returns false
  // when a redo is needed: moved reached skin/2).
  bool Accept(double moved);
  // The per-particle test, after one sweep that Accept refused: start and x are the positions
  // before and after the sweep, path_s the length of the projection moves of slot s in it; then
  // b_s = (‖start_s − X_s^build‖ + ‖x_s − X_s^build‖ + path_s) / 2 bounds how far slot s was from
  // its build position during the sweep (a point of a path of length L from A to B is within L of
  // A and B together), and a pair left out of the list stayed apart while b_s + b_t < skin.
  // Accepts when every b_s < skin, at most max(kMaxFastSlots, n/16) slots are fast (b_f ≥
  // skin/2), and every fast slot f and every slot t within 2 cells of it (cells: the build's cell
  // list, members as in Build) are a pair of the list or were farther apart at the build than
  // r_f + r_t + ℓ + b_f + b_t; slots farther away are ≥ 2 min edge apart, which covers them. The
  // few slots a division or a deep overlap pushes far then cost no redo.
  bool AcceptEach(const double* start, const double* x, const double* radius,
                  const std::vector<double>& path, const CellList& cells, const int* members,
                  int threads);
  static constexpr int kMaxFastSlots = 64;
  // Before a redo: false when the skin cannot grow (it is at the periodic limit); else widens
  // the skin if the list was built at this step's predicted positions already.
  bool PrepareRedo();
  void MarkPredicted() { built_here_ = false; }
  // Where the storage reorder before the next Build writes that Build's positions (k per slot,
  // in the new order): that Build then copies none into its build positions.
  double* BuildPositionsTarget() {
    build_positions_written_ = true;
    return reference_.data();
  }
  // r > 0: every radius of later builds is r (a build then loads no radius); 0: radii differ.
  void AssumeUniformRadius(double r) { uniform_radius_ = r; }

  // For checkpoints: the state, the positions of the last build (storage order, wrapped), and
  // a restore (the skin before Build at reference(), everything after it).
  NeighbourListState State() const { return {skin_, drift_bound_, last_build_step_, stats_}; }
  void Restore(const NeighbourListState& state) {
    skin_ = state.skin;
    drift_bound_ = state.drift_bound;
    last_build_step_ = state.last_build_step;
    stats_ = state.stats;
  }
  const std::vector<double>& reference() const { return reference_; }

  const PeriodicBox& box() const { return box_; }
  double skin() const { return skin_; }
  double extra() const { return attraction_range_ + skin_; }
  // How far beyond contact the list still holds every pair: each pair closer than
  // r_s + r_t + coverage() now is in it (the build's reach less twice the drift bound since).
  double coverage() const { return built_extra_ - 2.0 * drift_bound_; }
  const NeighbourListStats& stats() const { return stats_; }
  std::int64_t pairs() const { return static_cast<std::int64_t>(nbr_.size()); }
  const int* row_start() const { return row_start_.data(); }
  const int* neighbours() const { return nbr_.data(); }
  const std::uint8_t* images() const { return image_.data(); }  // periodic boxes only
  // The slots with a non-empty row, increasing ([active_rows(), active_rows_end())): a sweep
  // visits only these, without a branch per empty row.
  const int* active_rows() const { return active_rows_.data(); }
  const int* active_rows_end() const { return active_rows_.data() + active_rows_.size(); }

  // u = X_s − X_t for the pair p = (s, t) of the list (its image on periodic axes).
  template <int K, bool P>
  void Displacement(const double* x, int s, int t, std::int64_t p, double* u) const {
    for (int a = 0; a < K; ++a) u[a] = x[K * s + a] - x[K * t + a];
    if constexpr (P) {
      const int code = image_[static_cast<std::size_t>(p)];
      if (code != 13) {
        for (int a = 0; a < K; ++a) u[a] -= box_.shift[code][a];
      }
    }
  }

  // The largest overlap max(0, r_s + r_t − ‖X_s − X_t‖) over the pairs of row s at x.
  template <int K, bool P>
  double RowOverlap(const double* x, const double* radius, int s) const {
    double worst = 0.0;
    const double ri = radius[s];
    for (std::int64_t p = row_start_[static_cast<std::size_t>(s)];
         p < row_start_[static_cast<std::size_t>(s) + 1]; ++p) {
      const int t = nbr_[static_cast<std::size_t>(p)];
      double u[K];
      Displacement<K, P>(x, s, t, p, u);
      const double c = ri + radius[t];
      const double r2 = SquaredNorm<K>(u);
      if (r2 >= c * c) continue;
      worst = std::max(worst, c - std::sqrt(r2));
    }
    return worst;
  }

 private:
  template <int K, bool P>
  void BuildRows(const double* x, const double* radius, const CellList& cells, const int* members,
                 ListRows rows, int threads);
  template <int K, bool P>
  void BuildCellRows(const double* x, const double* radius, const CellList& cells, int threads);
  template <int K, bool P, bool U>
  std::size_t FillBlocks(const double* x, const double* radius, const CellList& cells,
                         std::int64_t first, std::int64_t last, int q);
  void Concatenate(const double* x, int k, bool periodic, int chunks, int threads);
  bool Listed(int s, int t) const;
  template <int K>
  bool LocalPairsApart(int f, const CellList& cells, const int* members,
                       const double* radius) const;

  PeriodicBox box_;
  int n_ = 0;
  double skin_ = 0.0;
  double nominal_skin_ = 0.0;
  double skin_limit_ = std::numeric_limits<double>::infinity();
  double attraction_range_ = 0.0;
  double uniform_radius_ = 0.0;           // > 0: every radius (AssumeUniformRadius)
  bool built_here_ = false;               // built at the current predicted positions
  bool build_positions_written_ = false;  // BuildPositionsTarget was filled for the next Build
  double built_extra_ = 0.0;              // extra() at the last build
  double drift_bound_ = 0.0;    // ≥ max_i ‖X_i − X_i^build‖ after the last accepted step
  std::int64_t far_slots_ = 0;  // slots beyond skin/4 at the last exact bound (else INT64_MAX)
  std::int64_t last_build_step_ = -1;
  std::vector<double> reference_;  // positions at the last build
  // Half-lists: pairs (s, nbr_[p]) for p in [row_start_[s], row_start_[s + 1]), nbr_ > s.
  std::vector<int> row_start_;  // int: the list is capped at INT_MAX pairs
  std::vector<int> nbr_;
  std::vector<std::uint8_t> image_;          // per pair, periodic only: the image code
  std::vector<int> active_rows_;             // the slots with a non-empty row, increasing
  std::vector<std::int64_t> chunk_active_;   // build: the non-empty rows of chunk q
  std::vector<double> bound_;                // per slot, AcceptEach's b_s
  std::vector<std::vector<int>> chunk_nbr_;  // build buffers, reused
  std::vector<std::vector<std::uint8_t>> chunk_image_;
  std::vector<int> chunk_slot_;  // chunk q holds the rows of slots [chunk_slot_[q], [q + 1])
  std::vector<std::size_t> chunk_used_;  // the entries of chunk q's buffers that hold its rows
  NeighbourListStats stats_;
};

// The pairs i < j in lexicographic order (id-order slots, rows sorted by j) with
// ‖X_i − X_j‖ < r_i + r_j + skin, from a cell list of its own, on one thread: the neighbour search
// of the initial-state checks and of pbd::ParticleConstraints. Buffers are kept between builds.
class LexicographicPairList {
 public:
  // n particles of radii ≤ max_radius in `box`; skin > 0.
  LexicographicPairList(const PeriodicBox& box, int n, double max_radius, double skin);
  // Builds at x (n points, wrapped into the box) with the given radii.
  void Build(const double* x, const double* radius);
  const NeighbourList& list() const { return list_; }

 private:
  PeriodicBox box_;
  double reach_;
  CellList cells_;
  NeighbourList list_;
  std::vector<int> id_;
};

// The largest pair overlap max(0, r_s + r_t − ‖X_s − X_t‖) over the list's pairs at x.
double MaxPairOverlap(const NeighbourList& list, const double* x, const double* radius, int n,
                      int threads);

}  // namespace moreau::particles::internal
