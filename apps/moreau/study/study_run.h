// `moreau study` for the paper's cases: every method at every step size against the exact
// (sliding) or a reference (disks) solution.
#pragma once

#include <string>
#include <vector>

#include "moreau/pbd/study.h"
#include "run/pbd_scenario.h"

namespace moreau::cli {

// The command-line part of a study.
struct StudyRequest {
  std::vector<std::string> methods;  // --methods: pbd, pngs, pgs, penalty[:γ]
  std::vector<double> hs;            // --h
  int fit_points = 4;                // --fit-points: the smallest h the order is fitted over
};

struct PbdStudyPlan {
  std::vector<pbd::MethodSpec> methods;
  std::vector<double> hs;  // decreasing
  int fit_points = 4;
};

// Validates the request against the scenario; throws InputError naming the flag.
PbdStudyPlan MakeStudyPlan(const StudyRequest& request, const PbdScenario& scenario);

struct PbdStudyResult {
  std::vector<pbd::StudyRow> rows;  // method by method, h decreasing
  double total_seconds = 0.0;       // reference and runs
};

// Computes the reference first when the scenario has no exact solution (its step must divide
// the smallest h: else InputError naming reference.h in the scenario file).
PbdStudyResult RunPbdStudy(const Scenario& file, const PbdScenario& scenario,
                           const PbdStudyPlan& plan);

}  // namespace moreau::cli
