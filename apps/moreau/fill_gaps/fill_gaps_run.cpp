#include "fill_gaps/fill_gaps_run.h"

#include <algorithm>

namespace moreau::cli {
namespace {

// The error against `truth` when the gap was filled and every one of its samples is observed in
// `truth` (so it was deleted, not missing from the start).
std::optional<DeletedGapError> ErrorAgainstTruth(const mocap::Recording& truth,
                                                 const mocap::Recording& filled,
                                                 const mocap::GapReport& gap) {
  if (!gap.filled()) return std::nullopt;
  DeletedGapError error;
  for (std::int64_t f = gap.first; f <= gap.last; ++f) {
    if (!truth.observed(f, gap.marker)) return std::nullopt;
    const double d = (filled.point(f, gap.marker) - truth.point(f, gap.marker)).norm();
    error.mean_error += d;
    error.max_error = std::max(error.max_error, d);
  }
  error.mean_error /= static_cast<double>(gap.last - gap.first + 1);
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
    result.errors.push_back(ErrorAgainstTruth(recording, result.filled, gap));
  }
  return result;
}

}  // namespace moreau::cli
