#include "sweep/sweep_run.h"

#include <sstream>

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
#include "run/particles_report.h"
#include "run/particles_run.h"
#include "run/particles_scenario.h"
#include "run/pbd_report.h"
#include "run/pbd_run.h"
#include "run/pbd_scenario.h"

namespace moreau::cli {
namespace {

namespace fs = std::filesystem;

// Writes summary.json (and `extra` files) into run_dir when one is asked for.
void WriteRunFolder(const fs::path& run_dir, const nlohmann::json& summary,
                    const std::vector<std::pair<std::string, std::string>>& extra = {}) {
  if (run_dir.empty()) return;
  OutputDir out(run_dir);
  out.WriteText("summary.json", summary.dump(2) + "\n");
  for (const auto& [name, text] : extra) out.WriteText(name, text);
  out.Commit();
}

// The time of the first row of "t,out" whose count is everybody; null when there is none.
nlohmann::json EvacuationTime(const std::string& series_csv, int people) {
  std::istringstream in(series_csv);
  std::string line;
  std::getline(in, line);  // header
  while (std::getline(in, line)) {
    const std::size_t comma = line.find(',');
    if (std::stoi(line.substr(comma + 1)) == people) return std::stod(line.substr(0, comma));
  }
  return nullptr;
}

double MeanSquaredDisplacement(const std::vector<double>& x0, const std::vector<double>& x,
                               int count) {
  double sum = 0.0;
  for (std::size_t i = 0; i < x.size(); ++i) sum += (x[i] - x0[i]) * (x[i] - x0[i]);
  return count > 0 ? sum / count : 0.0;
}

nlohmann::json RunParticlePoint(Scenario& scenario, const fs::path& run_dir) {
  ParticleScenario settings = ReadParticleScenario(scenario, false);
  scenario.CheckAllKeysUsed();
  if (run_dir.empty()) {  // no trajectory, no figures: the numbers only
    settings.output.hdf5 = false;
    settings.output.vtu = false;
    settings.output.snapshots = false;
  }
  ParticleSetup setup = SetUpParticleRun(settings, scenario);
  const std::vector<double> x0 = setup.engine.Positions();
  // RunParticles stages its trajectory here; without a run folder nothing is staged and the
  // scratch folder goes with `out`.
  OutputDir out = run_dir.empty() ? OutputDir::Scratch() : OutputDir(run_dir);
  const ParticleRunResult result = RunParticles(settings, setup, out);
  nlohmann::json j = ParticleRunJson(settings, setup, result, scenario.path());
  j["msd"] = MeanSquaredDisplacement(x0, result.x, setup.engine.count());
  if (result.evacuated)
    j["evacuation_time"] = EvacuationTime(result.evacuation_csv, setup.engine.count());
  if (!run_dir.empty()) {
    out.WriteText("summary.json", j.dump(2) + "\n");
    if (result.evacuated) out.WriteText("evacuation.csv", result.evacuation_csv);
    out.Commit();
  }
  return j;
}

nlohmann::json FailedRow(std::string_view status, std::string_view message) {
  return {{"status", status}, {"message", message}};
}

}  // namespace

nlohmann::json RunSweepPoint(const SweepScenario& sweep, const std::vector<std::string>& overrides,
                             const fs::path& run_dir) {
  if (sweep.command == "fill-gaps") {
    Scenario scenario = sweep.scenario.empty() ? Scenario::FromCommandLine(overrides)
                                               : Scenario::Load(sweep.scenario, overrides);
    const FillGapsSettings settings = ReadFillGapsSettings(scenario);
    const mocap::Recording recording =
        ReadRecordingReportingWarnings(sweep.recording, settings.read);
    const FillGapsResult result = RunFillGaps(recording, {}, settings);
    const nlohmann::json j = FillGapsReportJson(settings, result, {sweep.recording, ""});
    WriteRunFolder(run_dir, j);
    return j;
  }
  Scenario scenario = Scenario::Load(sweep.scenario, overrides);
  if (sweep.command == "control") {
    const ControlScenario c = ReadControlScenario(scenario);
    scenario.CheckAllKeysUsed();
    const nlohmann::json j = ControlRunJson(c, RunControl(c), sweep.scenario);
    WriteRunFolder(run_dir, j);
    return j;
  }
  if (scenario.GetString("problem.kind", "") == "particles") {
    return RunParticlePoint(scenario, run_dir);
  }
  const PbdScenario pbd_scenario = ReadPbdScenario(scenario);
  scenario.CheckAllKeysUsed();
  const PbdRunResult result = RunPbdScenario(pbd_scenario);
  const nlohmann::json j = PbdRunJson(pbd_scenario, result, sweep.scenario);
  WriteRunFolder(run_dir, j, {{"trajectory.csv", PbdTrajectoryCsv(pbd_scenario, result)}});
  return j;
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
    const nlohmann::json summary = RunSweepPoint(sweep, sweep.Overrides(index), run_dir);
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
