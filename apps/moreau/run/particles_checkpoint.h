// `moreau run --checkpoint-every K [--resume DIR]` for particle runs (a room or not) and
// agent-based runs: every K steps the engine's state (particles/checkpoint.h), a population's
// agents and counters, and the run's recorder state (the trajectory frames so far, the
// evacuation series, population.csv and the lineage so far) go atomically into
// DIR/checkpoint.bin, DIR = --resume's folder or <out>.checkpoint; `--resume DIR` continues from
// it and gives the same bits (positions, counters, output files, trajectory datasets) as a run
// that never stopped.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "moreau/particles/checkpoint.h"
#include "moreau/particles/engine.h"
#include "moreau/particles/population.h"

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

// Restores a run from a checkpoint's engine state and its run part.
using CheckpointRestore =
    std::function<void(const particles::EngineState& engine, const nlohmann::json& run)>;

// Throws InputError unless every ≥ 0. With --resume, reads DIR/checkpoint.bin, checks that it was
// made for this scenario and hands it to `restore`. Throws InputError "--resume: …" /
// "FILE: checkpoint: …" before anything is written.
CheckpointPlan PlanCheckpoints(std::int64_t every, const std::string& resume_dir,
                               const std::string& out_dir, std::string fingerprint,
                               const CheckpointRestore& restore);
// The same restoring an engine, or a population (its state in the run part's "population").
CheckpointPlan PlanCheckpoints(std::int64_t every, const std::string& resume_dir,
                               const std::string& out_dir, std::string fingerprint,
                               particles::Engine& engine);
CheckpointPlan PlanCheckpoints(std::int64_t every, const std::string& resume_dir,
                               const std::string& out_dir, std::string fingerprint,
                               particles::Population& population);

// Writes the engine's (or the population's) state and `recorder` (the caller's state) to
// plan.file, atomically.
void WriteRunCheckpoint(const CheckpointPlan& plan, const particles::Engine& engine,
                        nlohmann::json recorder);
void WriteRunCheckpoint(const CheckpointPlan& plan, const particles::Population& population,
                        nlohmann::json recorder);

// Whether a run observed at `step` writes a checkpoint: it crossed a multiple of plan.every since
// `last` (the step of the last checkpoint or of the start) and is not at the end (`steps`).
inline bool CheckpointDue(const CheckpointPlan& plan, std::int64_t last, std::int64_t step,
                          std::int64_t steps) {
  return plan.every > 0 && step < steps && step / plan.every > last / plan.every;
}

}  // namespace moreau::cli
