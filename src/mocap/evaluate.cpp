#include "moreau/mocap/evaluate.h"

#include <fmt/format.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "mocap/evaluate_internal.h"
#include "moreau/common/error.h"
#include "moreau/common/memory.h"
#include "moreau/common/random.h"
#include "moreau/common/stop.h"
#include "moreau/common/stopwatch.h"
#include "moreau/common/summary_json.h"
#include "moreau/mocap/complete_part.h"

namespace moreau::mocap {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// One drawn trial: which gap length, which trial, the hidden markers' gaps (same frames, the
// group's first marker first).
struct Trial {
  std::size_t length_index = 0;
  int trial = 0;
  std::vector<Gap> gaps;
};

// The first marker sample missing in `truth`, as (frame, marker), or (−1, −1).
std::pair<std::int64_t, int> FirstMissing(const Recording& truth) {
  for (std::int64_t f = 0; f < truth.frames(); ++f) {
    for (int m = 0; m < truth.markers(); ++m) {
      if (truth.is_marker(m) && !truth.observed(f, m)) return {f, m};
    }
  }
  return {-1, -1};
}

// A gap of `seconds` in frames (at least one).
std::int64_t GapFrames(double seconds, double rate) {
  return std::max<std::int64_t>(1, std::llround(seconds * rate));
}

// Observed frames beside a gap: `margin` on each side inside the take, on one side at its ends.
std::int64_t MarginFrames(const EvaluationOptions& options) {
  const std::int64_t margin = options.fill.baseline.interpolation.samples_per_side;
  return (options.placement == GapPlacement::kInterior ? 2 : 1) * margin;
}

// Frames a part needs for the longest gap and its margins (GapPositions).
std::int64_t PartFrames(const Recording& truth, const EvaluationOptions& options) {
  const double longest = *std::max_element(options.gap_seconds.begin(), options.gap_seconds.end());
  return GapFrames(longest, truth.rate()) + MarginFrames(options);
}

// The options that depend on the recording: the filter below its Nyquist frequency, enough
// markers for a group.
void CheckAgainstRecording(const Recording& truth, const EvaluationOptions& options) {
  if (!(options.filter_hz < 0.5 * truth.rate())) {
    throw InputError("evaluation.filter_hz",
                     fmt::format("must be below the Nyquist frequency of the recording, {} Hz "
                                 "(got {})",
                                 0.5 * truth.rate(), options.filter_hz));
  }
  const int markers = truth.CountPoints(PointType::kMarker);
  if (options.markers_per_gap > markers) {
    throw InputError(
        "evaluation.markers_per_gap",
        fmt::format("the recording has {} markers (got {})", markers, options.markers_per_gap));
  }
}

// The standard deviation of every pair's distance over the truth's frames (markers × markers).
Eigen::MatrixXd DistanceSpreads(const Recording& truth) {
  const int m = truth.markers();
  Eigen::MatrixXd spread = Eigen::MatrixXd::Zero(m, m);
  for (int a = 0; a < m; ++a) {
    for (int b = a + 1; b < m; ++b) {
      spread(a, b) = spread(b, a) = MarkerDistanceStatistics(truth, a, b).sd;
    }
  }
  return spread;
}

// `first` and the `count` − 1 markers added one at a time, each the one whose largest spread to
// the markers already chosen is smallest (ties by index); points of other types are never chosen.
std::vector<int> ChooseGroup(const Recording& truth, const Eigen::MatrixXd& spread, int first,
                             int count) {
  std::vector<int> group = {first};
  while (static_cast<int>(group.size()) < count) {
    int best = -1;
    double best_spread = 0.0;
    for (int c = 0; c < spread.rows(); ++c) {
      if (!truth.is_marker(c) || std::find(group.begin(), group.end(), c) != group.end()) continue;
      double largest = 0.0;
      for (int g : group) largest = std::max(largest, spread(c, g));
      if (best < 0 || largest < best_spread) {
        best = c;
        best_spread = largest;
      }
    }
    group.push_back(best);
  }
  return group;
}

// The first frame a gap of `length` frames may take and how many positions follow it, by the
// placement; InputError when the gap does not fit with `margin` observed frames beside it.
std::pair<std::int64_t, std::int64_t> GapPositions(const Recording& truth,
                                                   const EvaluationOptions& options, std::size_t g,
                                                   std::int64_t length) {
  const std::int64_t margin = options.fill.baseline.interpolation.samples_per_side;
  const std::int64_t frames = truth.frames();
  const bool interior = options.placement == GapPlacement::kInterior;
  const std::int64_t left = frames - MarginFrames(options) - length + 1;
  if (left < 1) {
    throw InputError(fmt::format(
        "evaluation.gap_seconds: a gap of {} s ({} frames) does not fit in {} frames with {} "
        "observed frames on {}",
        options.gap_seconds[g], length, frames, margin, interior ? "each side" : "one side"));
  }
  switch (options.placement) {
    case GapPlacement::kInterior:
      return {margin, left};
    case GapPlacement::kStart:
      return {0, 1};
    case GapPlacement::kEnd:
      return {frames - length, 1};
    case GapPlacement::kAny:
      return {0, frames - length + 1};
  }
  MOREAU_ASSERT(false);
}

std::vector<Trial> DrawTrials(const Recording& truth, const EvaluationOptions& options,
                              std::vector<std::int64_t>* lengths) {
  const Eigen::MatrixXd spread =
      options.markers_per_gap > 1 ? DistanceSpreads(truth) : Eigen::MatrixXd();
  std::vector<int> markers;  // the points that may be hidden
  for (int m = 0; m < truth.markers(); ++m) {
    if (truth.is_marker(m)) markers.push_back(m);
  }
  SplitMix64 rng(options.seed);
  std::vector<Trial> trials;
  for (std::size_t g = 0; g < options.gap_seconds.size(); ++g) {
    const std::int64_t length = GapFrames(options.gap_seconds[g], truth.rate());
    const auto [lowest, positions] = GapPositions(truth, options, g, length);
    lengths->push_back(length);
    for (int t = 0; t < options.trials; ++t) {
      const int marker =
          markers[static_cast<std::size_t>(rng.Uniform01() * static_cast<double>(markers.size()))];
      const auto first =
          lowest + static_cast<std::int64_t>(rng.Uniform01() * static_cast<double>(positions));
      Trial trial{g, t, {}};
      const std::vector<int> group =
          options.markers_per_gap > 1 ? ChooseGroup(truth, spread, marker, options.markers_per_gap)
                                      : std::vector<int>{marker};
      for (int m : group) trial.gaps.push_back(Gap{m, first, first + length - 1});
      trials.push_back(std::move(trial));
    }
  }
  return trials;
}

// The row of one hidden marker's gap; `filled` holds the method's fills of every hidden marker.
EvaluationRow MeasureRow(const Recording& truth, const Recording& filled, const Trial& trial,
                         std::size_t j, const RigidPartners& partners, GapStatus status,
                         const EvaluationOptions& options, GapFillMethod method) {
  const Gap& gap = trial.gaps[j];
  EvaluationRow row{method,       options.gap_seconds[trial.length_index],
                    gap.length(), trial.trial,
                    gap.marker,   gap.first,
                    kNaN,         kNaN,
                    status,       kNaN,
                    kNaN,         kNaN,
                    kNaN,         kNaN,
                    kNaN,         kNaN};
  if (status != GapStatus::kFilled) {
    row.outcome = GapOutcome::kUnfillable;
    return row;
  }
  const FilledGapMeasures m = MeasureFilledGap(truth, filled, gap, partners, options.filter_hz);
  row.mean_error = m.position.mean;
  row.max_error = m.position.max;
  row.p90_error = m.position.p90;
  row.velocity_error = m.derivative.velocity_mean;
  row.acceleration_error = m.derivative.acceleration_mean;
  row.velocity_jump_start = m.jump.start;
  row.velocity_jump_end = m.jump.end;
  row.distance_deviation = m.distance.mean;
  row.distance_z = m.distance.z;
  return row;
}

// One trial with every method: rows[k K + j] for method k and hidden marker j. `work` is the
// truth on entry and on return; in between the hidden markers' samples are cleared, and set to a
// method's fills while they are measured.
void EvaluateTrial(const Recording& truth, Recording& work, const Trial& trial,
                   const EvaluationOptions& options, EvaluationRow* rows, double* seconds) {
  for (const Gap& gap : trial.gaps) {
    for (std::int64_t f = gap.first; f <= gap.last; ++f) work.ClearPoint(f, gap.marker);
  }
  std::vector<RigidPartners> partners;
  for (const Gap& gap : trial.gaps) {
    partners.push_back(FindRigidPartners(work, gap.marker, options.distance_partners));
  }
  const std::size_t k_markers = trial.gaps.size();
  for (std::size_t k = 0; k < options.methods.size(); ++k) {
    GapFillOptions fill_options = options.fill;
    fill_options.method = options.methods[k];
    const Stopwatch fill_time;
    const std::vector<GapFill> fills = FillGapList(work, trial.gaps, fill_options);
    seconds[k] = fill_time.Seconds();
    const auto each_filled = [&](const auto& apply) {
      for (std::size_t j = 0; j < k_markers; ++j) {
        if (fills[j].status != GapStatus::kFilled) continue;
        const Gap& gap = trial.gaps[j];
        for (std::int64_t f = gap.first; f <= gap.last; ++f) apply(gap, f, j);
      }
    };
    each_filled([&](const Gap& gap, std::int64_t f, std::size_t j) {
      work.SetPoint(f, gap.marker, fills[j].points.col(f - gap.first));
    });
    for (std::size_t j = 0; j < k_markers; ++j) {
      rows[k * k_markers + j] = MeasureRow(truth, work, trial, j, partners[j], fills[j].status,
                                           options, options.methods[k]);
      if (fills[j].status == GapStatus::kFilled) {
        rows[k * k_markers + j].outcome = fills[j].outcome;
        rows[k * k_markers + j].prior_reason = fills[j].prior_reason;
      }
    }
    each_filled(
        [&](const Gap& gap, std::int64_t f, std::size_t) { work.ClearPoint(f, gap.marker); });
  }
  for (const Gap& gap : trial.gaps) {
    for (std::int64_t f = gap.first; f <= gap.last; ++f) {
      work.SetPoint(f, gap.marker, truth.point(f, gap.marker));
    }
  }
}

// Before the trials are drawn: their gaps, result rows (and the CSV text a caller writes of
// them, about 400 bytes a row), timings and flags must fit in memory.
void CheckEvaluationMemory(const EvaluationOptions& options) {
  const double trials =
      static_cast<double>(options.gap_seconds.size()) * static_cast<double>(options.trials);
  const double rows = static_cast<double>(options.methods.size() * options.markers_per_gap);
  const double per_trial = sizeof(Trial) + options.markers_per_gap * sizeof(Gap) +
                           rows * (sizeof(EvaluationRow) + 400.0) +
                           static_cast<double>(options.methods.size()) * sizeof(double) + 1.0;
  try {
    CheckMemory(fmt::format("{:.0f} trials", trials), trials * per_trial);
  } catch (const InputError& e) {
    throw InputError("trials", e.what());
  }
}

// The protocol on a complete recording.
EvaluationSummary EvaluateComplete(const Recording& truth, const EvaluationOptions& options) {
  const Stopwatch total;
  CheckAgainstRecording(truth, options);
  CheckEvaluationMemory(options);
  std::vector<std::int64_t> lengths;
  const std::vector<Trial> trials = DrawTrials(truth, options, &lengths);
  const std::size_t per_trial =
      options.methods.size() * static_cast<std::size_t>(options.markers_per_gap);

  EvaluationSummary summary;
  summary.settings = options;
  summary.units = truth.units();
  summary.rows.resize(trials.size() * per_trial);
  std::vector<double> seconds(trials.size() * options.methods.size());
  const int threads = options.threads > 0 ? options.threads : omp_get_max_threads();
  const auto n_trials = static_cast<std::int64_t>(trials.size());
  std::vector<char> done(trials.size(), 0);  // 0: skipped after a stop request
#pragma omp parallel num_threads(threads)
  {
    Recording work = truth;  // per thread: the truth with one trial's gaps cleared at a time
#pragma omp for schedule(dynamic)
    for (std::int64_t i = 0; i < n_trials; ++i) {
      if (StopRequested()) continue;
      try {
        EvaluateTrial(truth, work, trials[static_cast<std::size_t>(i)], options,
                      &summary.rows[static_cast<std::size_t>(i) * per_trial],
                      &seconds[static_cast<std::size_t>(i) * options.methods.size()]);
        done[static_cast<std::size_t>(i)] = 1;
      } catch (const Interrupted&) {  // `work` is left dirty: every later trial is skipped
      }
    }
  }
  const auto trials_done = std::count(done.begin(), done.end(), 1);
  if (trials_done < n_trials) {
    std::vector<EvaluationRow> kept;
    for (std::size_t i = 0; i < done.size(); ++i) {
      const auto first = summary.rows.begin() + static_cast<std::ptrdiff_t>(i * per_trial);
      if (done[i]) kept.insert(kept.end(), first, first + static_cast<std::ptrdiff_t>(per_trial));
    }
    summary.rows = std::move(kept);
  }
  summary.method_seconds.assign(options.methods.size(), 0.0);
  for (std::size_t i = 0; i < seconds.size(); ++i) {
    summary.method_seconds[i % options.methods.size()] += seconds[i];
  }
  summary.statistics = internal::EvaluationStatisticsOf(summary.rows, options, lengths);
  summary.message = fmt::format("{} methods × {} gap lengths × {} trials", options.methods.size(),
                                lengths.size(), options.trials);
  if (options.markers_per_gap > 1) {
    summary.message += fmt::format(" × {} markers", options.markers_per_gap);
  }
  if (trials_done < n_trials) {
    summary.termination = Termination::kInterrupted;
    summary.message = fmt::format("stopped on request after {} of {} trials ({})", trials_done,
                                  n_trials, summary.message);
  }
  summary.total_seconds = total.Seconds();
  return summary;
}

}  // namespace

