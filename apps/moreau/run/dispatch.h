// The one place that tells apart the kinds of scenario `moreau run` runs and runs each: the
// paper's cases (problem.kind = "sliding", "disks": pbd_scenario → pbd_run → pbd_report), particles
// at scale with or without a room (problem.kind = "particles": particles_scenario →
// particles_run → particles_report) and agent-based models (a particle scenario with [[types]]:
// population_run). `moreau run` and every run of `moreau sweep` with command = "run" go through
// it, so a sweep's row holds what the run's summary.json holds.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "moreau/common/termination.h"
#include "output.h"
#include "scenario.h"

namespace moreau::cli {

enum class RunKind {
  kPaperCase,   // sliding, disks: the paper's steppers
  kParticles,   // the particle engine, a fixed set of particles (a room or not)
  kPopulation,  // the particle engine under an agent-based model's rules
};

// What a run writes into its output folder.
enum class RunFiles {
  kAll,        // `moreau run`: every file of its kind, figures included
  kNoFigures,  // a sweep's run folder: the same without the figures (no figure script runs)
  kNone,       // nothing: the summary is only returned (no trajectory either)
};

// How to run; the defaults are those of `moreau run` without flags.
struct RunRequest {
  RunFiles files = RunFiles::kAll;
  bool fix_overlaps = false;          // --fix-overlaps
  std::int64_t checkpoint_every = 0;  // --checkpoint-every (particle and population runs)
  std::string resume;                 // --resume DIR
  std::string out_dir;                // where the checkpoints go by default (<out_dir>.checkpoint)
  std::string fingerprint;            // ScenarioFingerprint, for the checkpoints
  bool check_only = false;  // read and check every key, set nothing up (the run cannot be run)
};

struct RunOutcome {
  nlohmann::json summary;  // what summary.json holds
  std::string report;      // the lines `moreau run` prints (empty with RunFiles::kNone)
  Termination termination = Termination::kCompleted;
  std::string message;  // why, when the run did not succeed
};

// A scenario read, checked and set up on its initial state, with nothing written yet.
class PreparedRun {
 public:
  // Reads every key of SCENARIO (CheckAllKeysUsed included), builds the model and the initial
  // state and, with checkpoints, plans them (restoring the engine from --resume). Throws
  // InputError "FILE: KEY: REASON" exactly as `moreau run` reports bad input.
  PreparedRun(Scenario& scenario, RunRequest request);
  ~PreparedRun();
  PreparedRun(PreparedRun&&) noexcept;
  PreparedRun& operator=(PreparedRun&&) noexcept;

  RunKind kind() const;

  // Runs it once over [0, T] and writes into the folder OUT_DIR what the request asks for
  // (nothing with RunFiles::kNone: then a particle run stages into a scratch folder that goes
  // with it). The folder is made when the run starts writing (OutputDir: staged, published
  // whole): particle runs stream their trajectory, the paper's cases write at the end, so a
  // signal during their run leaves nothing behind. Throws NumericalError when a requested
  // reference solution fails.
  RunOutcome Run(const std::filesystem::path& out_dir);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace moreau::cli
