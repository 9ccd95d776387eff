#include "moreau/mocap/evaluate.h"

#include <fmt/format.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "moreau/common/error.h"
#include "moreau/common/random.h"
#include "moreau/common/stopwatch.h"
#include "moreau/common/summary_json.h"

namespace moreau::mocap {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// One drawn gap: which gap length, which trial, where.
struct Trial {
  std::size_t length_index = 0;
  int trial = 0;
  Gap gap;
};

void CheckComplete(const Recording& truth) {
  for (std::int64_t f = 0; f < truth.frames(); ++f) {
    for (int m = 0; m < truth.markers(); ++m) {
      if (!truth.observed(f, m)) {
        throw InputError(
            fmt::format("evaluation: the recording must be complete, but marker '{}' "
                        "is missing at frame {}",
                        truth.labels()[static_cast<std::size_t>(m)], f));
      }
    }
  }
}

std::vector<Trial> DrawTrials(const Recording& truth, const EvaluationOptions& options,
                              std::vector<std::int64_t>* lengths) {
  const std::int64_t margin = options.fill.baseline.interpolation.samples_per_side;
  SplitMix64 rng(options.seed);
  std::vector<Trial> trials;
  for (std::size_t g = 0; g < options.gap_seconds.size(); ++g) {
    const std::int64_t length =
        std::max<std::int64_t>(1, std::llround(options.gap_seconds[g] * truth.rate()));
    const std::int64_t positions = truth.frames() - 2 * margin - length + 1;
    if (positions < 1) {
      throw InputError(
          fmt::format("evaluation.gap_seconds: a gap of {} s ({} frames) does not "
                      "fit in {} frames with {} observed frames on each side",
                      options.gap_seconds[g], length, truth.frames(), margin));
    }
    lengths->push_back(length);
    for (int t = 0; t < options.trials; ++t) {
      const auto marker = static_cast<int>(rng.Uniform01() * truth.markers());
      const auto first =
          margin + static_cast<std::int64_t>(rng.Uniform01() * static_cast<double>(positions));
      trials.push_back({g, t, Gap{marker, first, first + length - 1}});
    }
  }
  return trials;
}

EvaluationRow Evaluate(const Recording& truth, const Recording& gapped, const Trial& trial,
                       const EvaluationOptions& options, GapFillMethod method) {
  GapFillOptions fill_options = options.fill;
  fill_options.method = method;
  const GapFill fill = FillGap(gapped, trial.gap, fill_options);
  EvaluationRow row{method,
                    options.gap_seconds[trial.length_index],
                    trial.gap.length(),
                    trial.trial,
                    trial.gap.marker,
                    trial.gap.first,
                    kNaN,
                    kNaN,
                    fill.status};
  if (fill.status == GapStatus::kFilled) {
    double sum = 0.0, max = 0.0;
    for (std::int64_t f = trial.gap.first; f <= trial.gap.last; ++f) {
      const double e =
          (fill.points.col(f - trial.gap.first) - truth.point(f, trial.gap.marker)).norm();
      sum += e;
      max = std::max(max, e);
    }
    row.mean_error = sum / static_cast<double>(trial.gap.length());
    row.max_error = max;
  }
  return row;
}

}  // namespace

const FieldList<EvaluationOptions>& EvaluationOptions::Fields() {
  using O = EvaluationOptions;
  static const FieldList<O> list = [] {
    FieldList<O> t;
    t.Choices("methods", &O::methods, GapFillMethodNameTable(), 1, "the methods compared")
        .Numbers("gap_seconds", &O::gap_seconds, Range::Positive(), 1, "s", "gap durations")
        .Integer("trials", &O::trials, Range::AtLeast(1), "", "trials per gap length")
        .Integer("seed", &O::seed, Range::Any(), "", "seed of the drawn gaps (SplitMix64)")
        .Integer("threads", &O::threads, Range::NonNegative(), "",
                 "OpenMP threads (0: the default); results do not depend on it");
    return t;
  }();
  return list;
}

void EvaluationOptions::Validate() const {
  Fields().Validate(*this);
  fill.Validate();
}

nlohmann::json EvaluationOptions::ToJson() const {
  nlohmann::json names = nlohmann::json::array();
  for (GapFillMethod m : methods) names.push_back(std::string(ToString(m)));
  nlohmann::json fill_json = fill.ToJson();
  fill_json.erase("method");
  return {{"methods", names}, {"gap_seconds", gap_seconds}, {"trials", trials},
          {"seed", seed},     {"threads", threads},         {"fill", fill_json}};
}

