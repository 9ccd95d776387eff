#include "fill_gaps/fill_gaps_run.h"

#include <algorithm>
#include <limits>

#include "moreau/mocap/evaluate.h"
#include "moreau/mocap/fill_metrics.h"

namespace moreau::cli {
namespace {

// The error against `truth` when the gap was filled and every one of its samples is observed in
// `truth` (so it was deleted, not missing from the start); `gapped` is the input of the fill.
// The filter and the partners are evaluate-gaps' defaults.
std::optional<DeletedGapError> ErrorAgainstTruth(const mocap::Recording& truth,
                                                 const mocap::Recording& gapped,
                                                 const mocap::Recording& filled,
                                                 const mocap::GapReport& gap) {
  if (!gap.filled()) return std::nullopt;
  for (std::int64_t f = gap.first; f <= gap.last; ++f) {
    if (!truth.observed(f, gap.marker)) return std::nullopt;
  }
  const mocap::EvaluationOptions defaults;
  const mocap::Gap g{gap.marker, gap.first, gap.last};
  const mocap::PositionError position = mocap::PositionErrorInGap(truth, filled, g);
  DeletedGapError error;
  error.mean_error = position.mean;
  error.max_error = position.max;
  error.p90_error = position.p90;
  error.velocity_error = error.acceleration_error = std::numeric_limits<double>::quiet_NaN();
  if (filled.rate() > 2.0 * defaults.filter_hz) {
    const mocap::DerivativeError derivative =
        mocap::FilteredDerivativeErrorInGap(truth, filled, g, defaults.filter_hz);
    error.velocity_error = derivative.velocity_mean;
    error.acceleration_error = derivative.acceleration_mean;
  }
  const mocap::VelocityJump jump = mocap::VelocityJumpAtGapEnds(filled, g);
  error.velocity_jump_start = jump.start;
  error.velocity_jump_end = jump.end;
  const mocap::DistanceDeviation distance = mocap::PartnerDistanceDeviation(
      filled, g, mocap::FindRigidPartners(gapped, gap.marker, defaults.distance_partners));
  error.distance_deviation = distance.mean;
  error.distance_z = distance.z;
  return error;
}

}  // namespace

FillGapsResult RunFillGaps(const mocap::Recording& recording,
                           const std::vector<mocap::Gap>& deletions,
                           const FillGapsSettings& settings) {
  FillGapsResult result;
  mocap::Recording gapped = recording;
  for (const mocap::Gap& d : deletions) {
    for (std::int64_t f = d.first; f <= d.last; ++f) {
      if (!gapped.observed(f, d.marker)) continue;
      gapped.ClearPoint(f, d.marker);
      ++result.samples_deleted;
    }
  }
  result.summary = mocap::FillGaps(gapped, mocap::FindGaps(gapped), settings.fill, &result.filled);
  for (const mocap::GapReport& gap : result.summary.gaps) {
    result.errors.push_back(ErrorAgainstTruth(recording, gapped, result.filled, gap));
  }
  return result;
}

}  // namespace moreau::cli
