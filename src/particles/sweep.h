// The engine's PBD sweep: every candidate pair of the neighbour list (non-overlap), then for
// every particle its walls (model order), sphere obstacles and segment obstacles, each an exact
// projection (kernels.h).
//
// Order: kLexicographic visits the rows of slots 0 … N−1 on one thread (storage = id order);
// kColoured visits the colours in order, the blocks of one colour in parallel, each block's
// slots in storage order, then the fixed sets in chunks of 1024 slots. Both are the same for any
// thread count. The threads do not wait for a whole colour: a block starts once the blocks of
// smaller colours it depends on are done (colouring.h), which gives the same result.
//
// Path bounds: the sweep adds the length of every projection move to the moved particle's path
// (per sweep, reset lazily by a sweep stamp) and returns the longest path, which bounds how far
// any particle moved in the sweep (the neighbour list's no-missed-contact bound). The position of
// a slot before its first move in the sweep is kept beside its path (StartPositions).
#pragma once

#include <cstdint>
#include <vector>

#include "particles/segment_grid.h"
#include "particles/colouring.h"
#include "particles/neighbour_list.h"

namespace moreau::particles::internal {

struct StepContext;  // step_context.h

// What a sweep records for the overlap monitor (overlap_monitor.h): the rows with a pair closer
// than r_s + r_t + margin when the sweep visited it (each thread its own list), and the sweep's
// longest path.
struct NearContactRows {
  double margin = 0.0;
  std::vector<std::vector<int>> rows;  // per thread
  double max_path = 0.0;
};

class ProjectionSweep {
 public:
  // The fixed sets of the model (walls normalised) and n path slots; uniform_radius: all r_i
  // equal (the pair loop then skips the radius loads).
  ProjectionSweep(const ParticleModel& model, bool uniform_radius);

  // One sweep over the store's predicted positions with the context's list, colouring, cell
  // list, order and threads; adds the number of projections that moved a particle to
  // *projections and returns the longest path. near (optional): the rows near contact are
  // appended to near->rows[thread] (sized ≥ threads) and near->max_path is set.
  double Sweep(StepContext& context, std::int64_t* projections, NearContactRows* near = nullptr);

  // The length of the projection moves applied to slot s in the last sweep.
  double PathOf(int s) const {
    const auto us = static_cast<std::size_t>(s);
    return stamp_[us] == sweep_id_ ? path_[us] : 0.0;
  }
  // The positions before the last sweep, given x after it: a slot's position before its first
  // move in the sweep (kept by the sweep, only for the slots it moved), else x. The same values
  // as a copy of x taken before the sweep, without copying every step.
  void StartPositions(const double* x, std::vector<double>* start) const;
  // Sets visited per sweep besides the pairs: N · (walls + obstacles).
  int fixed_sets() const { return fixed_sets_; }
  // The largest violation of a wall or obstacle at x (0 when none is violated).
  double MaxFixedViolation(const double* x, const double* radius) const;

 private:
  template <int K, bool P>
  double SweepImpl(double* x, const double* radius, const NeighbourList& list,
                   const Colouring& colouring, const CellList& cells, bool lexicographic,
                   int threads, std::int64_t* projections, NearContactRows* near);
  template <int K, bool P, bool U, bool R>
  void SweepRows(int begin, int end, double* x, const double* radius, const NeighbourList& list,
                 double* max_path, std::int64_t* proj, double margin, std::vector<int>* near);
  template <int K>
  void SweepFixed(int begin, int end, double* x, const double* radius, double* max_path,
                  std::int64_t* proj);
  // Before slot s first moves in this sweep (not yet stamped): keep its position.
  template <int K>
  void KeepStart(int s, const double* xs) {
    if (stamp_[static_cast<std::size_t>(s)] == sweep_id_) return;
    double* keep = start_.data() + static_cast<std::ptrdiff_t>(K) * s;
    for (int a = 0; a < K; ++a) keep[a] = xs[a];
  }
  double AddPath(int s, double d) {
    const auto us = static_cast<std::size_t>(s);
    if (stamp_[us] != sweep_id_) {
      stamp_[us] = sweep_id_;
      path_[us] = 0.0;
    }
    path_[us] += d;
    return path_[us];
  }

  int k_ = 2;
  int n_ = 0;
  bool uniform_radius_ = false;
  // Fixed sets: unit wall normals (k per wall) and offsets (the radius is added per particle),
  // sphere centres and radii, segment ends.
  std::vector<double> wall_n_, wall_b_, sphere_c_, sphere_r_, seg_a_, seg_b_;
  int fixed_sets_ = 0;
  // The segments near each cell (cut-off 2 max r: a particle that moves by less than max r
  // through its segment projections meets only its start cell's segments); many segments only.
  SegmentGrid seg_grid_;
  double seg_reach_ = 0.0;  // max r
  std::vector<double> path_;
  std::vector<double> start_;  // k per slot: the position before the slot's first move
  std::vector<std::uint32_t> stamp_;
  std::uint32_t sweep_id_ = 0;
  BlockProgress progress_;  // the coloured sweep's block schedule
};

}  // namespace moreau::particles::internal
