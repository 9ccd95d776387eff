// Checkpoints of the particle engine: everything a run needs to continue bit-for-bit as if it had
// never stopped (the noise is a pure function of (seed, id, step), so the step index is its whole
// state; the sweep order depends on the neighbour list's last build, so that is saved too).
//
// A checkpoint file is "MOREAUCK" (8 bytes), the payload size (8 bytes, little-endian), its
// FNV-1a 64-bit hash (8 bytes), then the payload: CBOR of {"engine": the state, "run": what the
// caller adds (its scenario fingerprint, its recorder's state)}. Doubles are stored as 64-bit
// floats, so every bit comes back.
#pragma once

#include <cstdint>
#include <filesystem>
#include <vector>

#include <nlohmann/json.hpp>

#include "moreau/particles/engine.h"
#include "moreau/particles/population.h"

namespace moreau::particles {

// The engine between two steps (Engine::SaveState / RestoreState).
struct EngineState {
  int dimension = 2;              // k
  int count = 0;                  // N
  std::int64_t step = 0;          // steps taken
  std::vector<int> slot_ids;      // N: the particle id of each storage slot
  std::vector<double> current;    // k·N, storage order: positions (unwrapped between builds)
  std::vector<double> reference;  // k·N, storage order: positions at the last list build
  double skin = 0.0;              // Verlet skin now (a widened one relaxes later)
  double drift_bound = 0.0;       // bound on ‖X_i − X_i^build‖ after the last step
  std::int64_t last_build_step = -1;
  std::int64_t shortest_rebuild_interval = -1;
  double grid_lo[3] = {0.0, 0.0, 0.0};  // the bounding box the cell grid was fitted to
  double grid_hi[3] = {0.0, 0.0, 0.0};
  double grid_reach = 0.0;
  EngineStats stats;  // counters carry on; timings too

  nlohmann::json ToJson() const;
  // Throws InputError naming the field for a missing or mistyped one.
  static EngineState FromJson(const nlohmann::json& j);
};

// A population between two steps (Population::SaveState / RestoreState): its engine and what the
// rules need to go on. The rules' randomness is Philox4x32 keyed by (seed, id, step), a pure
// function, so it has no state of its own; the motility and the ids in use follow from the
// agents. User code (drift, rule) is not state: the caller sets it again.
struct PopulationState {
  EngineState engine;
  std::vector<Agent> agents;                   // index order (the engine's particle ids)
  std::vector<std::vector<double>> variables;  // per declared variable, N values
  std::vector<double> last_positions;          // at the last rule step (velocity alignment)
  std::vector<std::int64_t> last_deaths, last_removals;  // of the last rule step
  PopulationSummary counters;  // rule steps, births, …, timings, termination (not engine/settings)
  double overlap_before = 0.0;
  bool stopped = false;
  // With diffusing fields (Population::CoupleFields): per substrate the grid's values, and the
  // samples at the agents (N and k·N); the fields' time and step count. A checkpoint stores the
  // arrays as bytes (CBOR byte strings of little-endian doubles), every bit kept.
  std::vector<std::vector<double>> field_values, field_samples, field_gradients;
  double field_time = 0.0;
  std::int64_t field_steps = 0;

  // Everything but `engine` (a checkpoint file stores that in its own part).
  nlohmann::json ToJson() const;
  // Throws InputError "checkpoint: …" naming a missing or mistyped field.
  static PopulationState FromJson(const nlohmann::json& j, EngineState engine);
};

// Writes the checkpoint atomically: into PATH.tmp, flushed, then renamed onto PATH. Throws
// InputError naming the file when it cannot be written.
void WriteCheckpoint(const std::filesystem::path& path, const EngineState& state,
                     const nlohmann::json& run);

// Reads a checkpoint; *run receives the caller's part. Throws InputError "FILE: checkpoint: …"
// for a missing, truncated or corrupt file (bad magic, size or hash, or a malformed payload).
EngineState ReadCheckpoint(const std::filesystem::path& path, nlohmann::json* run);

}  // namespace moreau::particles
