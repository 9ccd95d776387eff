// The run of `moreau fill-gaps`: delete the samples GAPS.csv lists, fill every gap, and measure
// the error where the truth is known (the deleted samples).
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "fill_gaps/fill_gaps_scenario.h"
#include "moreau/mocap/gap_fill.h"
#include "moreau/mocap/recording.h"

namespace moreau::cli {

// The error of a filled gap whose every sample was deleted from an observed one (recording
// units), with the measures of evaluate-gaps (fill_metrics.h): the Euclidean distance between
// filled and deleted positions over the gap's frames (mean, p90, max); the velocity and
// acceleration errors after Winter's 6 Hz zero-lag filter (NaN when the rate is not above 12 Hz
// or a sample of the filter's window is missing); the velocity jump at each end (NaN at the
// recording's ends); the deviation of the distances to the marker's 3 most rigid partners.
struct DeletedGapError {
  double mean_error = 0.0;
  double max_error = 0.0;
  double p90_error = 0.0;
  double velocity_error = 0.0;       // units / s
  double acceleration_error = 0.0;   // units / s²
  double velocity_jump_start = 0.0;  // units / s
  double velocity_jump_end = 0.0;
  double distance_deviation = 0.0;  // units
  double distance_z = 0.0;          // in observed standard deviations
};

struct FillGapsResult {
  mocap::Recording filled;           // every frame and marker; unfilled samples stay missing
  std::int64_t samples_deleted = 0;  // observed samples deleted (GAPS.csv)
  mocap::FillSummary summary;        // one report per gap of the recording after deletion
  std::vector<std::optional<DeletedGapError>> errors;  // per summary.gaps entry
};

// Deletes `deletions` from `recording`, then fills every gap (FindGaps) with settings.fill.
FillGapsResult RunFillGaps(const mocap::Recording& recording,
                           const std::vector<mocap::Gap>& deletions,
                           const FillGapsSettings& settings);

}  // namespace moreau::cli
