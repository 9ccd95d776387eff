// The evaluation's options (field list, JSON), its statistics over the rows and its summary JSON.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "mocap/evaluate_internal.h"
#include "moreau/common/enum_names.h"
#include "moreau/common/summary_json.h"
#include "moreau/mocap/evaluate.h"

namespace moreau::mocap {

namespace {

constexpr EnumNames<GapPlacement, 4> kPlacements{{
    {GapPlacement::kInterior, "interior"},
    {GapPlacement::kStart, "start"},
    {GapPlacement::kEnd, "end"},
    {GapPlacement::kAny, "any"},
}};

// The mean and 90th percentile of the finite values of `measure` over `rows`.
template <typename Measure>
MeasureStatistics StatisticsOf(const std::vector<const EvaluationRow*>& rows, Measure measure) {
  std::vector<double> values;
  for (const EvaluationRow* row : rows) {
    const double x = measure(*row);
    if (std::isfinite(x)) values.push_back(x);
  }
  if (values.empty()) {
    return {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::quiet_NaN()};
  }
  return {std::accumulate(values.begin(), values.end(), 0.0) / static_cast<double>(values.size()),
          Percentile(values, 90.0)};
}

// One method at one gap length: the statistics of `rows` (all of that method and length).
EvaluationStatistics StatisticsOfRows(EvaluationStatistics stats,
                                      const std::vector<const EvaluationRow*>& rows) {
  std::vector<double> errors;
  for (const EvaluationRow* row : rows) {
    ++stats.gaps;
    stats.optimal_control += row->outcome == GapOutcome::kOptimalControl ? 1 : 0;
    stats.prior += row->outcome == GapOutcome::kPrior ? 1 : 0;
    stats.rejected_by_guard += row->prior_reason == "rejected_by_guard" ? 1 : 0;
    if (row->status == GapStatus::kFilled) {
      errors.push_back(row->mean_error);
    } else {
      ++stats.failed;
    }
  }
  stats.mean = errors.empty() ? std::numeric_limits<double>::quiet_NaN()
                              : std::accumulate(errors.begin(), errors.end(), 0.0) /
                                    static_cast<double>(errors.size());
  stats.median = Percentile(errors, 50.0);
  stats.percentile_90 = Percentile(errors, 90.0);
  stats.max_error = StatisticsOf(rows, [](const EvaluationRow& r) { return r.max_error; });
  stats.p90_error = StatisticsOf(rows, [](const EvaluationRow& r) { return r.p90_error; });
  stats.velocity_error =
      StatisticsOf(rows, [](const EvaluationRow& r) { return r.velocity_error; });
  stats.acceleration_error =
      StatisticsOf(rows, [](const EvaluationRow& r) { return r.acceleration_error; });
  stats.velocity_jump =
      StatisticsOf(rows, [](const EvaluationRow& r) { return r.velocity_jump(); });
  stats.distance_deviation =
      StatisticsOf(rows, [](const EvaluationRow& r) { return r.distance_deviation; });
  stats.distance_z = StatisticsOf(rows, [](const EvaluationRow& r) { return r.distance_z; });
  return stats;
}

}  // namespace

std::string_view ToString(GapPlacement placement) { return EnumName(kPlacements, placement); }

std::vector<std::pair<GapPlacement, std::string_view>> GapPlacementNameTable() {
  return {kPlacements.begin(), kPlacements.end()};
}

double EvaluationRow::velocity_jump() const {
  if (std::isnan(velocity_jump_start)) return velocity_jump_end;
  if (std::isnan(velocity_jump_end)) return velocity_jump_start;
  return std::max(velocity_jump_start, velocity_jump_end);
}

const FieldList<EvaluationOptions>& EvaluationOptions::Fields() {
  using O = EvaluationOptions;
  static const FieldList<O> list = [] {
    FieldList<O> t;
    t.Choices("methods", &O::methods, GapFillMethodNameTable(), 1, "the methods compared")
        .Numbers("gap_seconds", &O::gap_seconds, Range::Positive(), 1, "s", "gap durations")
        .Integer("trials", &O::trials, Range::AtLeast(1), "", "trials per gap length")
        .Integer("seed", &O::seed, Range::Any(), "", "seed of the drawn gaps (SplitMix64)")
        .Integer("threads", &O::threads, Range::NonNegative(), "",
                 "OpenMP threads (0: the default); results do not depend on it")
        .Number("filter_hz", &O::filter_hz, Range::Positive(), "Hz",
                "cutoff of the zero-lag Butterworth filter before velocity and acceleration "
                "errors (below rate / 2)")
        .Integer("markers_per_gap", &O::markers_per_gap, Range::AtLeast(1), "",
                 "markers hidden together: the drawn one and its most rigid neighbours")
        .Choice("placement", &O::placement, GapPlacementNameTable(),
                "where gaps lie: interior, at the take's start or end, or anywhere")
        .Integer("distance_partners", &O::distance_partners, Range::AtLeast(1), "",
                 "most rigid partners of the distance deviation")
        .Flag("complete_part", &O::complete_part,
              "evaluate a recording with holes on its complete part (false: refuse it)");
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
  return {{"methods", names},
          {"gap_seconds", gap_seconds},
          {"trials", trials},
          {"seed", seed},
          {"threads", threads},
          {"fill", fill_json},
          {"filter_hz", filter_hz},
          {"markers_per_gap", markers_per_gap},
          {"placement", std::string(ToString(placement))},
          {"distance_partners", distance_partners},
          {"complete_part", complete_part}};
}

namespace internal {

std::vector<EvaluationStatistics> EvaluationStatisticsOf(const std::vector<EvaluationRow>& rows,
                                                         const EvaluationOptions& options,
                                                         const std::vector<std::int64_t>& lengths) {
  std::vector<EvaluationStatistics> statistics;
  for (std::size_t g = 0; g < lengths.size(); ++g) {
    for (GapFillMethod method : options.methods) {
      std::vector<const EvaluationRow*> of;
      for (const EvaluationRow& row : rows) {
        if (row.method == method && row.gap_frames == lengths[g] &&
            row.gap_seconds == options.gap_seconds[g]) {
          of.push_back(&row);
        }
      }
      EvaluationStatistics stats;
      stats.method = method;
      stats.gap_seconds = options.gap_seconds[g];
      stats.gap_frames = lengths[g];
      // options.trials, fewer when a stop request skipped trials
      stats.trials =
          std::min(options.trials, static_cast<int>(of.size()) / options.markers_per_gap);
      statistics.push_back(StatisticsOfRows(stats, of));
    }
  }
  return statistics;
}

}  // namespace internal

nlohmann::json EvaluationSummary::ToJson() const {
  // NaN (unfilled) is written as null.
  const auto number = [](double x) { return std::isfinite(x) ? nlohmann::json(x) : nullptr; };
  nlohmann::json j = SummaryJson(termination, message, total_seconds);
  j["units"] = units;
  nlohmann::json stats = nlohmann::json::array();
  for (const EvaluationStatistics& s : statistics) {
    nlohmann::json entry = {{"method", std::string(ToString(s.method))},
                            {"gap_seconds", s.gap_seconds},
                            {"gap_frames", s.gap_frames},
                            {"trials", s.trials},
                            {"failed", s.failed},
                            {"mean_error", number(s.mean)},
                            {"median_error", number(s.median)},
                            {"p90_error", number(s.percentile_90)},
                            {"gaps", s.gaps}};
    if (s.method == GapFillMethod::kOcp) {
      entry["optimal_control"] = s.optimal_control;
      entry["prior"] = s.prior;
      entry["rejected_by_guard"] = s.rejected_by_guard;
    }
    const std::pair<const char*, const MeasureStatistics*> measures[] = {
        {"max_error", &s.max_error},           {"p90_error", &s.p90_error},
        {"velocity_error", &s.velocity_error}, {"acceleration_error", &s.acceleration_error},
        {"velocity_jump", &s.velocity_jump},   {"distance_deviation", &s.distance_deviation},
        {"distance_z", &s.distance_z}};
    for (const auto& [name, m] : measures) {
      entry["measures"][name] = {{"mean", number(m->mean)}, {"p90", number(m->p90)}};
    }
    stats.push_back(std::move(entry));
  }
  j["statistics"] = std::move(stats);
  nlohmann::json times = nlohmann::json::object();
  for (std::size_t k = 0; k < method_seconds.size(); ++k) {
    times[std::string(ToString(settings.methods[k]))] = method_seconds[k];
  }
  j["method_seconds"] = std::move(times);
  j["complete_part"] = complete_part;
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
                         {"status", std::string(ToString(r.status))},
                         {"p90_error", number(r.p90_error)},
                         {"velocity_error", number(r.velocity_error)},
                         {"acceleration_error", number(r.acceleration_error)},
                         {"velocity_jump_start", number(r.velocity_jump_start)},
                         {"velocity_jump_end", number(r.velocity_jump_end)},
                         {"distance_deviation", number(r.distance_deviation)},
                         {"distance_z", number(r.distance_z)},
                         {"outcome", std::string(ToString(r.outcome))},
                         {"prior_reason", r.prior_reason}});
  }
  j["rows"] = std::move(rows_json);
  j["settings"] = settings.ToJson();
  return j;
}

}  // namespace moreau::mocap
