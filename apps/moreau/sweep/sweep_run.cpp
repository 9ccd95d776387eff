#include "sweep/sweep_run.h"

#include <cstdio>
#include <cstdlib>
#include <memory>

#include <fmt/format.h>

#include "control/control_report.h"
#include "control/control_run.h"
#include "control/control_scenario.h"
#include "fill_gaps/fill_gaps_report.h"
#include "fill_gaps/fill_gaps_run.h"
#include "fill_gaps/fill_gaps_scenario.h"
#include "mocap_settings.h"
#include "moreau/common/summary_json.h"
#include "moreau/common/error.h"
#include "moreau/common/stop.h"
#include "moreau/common/stopwatch.h"
#include "moreau/common/termination.h"
#include "moreau/sweep/grid.h"
#include "output.h"
#include "run/dispatch.h"
#include "signals.h"

namespace moreau::cli {
namespace {

namespace fs = std::filesystem;

// Writes summary.json into run_dir when one is asked for.
void WriteRunFolder(const fs::path& run_dir, const nlohmann::json& summary) {
  if (run_dir.empty()) return;
  OutputDir out(run_dir);
  out.WriteText("summary.json", JsonText(summary) + "\n");
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
SweepPointRun PrepareRunPoint(const SweepScenario& sweep, const std::vector<std::string>& overrides,
                              bool check_only) {
  Scenario scenario = Scenario::Load(sweep.scenario, overrides);
  RunRequest request;
  request.files = sweep.run_folders ? RunFiles::kNoFigures : RunFiles::kNone;
  request.check_only = check_only;
  auto run = std::make_shared<PreparedRun>(scenario, std::move(request));
  return [run](const fs::path& run_dir) { return run->Run(run_dir).summary; };
}

nlohmann::json FailedRow(std::string_view status, std::string_view message) {
  return {{"status", status}, {"message", message}};
}

// The key of the sweep file that sets a key of the base scenario named in MESSAGE (an
// InputError's "BASE: KEY: REASON" or "--set KEY=VALUE: REASON"): axes.KEY, seeds or set.KEY;
// "scenario" when none does.
std::string BlamedSweepKey(const SweepScenario& sweep, const std::string& message) {
  std::vector<std::pair<std::string, std::string>> keys;  // (in the sweep file, in the scenario)
  for (const sweep::Axis& axis : sweep.grid.axes) keys.emplace_back("axes." + axis.key, axis.key);
  if (!sweep.grid.seeds.empty()) keys.emplace_back("seeds", sweep.grid.seed_key);
  for (const sweep::Setting& f : sweep.fixed) keys.emplace_back("set." + f.key, f.key);
  for (const auto& [sweep_key, key] : keys) {
    if (message.find(": " + key + ": ") != std::string::npos ||
        message.rfind("--set " + key + "=", 0) == 0) {
      return sweep_key;
    }
  }
  return "scenario";
}

}  // namespace

SweepPointRun PrepareSweepPoint(const SweepScenario& sweep,
                                const std::vector<std::string>& overrides, bool check_only) {
  if (sweep.command == "fill-gaps") return PrepareFillGapsPoint(sweep, overrides);
  if (sweep.command == "control") return PrepareControlPoint(sweep, overrides);
  return PrepareRunPoint(sweep, overrides, check_only);
}

void CheckRuns(const SweepScenario& sweep, const Scenario& file) {
  for (std::int64_t i = 0; i < sweep.grid.RunCount(); ++i) {
    try {
      PrepareSweepPoint(sweep, sweep.Overrides(i), /*check_only=*/i > 0);
    } catch (const InputError& e) {
      std::string settings;
      for (const sweep::Setting& setting : sweep.grid.Run(i)) {
        settings +=
            fmt::format("{}{} = {}", settings.empty() ? " (" : ", ", setting.key, setting.value);
      }
      if (!settings.empty()) settings += ")";
      file.Fail(
          BlamedSweepKey(sweep, e.what()),
          fmt::format("{}{} is rejected: {}", i == 0 ? "the first run" : fmt::format("run {}", i),
                      settings, e.what()));
    }
  }
}

int RunOnRanks(const sweep::MpiSession& mpi, const std::function<int()>& body) {
  if (!mpi.active()) return body();
  if (mpi.rank() != 0) QuietStopMessages();
  int code = 1;
  try {
    return body();
  } catch (const Interrupted& e) {
    code = ReportInterrupted(std::string(e.what()) + "; no result published");
  } catch (const InputError& e) {
    std::fprintf(stderr, "moreau: error: %s\n", e.what());
    code = 2;
  } catch (const NumericalError& e) {
    std::fprintf(stderr, "moreau: numerical failure: %s\n", e.what());
    code = 3;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "moreau: error: %s\n", e.what());
  }
  std::fflush(stderr);
  QuietStopMessages();  // the SIGTERM mpirun sends the other ranks is no news
  mpi.Abort(code);
}

void CheckBeforeMpi(const std::function<void()>& checks) {
  try {
    checks();
  } catch (const InputError&) {
    for (const char* name : {"OMPI_COMM_WORLD_RANK", "PMI_RANK", "PMIX_RANK"}) {
      const char* rank = std::getenv(name);
      if (rank != nullptr && std::atoi(rank) != 0) std::exit(2);
    }
    throw;
  }
}

bool RowInterrupted(const nlohmann::json& status) {
  return status.is_string() &&
         status.get_ref<const std::string&>() == ToString(Termination::kInterrupted);
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
  } catch (const Interrupted& e) {
    row = FailedRow(ToString(Termination::kInterrupted), e.what());
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
