// `moreau run --checkpoint-every K [--resume DIR]` for particle runs: every K steps the engine's
// state (particles/checkpoint.h) and the run's recorder state (the trajectory frames and
// snapshots so far) go atomically into DIR/checkpoint.bin, DIR = --resume's folder or
// <out>.checkpoint; `--resume DIR` continues from it and gives the same bits (positions,
// counters, trajectory datasets) as a run that never stopped.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "moreau/particles/engine.h"
#include "run/particles_scenario.h"

namespace moreau::cli {

struct CheckpointPlan {
  std::int64_t every = 0;                 // a checkpoint every `every` steps (0: none)
  std::filesystem::path file;             // DIR/checkpoint.bin
  std::string fingerprint;                // of the scenario: a resume must match it
  std::optional<nlohmann::json> resumed;  // the recorder's state when resuming
};

// What makes two runs the same run: the scenario file's bytes, the --set overrides other than
// solver.threads (the bits do not depend on it) and --fix-overlaps, hashed (16 hex digits).
std::string ScenarioFingerprint(const std::string& scenario_path,
                                const std::vector<std::string>& overrides, bool fix_overlaps);

// Throws InputError unless every ≥ 0 and, when checkpointing or resuming, the scenario has no
// [[types]] (population) or [room] (their state is not saved yet).
void CheckCheckpointFlags(const ParticleScenario& scenario, std::int64_t every,
                          const std::string& resume_dir);

// CheckCheckpointFlags and, with --resume, reads
// DIR/checkpoint.bin, checks that it was made for this scenario and restores the engine from it.
// Throws InputError "--resume: …" / "FILE: checkpoint: …" before anything is written.
CheckpointPlan PlanCheckpoints(const ParticleScenario& scenario, std::int64_t every,
                               const std::string& resume_dir, const std::string& out_dir,
                               std::string fingerprint, particles::Engine& engine);

// Writes the engine's state and `recorder` (the caller's state) to plan.file, atomically.
void WriteRunCheckpoint(const CheckpointPlan& plan, const particles::Engine& engine,
                        nlohmann::json recorder);

}  // namespace moreau::cli
