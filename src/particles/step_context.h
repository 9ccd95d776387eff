// What the engine's parts share in a step, in one place the engine owns: the model and options,
// the particle store (positions, radii, mobilities, ids, noise keys, active velocities), the
// cell list with its colouring, the neighbour list and the schedule (threads, sweep order,
// neighbour search). A part's step function (the list build, the prediction, the sweep, the
// overlap monitor) takes the context and reads what it needs from it; the prediction, the sweep
// and the monitor keep their own buffers.
#pragma once

#include <optional>

#include "moreau/particles/engine.h"
#include "particles/cell_list.h"
#include "particles/colouring.h"
#include "particles/kernels.h"
#include "particles/neighbour_list.h"
#include "particles/particle_store.h"

namespace moreau::particles::internal {

struct StepContext {
  ParticleModel model;
  EngineOptions options;
  int k = 2;
  int n = 0;
  int threads = 1;
  // SweepOrder::kLexicographic: the storage stays in id order (slots are ids), list rows are
  // sorted, one thread. Otherwise the storage follows the cell list (coloured order).
  bool lexicographic = false;
  double rmax = 0.0;              // the largest radius
  double attraction_range = 0.0;  // how far the lists reach beyond contact (PairListWidening)
  PeriodicBox box;
  std::optional<ParticleStore> store;
  CellList cells;
  Colouring colouring;
  NeighbourList list;

  // The slots of each cell for a list build: none (the storage is in cell order) unless the
  // order is lexicographic.
  const int* members() const { return lexicographic ? cells.permutation().data() : nullptr; }
  // How a list build makes its rows: sorted for the lexicographic order, from all pairs for the
  // brute-force search.
  ListRows rows() const {
    if (options.search == NeighbourSearch::kBruteForce) return ListRows::kBruteForce;
    return lexicographic ? ListRows::kSorted : ListRows::kAsVisited;
  }
};

}  // namespace moreau::particles::internal
