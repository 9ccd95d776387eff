// The engine's state: the step context its parts share (step_context.h), the parts with buffers
// of their own (prediction, sweep, overlap monitor), the stage profile and the run's counters.
// engine.cpp steps it, engine_queries.cpp answers the queries, engine_checkpoint.cpp saves and
// restores it.
#pragma once

#include <optional>
#include <span>
#include <string>
#include <vector>

#include "moreau/particles/engine.h"
#include "particles/overlap_monitor.h"
#include "particles/prediction.h"
#include "particles/stage_profile.h"
#include "particles/step_context.h"
#include "particles/sweep.h"

namespace moreau::particles {

struct Engine::Impl {
  internal::StepContext context;
  Forces forces;
  std::optional<internal::Prediction> prediction;
  std::optional<internal::ProjectionSweep> sweep;
  internal::OverlapMonitor monitor;  // after each step (options.monitor_overlap)
  internal::StageProfile profile;
  double max_coordinate = 0.0;  // the last prediction's largest |Y_i,a|
  double last_step_move = 0.0;  // its largest move (whether to fuse the exact skin bound)
  // A build at the predicted positions left the current ones in the storage order before it:
  // only a redo needs them in the new order (FreshCurrent); the step's end replaces them.
  bool current_stale = false;

  std::int64_t step = 0;
  EngineStats stats;  // the counters (the timings are the profile's: Stats())
  Termination termination = Termination::kCompleted;
  std::string message;
  std::int64_t failed_step = -1;
  std::int64_t failed_particle = -1;
  std::vector<double> path_scratch;
  std::vector<double> sweep_start;  // the predicted positions before a single sweep

  // Validates and takes the model, forces, options and initial positions (the constructor).
  void Setup(std::span<const double> positions);
  // The parts made for context.model at `positions` (k·N, id order) with active velocities
  // (k·N or empty), and the list built there at the current step: the setup's and every
  // repopulation's.
  void ConfigureFor(std::span<const double> positions, std::span<const double> active);
  void ConfigureSkin();
  void Rebuild(std::vector<double>* at, std::int64_t at_step);
  internal::PredictionOutcome Predict(internal::ExactBound* bound = nullptr);
  void SweepUntilAccepted(double moved, int sweeps, bool relax);
  void Redo(bool relax);
  bool Step();
  void Monitor();
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
  // The counters with the profile's timings.
  EngineStats Stats() const {
    EngineStats s = stats;
    profile.Report(&s);
    return s;
  }
  // The largest pair overlap at the current positions, by a pass over every pair (the monitor
  // after a step needs fewer: overlap_monitor.h).
  double MaxOverlap() const {
    const internal::StepContext& c = context;
    return internal::MaxPairOverlap(c.list, c.store->current.data(), c.store->radius.data(), c.n,
                                    c.threads);
  }
  // Calls f(s, t) for every pair of slots that touch at the current positions,
  // ‖X_s − X_t‖ ≤ factor (r_s + r_t) with the pair's image on periodic axes: the engine's one
  // definition of touching (engine_queries.cpp).
  template <typename F>
  void ForEachContact(double factor, F&& f) const;
};

}  // namespace moreau::particles