EvaluationSummary EvaluateFillMethods(const Recording& truth, const EvaluationOptions& options) {
  options.Validate();
  const auto [frame, marker] = FirstMissing(truth);
  if (marker < 0) return EvaluateComplete(truth, options);
  const std::string& label = truth.labels()[static_cast<std::size_t>(marker)];
  if (!options.complete_part) {
    throw InputError(
        fmt::format("evaluation: the recording must be complete, but marker '{}' "
                    "is missing at frame {} (evaluation.complete_part is false)",
                    label, frame));
  }
  const CompletePart part = FindCompletePart(truth, PartFrames(truth, options));
  if (static_cast<int>(part.markers.size()) < std::max(2, options.markers_per_gap)) {
    throw InputError(fmt::format(
        "evaluation: the recording has holes (marker '{}' is missing at frame {}) and no {} "
        "frames hold {} complete markers",
        label, frame, PartFrames(truth, options), std::max(2, options.markers_per_gap)));
  }
  EvaluationSummary summary = EvaluateComplete(ExtractPart(truth, part), options);
  for (EvaluationRow& row : summary.rows) {
    row.marker = part.markers[static_cast<std::size_t>(row.marker)];
    row.first_frame += part.first;
  }
  summary.complete_part = part.ToJson(truth);
  return summary;
}

}  // namespace moreau::mocap
