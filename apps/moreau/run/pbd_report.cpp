#include "run/pbd_report.h"

#include <iterator>

#include <fmt/format.h>

#include "moreau/common/summary_json.h"

namespace moreau::cli {

std::string PbdTrajectoryCsv(const PbdScenario& scenario, const PbdRunResult& result) {
  fmt::memory_buffer csv;
  auto out = std::back_inserter(csv);
  if (scenario.is_disks()) {
    fmt::format_to(out, "t,i,x,y\n");
    for (const TrajectoryFrame& f : result.frames) {
      for (int i = 0; i < static_cast<int>(f.x.size() / 2); ++i) {
        fmt::format_to(out, "{:.17g},{},{:.17g},{:.17g}\n", f.t, i, f.x[2 * i], f.x[2 * i + 1]);
      }
    }
    return fmt::to_string(csv);
  }
  fmt::format_to(out, "t");
  const int d = scenario.sliding.dimension;
  for (int i = 0; i < d; ++i) fmt::format_to(out, ",x{}", i);
  fmt::format_to(out, "\n");
  for (const TrajectoryFrame& f : result.frames) {
    fmt::format_to(out, "{:.17g}", f.t);
    for (int i = 0; i < static_cast<int>(f.x.size()); ++i) fmt::format_to(out, ",{:.17g}", f.x[i]);
    fmt::format_to(out, "\n");
  }
  return fmt::to_string(csv);
}

nlohmann::json PbdRunJson(const PbdScenario& scenario, const PbdRunResult& result,
                          const std::string& scenario_file) {
  nlohmann::json j = result.summary.ToJson();
  // The error is null (the message says why) when the run failed before it was known.
  if (result.error) {
    j["error"] = *result.error;
  } else if (!result.summary.ok() && (!scenario.is_disks() || scenario.reference_for_run)) {
    j["error"] = nullptr;
  }
  if (result.neighbour_list) {
    j["neighbour_list_builds"] = result.neighbour_list->neighbour_list_builds;
    j["candidate_pairs"] = result.neighbour_list->candidate_pairs;
  }
  j["settings"] = EchoPbdScenario(scenario);
  j["scenario_file"] = scenario_file;
  return j;
}

std::string ReportPbdRun(const PbdScenario& scenario, const PbdRunResult& result,
                         const nlohmann::json& summary, OutputDir& out, bool figures) {
  out.WriteText("summary.json", JsonText(summary) + "\n");
  out.WriteText("trajectory.csv", PbdTrajectoryCsv(scenario, result));
  if (figures) {
    RunPlotScript(
        "plot_run.py",
        {out.Stage("trajectory.png").string(), out.StagedPath("trajectory.csv").string(),
         scenario.kind, fmt::format("{}", scenario.is_disks() ? scenario.disks.radius : 0.0)});
  }
  out.Commit();

  std::string report = result.summary.BriefReport() + "\n";
  if (result.error) {
    report += fmt::format("error against the {} solution: {:.6e}\n",
                          scenario.is_disks() ? "reference" : "exact", *result.error);
  }
  report += fmt::format("wrote {}/summary.json, trajectory.csv{}\n", out.dir().string(),
                        figures ? ", trajectory.png" : "");
  return report;
}

}  // namespace moreau::cli
