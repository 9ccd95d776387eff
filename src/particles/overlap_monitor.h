// The engine's overlap monitor (EngineOptions::monitor_overlap): after every step the largest pair
// overlap max(0, r_s + r_t − ‖X_s − X_t‖) over the neighbour list's pairs (which hold every
// overlapping pair), exact, mostly without a pass over all pairs.
//
// The step's last sweep records the rows that had a pair closer than r_s + r_t + m when it
// visited them (ProjectionSweep, NearContactRows), m the margin, and its longest path P. During
// the sweep a pair's distance changes only by the moves of its two particles, each at most P
// along its path, so a pair visited at distance ≥ r_s + r_t + m (not projected) ends at
// ≥ r_s + r_t + m − 2P. When m ≥ 2P + slack (slack = 2^−30 × the length scale of the positions,
// far above their rounding) the overlapping pairs are all in the recorded rows, and only those
// are measured; otherwise every row is (the previous pass). Either way the value is the exact
// maximum, the same bits for any thread count (a max over the same pairs, each computed as in
// MaxPairOverlap). The margin follows the paths: m = max(4P, m/2) + 2 slack after each step.
#pragma once

#include <cstdint>

#include "particles/neighbour_list.h"
#include "particles/sweep.h"

namespace moreau::particles::internal {

struct StepContext;  // step_context.h

class OverlapMonitor {
 public:
  // Before the last sweep of a step: the record for the sweep (rows cleared, the margin set).
  NearContactRows* Prepare(int threads);
  // After the step: the largest pair overlap at the store's current positions over the
  // context's list. max_coordinate: a bound on |x_i,a| before the sweep (the prediction's).
  double Measure(const StepContext& context, double max_coordinate);
  // Steps measured from the recorded rows only, and from every row.
  std::int64_t screened_steps() const { return screened_steps_; }
  std::int64_t full_steps() const { return full_steps_; }

 private:
  NearContactRows near_;
  bool prepared_ = false;
  double margin_ = 0.0;
  std::int64_t screened_steps_ = 0;
  std::int64_t full_steps_ = 0;
};

}  // namespace moreau::particles::internal
