#include "evaluate_gaps/evaluate_gaps_report.h"

#include <cmath>
#include <filesystem>
#include <iterator>

#include <fmt/format.h>

#include "moreau/common/summary_json.h"
#include "output.h"
#include "signals.h"

namespace moreau::cli {
namespace {

// A CSV field: quoted when it holds a comma, a quote or a line break.
std::string CsvField(const std::string& text) {
  if (text.find_first_of(",\"\n") == std::string::npos) return text;
  std::string quoted = "\"";
  for (char c : text) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
  return quoted + "\"";
}

std::string NumberOrEmpty(double x) { return std::isfinite(x) ? fmt::format("{:.9g}", x) : ""; }

}  // namespace

std::string EvaluationCsv(const mocap::EvaluationSummary& summary,
                          const mocap::Recording& recording) {
  fmt::memory_buffer csv;
  auto out = std::back_inserter(csv);
  fmt::format_to(out,
                 "method,gap_frames,trial,marker,first_frame,mean_error,max_error,gap_seconds,"
                 "status,p90_error,velocity_error,acceleration_error,velocity_jump_start,"
                 "velocity_jump_end,distance_deviation,distance_z,outcome,prior_reason\n");
  for (const mocap::EvaluationRow& r : summary.rows) {
    fmt::format_to(out, "{},{},{},{},{},{},{},{},{}", mocap::ToString(r.method), r.gap_frames,
                   r.trial, CsvField(recording.labels()[static_cast<std::size_t>(r.marker)]),
                   r.first_frame, NumberOrEmpty(r.mean_error), NumberOrEmpty(r.max_error),
                   r.gap_seconds, mocap::ToString(r.status));
    for (double x : {r.p90_error, r.velocity_error, r.acceleration_error, r.velocity_jump_start,
                     r.velocity_jump_end, r.distance_deviation, r.distance_z}) {
      fmt::format_to(out, ",{}", NumberOrEmpty(x));
    }
    fmt::format_to(out, ",{},{}\n", mocap::ToString(r.outcome), r.prior_reason);
  }
  return fmt::to_string(csv);
}

nlohmann::json EvaluationSummaryJson(const EvaluateGapsSettings& settings,
                                     const mocap::EvaluationSummary& summary,
                                     const mocap::Recording& recording, const std::string& input) {
  nlohmann::json j = summary.ToJson();
  j.erase("rows");
  j["input"] = input;
  j["markers"] = recording.CountPoints(mocap::PointType::kMarker);
  j["frames"] = recording.frames();
  j["rate"] = recording.rate();
  j["settings"] = EchoEvaluateGapsSettings(settings);
  return j;
}

namespace {

// "method × gap length": a header naming what the cells hold, then cell(s) per method and length.
template <typename Cell>
std::string MethodTable(const mocap::EvaluationSummary& summary, const std::string& what,
                        Cell cell) {
  const mocap::EvaluationOptions& o = summary.settings;
  std::string table = fmt::format("{:<8}", "method");
  for (const mocap::EvaluationStatistics& s : summary.statistics) {
    if (s.method != o.methods.front()) continue;
    table += fmt::format(" {:>20}", fmt::format("{} s ({} fr)", s.gap_seconds, s.gap_frames));
  }
  table += fmt::format("\n{:<8}", "");
  for (std::size_t g = 0; g < o.gap_seconds.size(); ++g) table += fmt::format(" {:>20}", what);
  for (mocap::GapFillMethod method : o.methods) {
    table += fmt::format("\n{:<8}", mocap::ToString(method));
    for (const mocap::EvaluationStatistics& s : summary.statistics) {
      if (s.method == method) table += fmt::format(" {:>20}", cell(s));
    }
  }
  return table + "\n";
}

}  // namespace

std::string EvaluationTable(const mocap::EvaluationSummary& summary) {
  return MethodTable(summary, fmt::format("mean / p90 ({})", summary.units),
                     [](const mocap::EvaluationStatistics& s) {
                       std::string cell = fmt::format("{:.3g} / {:.3g}", s.mean, s.percentile_90);
                       if (s.failed > 0) cell += fmt::format(" ({} failed)", s.failed);
                       return cell;
                     });
}

std::string DynamicsTable(const mocap::EvaluationSummary& summary) {
  return MethodTable(summary, "acc. / jump", [](const mocap::EvaluationStatistics& s) {
    return fmt::format("{:.3g} / {:.3g}", s.acceleration_error.mean, s.velocity_jump.mean);
  });
}

int ReportEvaluateGaps(const EvaluateGapsSettings& settings,
                       const mocap::EvaluationSummary& summary, const mocap::Recording& recording,
                       const std::string& input, const std::string& out_dir) {
  OutputDir out(out_dir);
  out.WriteText("evaluation.csv", EvaluationCsv(summary, recording));
  out.WriteText("summary.json",
                JsonText(EvaluationSummaryJson(settings, summary, recording, input)) + "\n");
  const std::string title =
      fmt::format("{}: {} markers, {} Hz, {} trials per gap length, error in {}",
                  std::filesystem::path(input).filename().string(), recording.markers(),
                  recording.rate(), settings.evaluation.trials, summary.units);
  RunPlotScript("plot_gap_errors.py", {out.StagedPath("evaluation.csv").string(),
                                       out.Stage("errors.png").string(), title});
  out.Commit(WhenStopped::kPublish);
  fmt::print("{}: {} trials × {} gap lengths × {} methods in {:.3g} s\n", input,
             settings.evaluation.trials, settings.evaluation.gap_seconds.size(),
             settings.evaluation.methods.size(), summary.total_seconds);
  if (const nlohmann::json& part = summary.complete_part; !part.is_null()) {
    const auto first = part["first_frame"].get<std::int64_t>();
    fmt::print("evaluated on the complete part: frames {}–{} of {}, {} of {} markers\n", first,
               first + part["frames"].get<std::int64_t>() - 1, recording.frames(),
               part["markers"].size(), part["markers"].size() + part["dropped"].size());
  }
  fmt::print("{}", EvaluationTable(summary));
  fmt::print(
      "acceleration error ({}/s², filtered at {} Hz) / velocity jump at the ends ({}/s), "
      "means:\n{}",
      summary.units, settings.evaluation.filter_hz, summary.units, DynamicsTable(summary));
  fmt::print("wrote {}/evaluation.csv, summary.json, errors.png\n", out.dir().string());
  return RunExitCode(summary.termination, summary.message);
}

}  // namespace moreau::cli
