// The evaluation protocol of the gap-filling literature: hide samples of a complete recording,
// fill them, measure the error against the truth.
//
// For each gap length L (gap_seconds × rate, rounded, ≥ 1 frame) and each trial t, a group of
// markers and one gap position are drawn (moreau::SplitMix64 seeded with `seed`, two uniforms per
// trial in the order (gap length, trial): the group's first marker, then the position). The group
// is the first marker and, for markers_per_gap = K > 1, the K − 1 markers that keep closest to
// it: added one at a time, each the marker whose largest spread (standard deviation over the
// truth's frames) of distance to the markers already chosen is smallest (ties by index); on a
// body this is one segment. The position depends on `placement`: interior (the gap's first frame
// uniform in [margin, F − margin − L], margin = fill.baseline.interpolation.samples_per_side, so
// that every method has its samples on both sides), start (frames 0 … L − 1), end (the last L
// frames) or any (first frame uniform in [0, F − L]). The same markers and position are used for
// every method. The group's samples are cleared over the gap (every hidden marker's, so no fill
// sees another hidden marker's truth), all K gaps are filled together by FillGapList
// (gap_fill.h), and each hidden marker's fill is measured against the truth (fill_metrics.h):
// position error (mean, 90th percentile, maximum), velocity and acceleration errors after
// Winter's 6 Hz low-pass filter (filter_hz), the velocity jumps at the gap's ends and the
// deviation of the distances to the marker's `distance_partners` most rigid partners (chosen on
// the samples left observed) from their observed distribution. Trials run in parallel (OpenMP);
// the results do not depend on the number of threads.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "moreau/common/termination.h"
#include "moreau/mocap/fill_metrics.h"
#include "moreau/mocap/gap_fill.h"
#include "moreau/mocap/recording.h"

namespace moreau::mocap {

// Where the hidden gaps lie in the recording (see above).
enum class GapPlacement { kInterior, kStart, kEnd, kAny };

// "interior", "start", "end", "any".
std::string_view ToString(GapPlacement placement);
// The name table of GapPlacement (for field lists).
std::vector<std::pair<GapPlacement, std::string_view>> GapPlacementNameTable();

struct EvaluationOptions {
  std::vector<GapFillMethod> methods = AllGapFillMethods();  // methods compared (≥ 1)
  std::vector<double> gap_seconds = {0.1, 0.2, 0.5, 1.0};    // gap durations, each > 0
  int trials = 20;                                           // trials per gap length, ≥ 1
  std::uint64_t seed = 1;                                    // SplitMix64 seed of the draws
  int threads = 0;                                           // OpenMP threads; 0: the default
  GapFillOptions fill;  // every method's settings (fill.method is ignored)
  // Cutoff f_c of Winter's zero-lag low-pass filter applied to the truth and to the filled track
  // before the velocity and acceleration errors (fill_metrics.h); in (0, rate / 2).
  double filter_hz = 6.0;
  int markers_per_gap = 1;  // K markers hidden together (one segment), 1 ≤ K ≤ markers
  GapPlacement placement = GapPlacement::kInterior;
  int distance_partners = 3;  // most rigid partners of the distance deviation, ≥ 1
  // A recording with holes is evaluated on its complete part (complete_part.h): its markers
  // observed at every frame of the frame range with the most such samples (false: refused).
  bool complete_part = true;

