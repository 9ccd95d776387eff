// The engine's state and its parts (engine.cpp; the checkpoint's save and restore in
// engine_checkpoint.cpp).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "moreau/particles/engine.h"
#include "particles/cell_list.h"
#include "particles/colouring.h"
#include "particles/neighbour_list.h"
#include "particles/overlap_monitor.h"
#include "particles/particle_store.h"
#include "particles/prediction.h"
#include "particles/sweep.h"

namespace moreau::particles {

struct Engine::Impl {
  ParticleModel model;
  Forces forces;
  EngineOptions options;
  int k = 2;
  int n = 0;
  int threads = 1;
  bool lexicographic = false;
  double rmax = 0.0;
  double attraction_range = 0.0;  // how far the lists reach beyond contact (PairListWidening)
  internal::PeriodicBox box;

  // The parts, each owning its data.
  std::optional<internal::ParticleStore> store;
  internal::CellList cells;
  internal::Colouring colouring;
  internal::NeighbourList list;
  std::optional<internal::Prediction> prediction;
  std::optional<internal::ProjectionSweep> sweep;
  internal::OverlapMonitor monitor;  // after each step (options.monitor_overlap)
  double max_coordinate = 0.0;       // the last prediction's largest |Y_i,a|
  double last_step_move = 0.0;       // its largest move (whether to fuse the exact skin bound)
  // A build at the predicted positions left the current ones in the storage order before it:
  // only a redo needs them in the new order (FreshCurrent); the step's end replaces them.
  bool current_stale = false;

  std::int64_t step = 0;
  EngineStats stats;
  Termination termination = Termination::kCompleted;
  std::string message;
  std::int64_t failed_step = -1;
  std::int64_t failed_particle = -1;

  void Setup(std::span<const double> positions);
  void ConfigureSkin();
  void Rebuild(std::vector<double>* at, std::int64_t at_step);
  void Predict(double* max_move, std::int64_t* bad_id, internal::ExactBound* bound = nullptr);
  void SweepUntilAccepted(double moved, int sweeps, bool relax);
  bool Step();
  void Restore(const EngineState& state);  // engine_checkpoint.cpp
  void Repopulate(std::span<const double> positions, std::span<const double> active);
  int Relax(double tolerance, int max_sweeps);
  void Fail(std::int64_t bad);
  void FreshCurrent();  // the current positions in the storage order (after current_stale)
  // Calls FreshCurrent however its scope ends: a step or relaxation that throws keeps its last
  // good state in the storage order.
  struct FreshCurrentOnExit {
    Impl* engine;
    ~FreshCurrentOnExit() { engine->FreshCurrent(); }
  };
  bool AcceptEach();
  std::vector<double> path_scratch;
  std::vector<double> sweep_start;  // the predicted positions before a single sweep
  // The largest pair overlap at the current positions, by a pass over every pair (the monitor
  // after a step needs fewer: overlap_monitor.h).
  double MaxOverlap() const {
    return internal::MaxPairOverlap(list, store->current.data(), store->radius.data(), n, threads);
  }
};

}  // namespace moreau::particles
