// `moreau run` for particles at scale: the scenario's model, forces and engine options, the
// initial state, and Engine::Run with an observer that writes the trajectory (HDF5 + XDMF, VTU)
// as it goes and records the snapshot frames and the evacuation series.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "moreau/particles/engine.h"
#include "output.h"
#include "run/particles_checkpoint.h"
#include "run/particles_scenario.h"
#include "scenario.h"

namespace moreau::cli {

// A run ready to go: the engine on its initial state.
struct ParticleSetup {
  particles::Engine engine;
  std::vector<double> x0;       // the initial positions, id order (for the displacement)
  int fix_overlaps_sweeps = 0;  // FixOverlaps sweeps on the initial state (0: not asked, or
                                // feasible already)
  std::int64_t steps = 0;       // T / h
};

// Builds the model, forces, options and initial state (random sequential addition unless given,
// then FixOverlaps when asked) and the engine, which checks the initial state. Throws InputError
// "FILE: KEY: REASON" (KEY: problem, initial), before anything is written.
// The initial positions (k·N): initial.positions, or random sequential addition in the start
// region [initial.lo, initial.hi] (default: the domain) with problem.seed; errors name "initial".
std::vector<double> InitialPositions(const ParticleScenario& scenario,
                                     const particles::ParticleModel& model, const Scenario& file);

ParticleSetup SetUpParticleRun(const ParticleScenario& scenario, const Scenario& file);

struct ParticleRunResult {
  particles::EngineSummary summary;
  std::vector<double> x;         // final positions, id order
  std::optional<int> evacuated;  // with a room: people out at the end
  std::string evacuation_csv;    // with a room or a geometry: "t,out", one row per step
  std::vector<std::pair<double, std::vector<double>>> snapshots;  // (t, positions in id order)
  bool hdf5 = false;                                              // trajectory.h5 + .xdmf written
  bool vtu = false;                                               // vtu/frame.pvd written
  bool geometry = false;  // geometry.vtp written (walls and obstacles)
  bool txt = false;       // trajectory.txt written
  std::string exits_csv;  // with a geometry of several exits: "id,exit" per person out
};

// Runs the engine over [0, T] (with a progress bar on a terminal), writing the trajectory into
// `out` (staged); after a numerical failure the last good frame is written too. With
// checkpoints.every > 0 a checkpoint every so many steps (the frames so far are kept in memory
// for it); with checkpoints.resumed the engine is on the checkpoint's step already, and the
// frames and snapshots it holds are written first.
ParticleRunResult RunParticles(const ParticleScenario& scenario, ParticleSetup& setup,
                               OutputDir& out, const CheckpointPlan& checkpoints = {});

}  // namespace moreau::cli
