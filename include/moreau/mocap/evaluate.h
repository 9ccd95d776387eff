// The evaluation protocol of the gap-filling literature: hide samples of a complete recording,
// fill them, measure the error against the truth.
//
// For each gap length L (gap_seconds × rate, rounded, ≥ 1 frame) and each trial t, one marker
// and one gap position are drawn (moreau::SplitMix64 seeded with `seed`, in the order
// (gap length, trial)); the gap's first frame is uniform in [margin, F − margin − L] with
// margin = fill.baseline.interpolation.samples_per_side, so that every method has its samples on
// both sides. The same marker and position are used for every method. The marker's samples are
// cleared, the gap is filled by FillGap (gap_fill.h), and the error is the Euclidean distance
// between the filled and the true positions over the hidden frames: its mean and its maximum (in
// the recording's units). Trials run in parallel (OpenMP); the results do not depend on the number
// of threads.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "moreau/common/termination.h"
#include "moreau/mocap/gap_fill.h"
#include "moreau/mocap/recording.h"

namespace moreau::mocap {

struct EvaluationOptions {
  std::vector<GapFillMethod> methods = AllGapFillMethods();  // methods compared (≥ 1)
  std::vector<double> gap_seconds = {0.1, 0.2, 0.5, 1.0};    // gap durations, each > 0
  int trials = 20;                                           // trials per gap length, ≥ 1
  std::uint64_t seed = 1;                                    // SplitMix64 seed of the draws
  int threads = 0;                                           // OpenMP threads; 0: the default
  GapFillOptions fill;  // every method's settings (fill.method is ignored)

  // methods, gap_seconds, trials, seed, threads (the fill options have their own list).
  static const FieldList<EvaluationOptions>& Fields();
  // Throws InputError(key, reason) for a value out of range, or the fill options'.
  void Validate() const;
  nlohmann::json ToJson() const;
};

// One method on one trial.
struct EvaluationRow {
  GapFillMethod method = GapFillMethod::kLinear;
  double gap_seconds = 0.0;     // as asked
  std::int64_t gap_frames = 0;  // as used
  int trial = 0;
  int marker = 0;
  std::int64_t first_frame = 0;  // 0-based
  double mean_error = 0.0;       // recording units; NaN when not filled
  double max_error = 0.0;        // recording units; NaN when not filled
  GapStatus status = GapStatus::kFilled;
};

// One method at one gap length, over the trials it filled.
struct EvaluationStatistics {
  GapFillMethod method = GapFillMethod::kLinear;
  double gap_seconds = 0.0;
  std::int64_t gap_frames = 0;
  int trials = 0;
  int failed = 0;              // trials not filled
  double mean = 0.0;           // of the per-gap mean error (NaN if none filled)
  double median = 0.0;         // ditto
  double percentile_90 = 0.0;  // ditto (linear interpolation between order statistics)
};

struct EvaluationSummary {
  Termination termination = Termination::kCompleted;
  std::string message;
  std::vector<EvaluationRow> rows;               // ordered by gap length, trial, method
  std::vector<EvaluationStatistics> statistics;  // ordered by gap length, method
  std::string units;
  double total_seconds = 0.0;
  EvaluationOptions settings;

  bool ok() const { return IsSuccess(termination); }
  nlohmann::json ToJson() const;
};

// Runs the protocol on `truth`, which must be complete (every sample observed) and long enough
// for the longest gap plus the margins. Throws InputError otherwise or for invalid options.
EvaluationSummary EvaluateFillMethods(const Recording& truth, const EvaluationOptions& options);

// The p-th percentile (p in [0, 100]) of `values` by linear interpolation between the order
// statistics (NaN for none).
double Percentile(std::vector<double> values, double p);

}  // namespace moreau::mocap
