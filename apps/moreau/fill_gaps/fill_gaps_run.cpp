#include "fill_gaps/fill_gaps_run.h"


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
  const mocap::FilledGapMeasures m = mocap::MeasureFilledGap(
      truth, filled, g, mocap::FindRigidPartners(gapped, gap.marker, defaults.distance_partners),
      defaults.filter_hz);
  return DeletedGapError{m.position.mean,
                         m.position.max,
                         m.position.p90,
                         m.derivative.velocity_mean,
                         m.derivative.acceleration_mean,
                         m.jump.start,
                         m.jump.end,
                         m.distance.mean,
                         m.distance.z};
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
