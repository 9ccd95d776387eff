// `moreau study` for the paper's cases: every method at every step size against the exact
// (sliding) or a reference (disks) solution.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "moreau/pbd/study.h"
#include "moreau/sweep/dispatch.h"
#include "moreau/sweep/grid.h"
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
  std::int64_t runs = 0;            // in the grid: rows.size() unless interrupted
  bool interrupted = false;  // a stop request (signals.h) ended it: rows holds the runs finished
};

// The study's runs as a sweep grid: axes "method" (labels) and "h", crossed, so run i is method
// i / hs.size() at step hs[i % hs.size()], the order of the rows.
sweep::Grid StudyGrid(const PbdStudyPlan& plan);

// Runs the grid through sweep::Dispatch: `jobs` threads per process, over MPI ranks when
// launched by mpirun/srun. Computes the reference first (on every rank) when the scenario has no
// exact solution (its step must divide the smallest h: else InputError naming reference.h in
// the scenario file). Returns the rows on rank 0, nothing on the other ranks. After a stop
// request no run starts and the runs under way stop at their next step: the result holds the
// runs that finished, marked interrupted.
std::optional<PbdStudyResult> RunPbdStudy(const sweep::MpiSession& mpi, const Scenario& file,
                                          const PbdScenario& scenario, const PbdStudyPlan& plan,
                                          int jobs);

}  // namespace moreau::cli