double Percentile(std::vector<double> values, double p) {
  if (values.empty()) return kNaN;
  std::sort(values.begin(), values.end());
  const double rank = p / 100.0 * static_cast<double>(values.size() - 1);
  const auto lo = static_cast<std::size_t>(std::floor(rank));
  const std::size_t hi = std::min(lo + 1, values.size() - 1);
  const double w = rank - static_cast<double>(lo);
  return (1.0 - w) * values[lo] + w * values[hi];
}

EvaluationSummary EvaluateFillMethods(const Recording& truth, const EvaluationOptions& options) {
  const Stopwatch total;
  options.Validate();
  CheckComplete(truth);
  std::vector<std::int64_t> lengths;
  const std::vector<Trial> trials = DrawTrials(truth, options, &lengths);
  const std::size_t n_methods = options.methods.size();

  EvaluationSummary summary;
  summary.settings = options;
  summary.units = truth.units();
  summary.rows.resize(trials.size() * n_methods);
  const int threads = options.threads > 0 ? options.threads : omp_get_max_threads();
  const auto n_trials = static_cast<std::int64_t>(trials.size());
#pragma omp parallel num_threads(threads)
  {
    Recording gapped = truth;  // per thread: the truth with one gap cleared at a time
#pragma omp for schedule(dynamic)
    for (std::int64_t i = 0; i < n_trials; ++i) {
      const Trial& trial = trials[static_cast<std::size_t>(i)];
      for (std::int64_t f = trial.gap.first; f <= trial.gap.last; ++f) {
        gapped.ClearPoint(f, trial.gap.marker);
      }
      for (std::size_t k = 0; k < n_methods; ++k) {
        summary.rows[static_cast<std::size_t>(i) * n_methods + k] =
            Evaluate(truth, gapped, trial, options, options.methods[k]);
      }
      for (std::int64_t f = trial.gap.first; f <= trial.gap.last; ++f) {
        gapped.SetPoint(f, trial.gap.marker, truth.point(f, trial.gap.marker));
      }
    }
  }

  for (std::size_t g = 0; g < lengths.size(); ++g) {
    for (GapFillMethod method : options.methods) {
      EvaluationStatistics stats{method, options.gap_seconds[g], lengths[g], 0, 0, 0, 0, 0};
      std::vector<double> errors;
      for (const EvaluationRow& row : summary.rows) {
        if (row.method != method || row.gap_frames != lengths[g] ||
            row.gap_seconds != options.gap_seconds[g]) {
          continue;
        }
        ++stats.trials;
        if (row.status == GapStatus::kFilled) {
          errors.push_back(row.mean_error);
        } else {
          ++stats.failed;
        }
      }
      stats.mean = errors.empty() ? kNaN
                                  : std::accumulate(errors.begin(), errors.end(), 0.0) /
                                        static_cast<double>(errors.size());
      stats.median = Percentile(errors, 50.0);
      stats.percentile_90 = Percentile(errors, 90.0);
      summary.statistics.push_back(stats);
    }
  }
  summary.message = fmt::format("{} methods × {} gap lengths × {} trials", n_methods,
                                lengths.size(), options.trials);
  summary.total_seconds = total.Seconds();
  return summary;
}

nlohmann::json EvaluationSummary::ToJson() const {
  // NaN (unfilled) is written as null.
  const auto number = [](double x) { return std::isfinite(x) ? nlohmann::json(x) : nullptr; };
  nlohmann::json j = SummaryJson(termination, message, total_seconds);
  j["units"] = units;
  nlohmann::json stats = nlohmann::json::array();
  for (const EvaluationStatistics& s : statistics) {
    stats.push_back({{"method", std::string(ToString(s.method))},
                     {"gap_seconds", s.gap_seconds},
                     {"gap_frames", s.gap_frames},
                     {"trials", s.trials},
                     {"failed", s.failed},
                     {"mean_error", number(s.mean)},
                     {"median_error", number(s.median)},
                     {"p90_error", number(s.percentile_90)}});
  }
  j["statistics"] = std::move(stats);
  nlohmann::json rows_json = nlohmann::json::array();
  for (const EvaluationRow& r : rows) {
    rows_json.push_back({{"method", std::string(ToString(r.method))},
                         {"gap_seconds", r.gap_seconds},
                         {"gap_frames", r.gap_frames},
                         {"trial", r.trial},
                         {"marker", r.marker},
                         {"first_frame", r.first_frame},
                         {"mean_error", number(r.mean_error)},
                         {"max_error", number(r.max_error)},
                         {"status", std::string(ToString(r.status))}});
  }
  j["rows"] = std::move(rows_json);
  j["settings"] = settings.ToJson();
  return j;
}

}  // namespace moreau::mocap
