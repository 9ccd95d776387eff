#include "fill_gaps/fill_gaps_report.h"

#include <algorithm>
#include <cstdio>
#include <map>

#include <fmt/format.h>

#include "moreau/common/summary_json.h"
#include "moreau/mocap/recording_io.h"
#include "output.h"

namespace moreau::cli {

nlohmann::json FillGapsReportJson(const FillGapsSettings& settings, const FillGapsResult& result,
                                  const FillGapsInputs& inputs) {
  const mocap::Recording& r = result.filled;
  nlohmann::json j = result.summary.ToJson();
  j["input"] = inputs.recording;
  j["gaps_file"] = inputs.gaps_file.empty() ? nlohmann::json() : nlohmann::json(inputs.gaps_file);
  j["units"] = r.units();
  j["rate"] = r.rate();
  j["frames"] = r.frames();
  j["markers"] = r.markers();
  j["samples_deleted"] = result.samples_deleted;
  for (std::size_t i = 0; i < result.errors.size(); ++i) {
    const auto& error = result.errors[i];
    j["gaps"][i]["mean_error"] = error ? FiniteOrNull(error->mean_error) : nlohmann::json();
    j["gaps"][i]["max_error"] = error ? FiniteOrNull(error->max_error) : nlohmann::json();
  }
  j["settings"] = EchoFillGapsSettings(settings);
  return j;
}

namespace {

void PrintFillGapsReport(const FillGapsResult& result, const FillGapsInputs& inputs) {
  const mocap::FillSummary& s = result.summary;
  std::int64_t missing = 0;
  std::map<mocap::GapStatus, int> by_status;
  for (const mocap::GapReport& gap : s.gaps) {
    missing += gap.last - gap.first + 1;
    ++by_status[gap.status];
  }
  std::string statuses;
  for (const auto& [status, count] : by_status) {
    statuses +=
        fmt::format("{}{} {}", statuses.empty() ? "" : ", ", mocap::ToString(status), count);
  }
  fmt::print("{}: {} gaps, {} samples missing ({} deleted); method {}\n", inputs.recording,
             s.gaps.size(), missing, result.samples_deleted, s.method);
  fmt::print("  {}; {} samples filled in {:.3g} s\n", statuses.empty() ? "no gaps" : statuses,
             s.samples_filled, s.total_seconds);
  double mean = 0.0, max = 0.0;
  int measured = 0;
  for (const auto& error : result.errors) {
    if (!error) continue;
    mean += error->mean_error;
    max = std::max(max, error->max_error);
    ++measured;
  }
  if (measured > 0) {
    fmt::print("  error on the deleted samples: mean {:.4g} {}, max {:.4g} {} ({} gaps)\n",
               mean / measured, result.filled.units(), max, result.filled.units(), measured);
  }
}

}  // namespace

int ReportFillGaps(const FillGapsSettings& settings, const FillGapsResult& result,
                   const FillGapsInputs& inputs, const std::string& out_dir) {
  OutputDir out(out_dir);
  mocap::WriteRecording(result.filled, out.Stage("filled.c3d"));
  mocap::WriteRecording(result.filled, out.Stage("filled.csv"));
  out.WriteText("report.json", FillGapsReportJson(settings, result, inputs).dump(2) + "\n");
  RunPlotScript("plot_gaps.py",
                {out.StagedPath("filled.csv").string(), out.StagedPath("report.json").string(),
                 out.Stage("gaps.png").string()});
  out.Commit();
  PrintFillGapsReport(result, inputs);
  fmt::print("wrote {}/filled.c3d, filled.csv, report.json, gaps.png\n", out.dir().string());
  return 0;
}

}  // namespace moreau::cli
