// Reading a PBD scenario ([problem], [solver], [reference], [output]) into the library's models.
#pragma once

#include <memory>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "moreau/pbd/cases.h"
#include "moreau/pbd/study.h"
#include "scenario.h"

namespace moreau::cli {

struct PbdScenario {
  std::string kind;  // "sliding" or "disks"
  std::optional<pbd::SlidingCase> sliding;
  std::optional<pbd::DisksCase> disks;
  std::optional<pbd::Vector> positions;  // disks: initial positions given in the file
  pbd::StepperOptions solver;
  pbd::StepperOptions reference;         // disks: how the reference solution is computed
  bool reference_for_run = false;        // disks: compute a reference in `moreau run` too
  std::int64_t output_stride = 0;        // 0: about 1000 frames

  double T() const { return sliding ? sliding->T : disks->T; }
  // The problem for runs and studies; solution() is the exact solution (sliding) or, for disks,
  // empty until SetReference().
  pbd::StudyProblem MakeProblem() const;
  pbd::Vector InitialState() const;
  nlohmann::json ToJson() const;  // the settings used, written next to every result
};

// Reads and validates every key; throws InputError "FILE: KEY: REASON". Call
// scenario.CheckAllKeysUsed() after any further reading.
PbdScenario ReadPbdScenario(Scenario& scenario);

}  // namespace moreau::cli
