#include "fill_gaps/fill_gaps_report.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "moreau/common/stop.h"
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
  j["markers"] = r.CountPoints(mocap::PointType::kMarker);
  j["samples_deleted"] = result.samples_deleted;
  for (std::size_t i = 0; i < result.errors.size(); ++i) {
    const auto& error = result.errors[i];
    const std::pair<const char*, double DeletedGapError::*> measures[] = {
        {"mean_error", &DeletedGapError::mean_error},
        {"max_error", &DeletedGapError::max_error},
        {"p90_error", &DeletedGapError::p90_error},
        {"velocity_error", &DeletedGapError::velocity_error},
        {"acceleration_error", &DeletedGapError::acceleration_error},
        {"velocity_jump_start", &DeletedGapError::velocity_jump_start},
        {"velocity_jump_end", &DeletedGapError::velocity_jump_end},
        {"distance_deviation", &DeletedGapError::distance_deviation},
        {"distance_z", &DeletedGapError::distance_z}};
    for (const auto& [name, field] : measures) {
      j["gaps"][i][name] = error ? FiniteOrNull((*error).*field) : nlohmann::json();
    }
  }
  j["settings"] = EchoFillGapsSettings(settings);
  return j;
}

namespace {

namespace fs = std::filesystem;

void PrintFillGapsReport(const FillGapsResult& result, const FillGapsInputs& inputs) {
  const mocap::FillSummary& s = result.summary;
  std::int64_t missing = 0;
  for (const mocap::GapReport& gap : s.gaps) missing += gap.last - gap.first + 1;
  fmt::print("{}: {} gaps, {} samples missing ({} deleted); method {}\n", inputs.recording,
             s.gaps.size(), missing, result.samples_deleted, s.method);
  // The summary's message counts the gaps by outcome, as report.json's "outcomes" does.
  fmt::print("  {}; {} samples filled in {:.3g} s\n", s.message, s.samples_filled, s.total_seconds);
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

// One warning line per marker missing in every frame (left missing, listed as unfillable).
void WarnNeverObserved(const FillGapsResult& result, const FillGapsInputs& inputs) {
  for (const mocap::GapReport& gap : result.summary.gaps) {
    if (gap.status != mocap::GapStatus::kNeverObserved) continue;
    std::fprintf(stderr,
                 "moreau: warning: %s: marker %s (index %d) is missing in every frame; it stays "
                 "missing (report.json: unfillable, never_observed)\n",
                 inputs.recording.c_str(), gap.label.c_str(), gap.marker);
  }
}

bool IsNonEmptyFile(const fs::path& path) {
  std::error_code ec;
  return fs::is_regular_file(path, ec) && fs::file_size(path, ec) > 0 && !ec;
}

// gaps.png from the staged filled.csv and report.json: true when it was written; otherwise one
// warning line saying why, and no partial figure is left to publish.
bool WriteGapsFigure(OutputDir& out) {
  if (StopRequested()) return false;  // stopping: nothing is published
  const fs::path png = out.Stage("gaps.png");
  std::string failure =
      RunFigureScript("plot_gaps.py", {out.StagedPath("filled.csv").string(),
                                       out.StagedPath("report.json").string(), png.string()});
  if (failure.empty() && !IsNonEmptyFile(png)) failure = "plot_gaps.py wrote no figure";
  if (failure.empty()) return true;
  std::error_code ec;
  fs::remove(png, ec);
  std::fprintf(stderr, "moreau: warning: gaps.png not written: %s; the numbers are written\n",
               failure.c_str());
  return false;
}

}  // namespace

int ReportFillGaps(const FillGapsSettings& settings, const FillGapsResult& result,
                   const FillGapsInputs& inputs, const std::string& out_dir) {
  OutputDir out(out_dir);
  for (const char* name : {"filled.c3d", "filled.csv"}) {
    out.WriteWith(name, [&](const std::filesystem::path& path) {
      mocap::WriteRecording(result.filled, path);
    });
  }
  out.WriteText("report.json", JsonText(FillGapsReportJson(settings, result, inputs)) + "\n");
  std::vector<std::string> written = {"filled.c3d", "filled.csv", "report.json"};
  for (const std::string& name : written) {
    if (!IsNonEmptyFile(out.StagedPath(name))) {
      throw std::runtime_error(fmt::format("{}/{}: not written", out.dir().string(), name));
    }
  }
  if (WriteGapsFigure(out)) written.push_back("gaps.png");
  out.Commit();
  WarnNeverObserved(result, inputs);
  PrintFillGapsReport(result, inputs);
  std::string names;
  for (const std::string& name : written) names += (names.empty() ? "" : ", ") + name;
  fmt::print("wrote {}/{}\n", out.dir().string(), names);
  return 0;
}

}  // namespace moreau::cli
