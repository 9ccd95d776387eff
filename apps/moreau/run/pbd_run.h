// `moreau run` for the paper's cases: one simulation of a PbdScenario.
#pragma once

#include <optional>
#include <vector>

#include "moreau/pbd/particle_constraints.h"
#include "moreau/pbd/stepper.h"
#include "run/pbd_scenario.h"

namespace moreau::cli {

// A state written to trajectory.csv.
struct TrajectoryFrame {
  double t = 0.0;
  pbd::Vector x;
};

struct PbdRunResult {
  pbd::SimulationSummary summary;
  // max_k ‖x_k − x(t_k)‖ against the exact (sliding) or reference (disks with
  // reference.compute) solution; empty when there is none or the run failed.
  std::optional<double> error;
  std::vector<TrajectoryFrame> frames;  // every output.stride steps, and the last step
  std::optional<pbd::NeighbourListStats> neighbour_list;  // disks
};

// Runs the scenario's solver over [0, T] (with a progress bar on a terminal). Throws
// NumericalError when a requested reference solution fails.
PbdRunResult RunPbdScenario(const PbdScenario& scenario);

}  // namespace moreau::cli
