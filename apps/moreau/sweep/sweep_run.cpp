#include "sweep/sweep_run.h"

#include <memory>

#include <fmt/format.h>

#include "control/control_report.h"
#include "control/control_run.h"
#include "control/control_scenario.h"
#include "fill_gaps/fill_gaps_report.h"
#include "fill_gaps/fill_gaps_run.h"
#include "fill_gaps/fill_gaps_scenario.h"
#include "mocap_settings.h"
#include "moreau/common/error.h"
#include "moreau/common/stopwatch.h"
#include "moreau/common/termination.h"
#include "moreau/sweep/grid.h"
#include "output.h"
#include "run/dispatch.h"

namespace moreau::cli {
namespace {

namespace fs = std::filesystem;

// Writes summary.json into run_dir when one is asked for.
void WriteRunFolder(const fs::path& run_dir, const nlohmann::json& summary) {
  if (run_dir.empty()) return;
  OutputDir out(run_dir);
  out.WriteText("summary.json", summary.dump(2) + "\n");
  out.Commit();
}

SweepPointRun PrepareFillGapsPoint(const SweepScenario& sweep,
                                   const std::vector<std::string>& overrides) {
  Scenario scenario = sweep.scenario.empty() ? Scenario::FromCommandLine(overrides)
                                             : Scenario::Load(sweep.scenario, overrides);
  const FillGapsSettings settings = ReadFillGapsSettings(scenario);
  return [settings, &sweep](const fs::path& run_dir) {
    const mocap::Recording recording =
        ReadRecordingReportingWarnings(sweep.recording, settings.read);
    const FillGapsResult result = RunFillGaps(recording, {}, settings);
    const nlohmann::json j = FillGapsReportJson(settings, result, {sweep.recording, ""});
    WriteRunFolder(run_dir, j);
    return j;
  };
}

SweepPointRun PrepareControlPoint(const SweepScenario& sweep,
                                  const std::vector<std::string>& overrides) {
  Scenario scenario = Scenario::Load(sweep.scenario, overrides);
  const ControlScenario c = ReadControlScenario(scenario);
  scenario.CheckAllKeysUsed();
  return [c, &sweep](const fs::path& run_dir) {
    const nlohmann::json j = ControlRunJson(c, RunControl(c), sweep.scenario);
    WriteRunFolder(run_dir, j);
    return j;
  };
}

// command = "run": the run command's dispatch; a run folder gets what `moreau run` writes but
// the figures, and without one nothing is written (no trajectory either).
SweepPointRun PrepareRunPoint(const SweepScenario& sweep,
                              const std::vector<std::string>& overrides) {
  Scenario scenario = Scenario::Load(sweep.scenario, overrides);
  RunRequest request;
  request.files = sweep.run_folders ? RunFiles::kNoFigures : RunFiles::kNone;
  auto run = std::make_shared<PreparedRun>(scenario, std::move(request));
  return [run](const fs::path& run_dir) {
    // Without a run folder nothing is staged, and the scratch folder goes with `out`.
    OutputDir out = run_dir.empty() ? OutputDir::Scratch() : OutputDir(run_dir);
    return run->Run(out).summary;
  };
}

nlohmann::json FailedRow(std::string_view status, std::string_view message) {
  return {{"status", status}, {"message", message}};
}

// The sweep key that sets `key` of the base scenario in the first run, as the sweep file names
// it; "" when none does.
std::string SweepKeyOf(const SweepScenario& sweep, std::string_view key) {
  for (const sweep::Axis& axis : sweep.grid.axes) {
    if (axis.key == key) return "axes." + axis.key;
  }
  if (!sweep.grid.seeds.empty() && sweep.grid.seed_key == key) return "seeds";
  for (const sweep::Setting& f : sweep.fixed) {
    if (f.key == key) return "set." + f.key;
  }
  return "";
}

}  // namespace

SweepPointRun PrepareSweepPoint(const SweepScenario& sweep,
                                const std::vector<std::string>& overrides) {
  if (sweep.command == "fill-gaps") return PrepareFillGapsPoint(sweep, overrides);
  if (sweep.command == "control") return PrepareControlPoint(sweep, overrides);
  return PrepareRunPoint(sweep, overrides);
}

void CheckFirstRun(const SweepScenario& sweep, const Scenario& file) {
  const std::vector<sweep::Setting> first = sweep.grid.Run(0);
  try {
    PrepareSweepPoint(sweep, sweep.Overrides(0));
  } catch (const InputError& e) {
    // The base scenario's message is "BASE: KEY: REASON"; the key it names, when a sweep key
    // sets it, is the one to blame.
    const std::string what = e.what();
    std::string key = "scenario";
    for (const std::vector<sweep::Setting>* list : {&first, &sweep.fixed}) {
      for (const sweep::Setting& setting : *list) {
        if (what.find(": " + setting.key + ": ") != std::string::npos) {
          key = SweepKeyOf(sweep, setting.key);
        }
      }
    }
    std::string settings;
    for (const sweep::Setting& setting : first) {
      settings +=
          fmt::format("{}{} = {}", settings.empty() ? "" : ", ", setting.key, setting.value);
    }
    file.Fail(key, fmt::format("the first run ({}) is rejected: {}", settings, what));
  }
}

bool RowSucceeded(const nlohmann::json& status) {
  if (!status.is_string()) return false;
  const std::string& name = status.get_ref<const std::string&>();
  return name == ToString(Termination::kCompleted) || name == ToString(Termination::kConverged);
}

nlohmann::json SummaryValue(const nlohmann::json& summary, const std::string& key) {
  const nlohmann::json* node = &summary;
  std::size_t start = 0;
  while (true) {
    const std::size_t dot = key.find('.', start);
    const std::string part = key.substr(start, dot == std::string::npos ? dot : dot - start);
    if (!node->is_object() || !node->contains(part)) return nullptr;
    node = &(*node)[part];
    if (dot == std::string::npos) return *node;
    start = dot + 1;
  }
}

nlohmann::json SweepEntry(const SweepScenario& sweep, std::int64_t index, const fs::path& out_dir) {
  const std::string hash = sweep::RunHash(sweep.context, sweep.grid.Run(index));
  const Stopwatch clock;
  nlohmann::json row;
  try {
    const fs::path run_dir = sweep.run_folders ? out_dir / "runs" / hash : fs::path();
    const nlohmann::json summary = PrepareSweepPoint(sweep, sweep.Overrides(index))(run_dir);
    row = {{"status", summary.value("termination", "completed")},
           {"message", summary.value("message", "")}};
    for (const std::string& key : sweep.collect) row[key] = SummaryValue(summary, key);
  } catch (const InputError& e) {
    row = FailedRow("input_error", e.what());
  } catch (const NumericalError& e) {
    row = FailedRow("numerical_error", e.what());
  } catch (const std::exception& e) {
    row = FailedRow("error", e.what());
  }
  return {{"hash", hash}, {"index", index}, {"seconds", clock.Seconds()}, {"row", row}};
}

}  // namespace moreau::cli