  // methods, gap_seconds, trials, seed, threads, filter_hz, markers_per_gap, placement,
  // distance_partners, complete_part (the fill options have their own list).
  static const FieldList<EvaluationOptions>& Fields();
  // Throws InputError(key, reason) for a value out of range, or the fill options'.
  void Validate() const;
  nlohmann::json ToJson() const;
};

// One method on one hidden marker of one trial. Every measure is NaN when the gap was not filled
// or the measure cannot be formed there (fill_metrics.h).
struct EvaluationRow {
  GapFillMethod method = GapFillMethod::kLinear;
  double gap_seconds = 0.0;     // as asked
  std::int64_t gap_frames = 0;  // as used
  int trial = 0;
  int marker = 0;
  std::int64_t first_frame = 0;  // 0-based
  double mean_error = 0.0;       // position error, mean over the gap (recording units)
  double max_error = 0.0;        // position error, maximum over the gap (recording units)
  GapStatus status = GapStatus::kFilled;
  double p90_error = 0.0;            // position error, 90th percentile over the gap (units)
  double velocity_error = 0.0;       // filtered velocity error, mean over the gap (units / s)
  double acceleration_error = 0.0;   // filtered acceleration error, mean (units / s²)
  double velocity_jump_start = 0.0;  // units / s; NaN for a gap at the recording's start
  double velocity_jump_end = 0.0;    // units / s; NaN for a gap at the recording's end
  double distance_deviation = 0.0;   // units: mean |d − mean observed| over gap and partners
  double distance_z = 0.0;           // the same in observed standard deviations
  GapOutcome outcome = GapOutcome::kBaseline;  // what filled it (kUnfillable when not filled)
  // For outcome kPrior, why (GapFill::prior_reason): "rejected_by_guard" (the window converged,
  // its fill was turned down), "optimal_control_failed" or "optimal_control_off"; else empty.
  std::string prior_reason = {};

  // The larger of the two jumps that exist (NaN when none).
  double velocity_jump() const;
};

// The mean and the 90th percentile of one measure over the rows where it is finite (NaN if none).
struct MeasureStatistics {
  double mean = 0.0;
  double p90 = 0.0;
};

// One method at one gap length, over the hidden markers' gaps it filled.
struct EvaluationStatistics {
  GapFillMethod method = GapFillMethod::kLinear;
  double gap_seconds = 0.0;
  std::int64_t gap_frames = 0;
  int trials = 0;
  int failed = 0;              // hidden markers' gaps not filled
  double mean = 0.0;           // of the per-gap mean error (NaN if none filled)
  double median = 0.0;         // ditto
  double percentile_90 = 0.0;  // ditto (linear interpolation between order statistics)
  int gaps = 0;                // hidden markers' gaps: trials × markers_per_gap
  int optimal_control = 0;     // of them filled by the optimal control (ocp)
  int prior = 0;               // of them filled by ocp's prior (the optimal control failed)
  int rejected_by_guard = 0;   // of those, the window converged and the guard turned it down
  // Over the gaps, per measure of EvaluationRow: its mean and 90th percentile.
  MeasureStatistics max_error, p90_error, velocity_error, acceleration_error, velocity_jump,
      distance_deviation, distance_z;
};

struct EvaluationSummary {
  Termination termination = Termination::kCompleted;
  std::string message;
  std::vector<EvaluationRow> rows;  // ordered by gap length, trial, method, hidden marker
  std::vector<EvaluationStatistics> statistics;  // ordered by gap length, method
  std::string units;
  double total_seconds = 0.0;
  EvaluationOptions settings;
  // The complete part evaluated (CompletePart::ToJson) when the recording has holes; null when
  // the whole recording was. Rows name the input's markers and frames either way.
  nlohmann::json complete_part;
  // Per method (in settings.methods' order): wall-clock seconds of all its fills.
  std::vector<double> method_seconds;

  bool ok() const { return IsSuccess(termination); }
  nlohmann::json ToJson() const;
};

// Runs the protocol on `truth`, whose markers must be complete (every sample observed; points of
// other types are never hidden, partners or donors and may have holes) or, with complete_part,
// on its complete part, which must hold at least markers_per_gap markers and be long enough for
// the longest gap plus the margins, with at least markers_per_gap markers and a rate above
// 2 filter_hz. Throws InputError otherwise, for invalid options, or ("trials: …") when the
// trials' gaps and rows cannot fit in memory (checked before they are drawn). When a stop is requested
// (common/stop.h) the trials not yet finished are skipped: the summary ends kInterrupted with
// the rows and statistics of the trials that were done.
EvaluationSummary EvaluateFillMethods(const Recording& truth, const EvaluationOptions& options);

}  // namespace moreau::mocap
