// The scenario of `moreau run` and `moreau study` for the paper's cases (problem.kind = "sliding"
// or "disks"): [problem], [solver], [reference], [output], read through one field table per kind.
#pragma once

#include <memory>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "field_table.h"
#include "moreau/pbd/cases.h"
#include "moreau/pbd/particle_constraints.h"
#include "moreau/pbd/study.h"
#include "scenario.h"

namespace moreau::cli {

// The reference solver's defaults: PNGS with tight tolerances and a small step.
pbd::StepperOptions ReferenceSolverDefaults();

// The most disks of the disks case: its start and its feasibility check test all N²/2 pairs.
inline constexpr double kMaxAllPairsDisks = pbd::DisksCase::kMaxCount;

struct PbdScenario {
  std::string kind;                      // "sliding" or "disks"
  pbd::SlidingCase sliding;              // kind = "sliding"
  pbd::DisksCase disks;                  // kind = "disks"
  std::optional<pbd::Vector> positions;  // disks: initial positions given in the file
  pbd::StepperOptions solver;
  pbd::StepperOptions reference = ReferenceSolverDefaults();  // disks: the reference solution
  bool reference_for_run = false;  // disks: compute a reference in `moreau run` too
  std::int64_t output_stride = 0;  // frames written every stride steps; 0: about 1000 frames

  bool is_disks() const { return kind == "disks"; }
  double T() const { return is_disks() ? disks.T : sliding.T; }
  pbd::Vector InitialState() const;
  std::int64_t InitialStateSize() const { return is_disks() ? 2 * disks.count : sliding.dimension; }
  // Steps between written frames: output_stride, or about 1000 frames in all when it is 0.
  std::int64_t stride() const;
  // The problem for runs and studies; solution() is the exact solution (sliding) or, for disks,
  // empty until a reference is computed.
  pbd::StudyProblem MakeProblem() const;
  // The particle constraints of a disks scenario (the run reads their neighbour-list statistics).
  std::unique_ptr<pbd::ParticleConstraints> MakeParticleConstraints() const;
};

// The fields of KIND ("sliding" or "disks"), with [solver], [reference] and [output].
const FieldTable<PbdScenario>& PbdFields(const std::string& kind);

// Reads and validates every key; throws InputError "FILE: KEY: REASON". Call
// scenario.CheckAllKeysUsed() after any further reading.
PbdScenario ReadPbdScenario(Scenario& scenario);

// The settings used, as read: {"problem": {…}, "solver": {…}, "reference": {…}, "output": {…}}.
nlohmann::json EchoPbdScenario(const PbdScenario& scenario);

}  // namespace moreau::cli
