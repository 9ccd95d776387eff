#include "run/particles_report.h"

#include <filesystem>
#include <fstream>
#include <sstream>

#include <fmt/format.h>

#include "moreau/common/summary_json.h"
#include "moreau/common/hash.h"

namespace moreau::cli {
namespace {

// "t,i,x,y,r", one row per particle and snapshot (2D), for the snapshot figure.
void WriteFramesCsv(const std::filesystem::path& path, int k, const std::vector<double>& radius,
                    const std::vector<std::pair<double, std::vector<double>>>& frames) {
  std::ofstream f(path);
  f << "t,i,x,y,r\n";
  const auto stride = static_cast<std::size_t>(k);
  for (const auto& [t, x] : frames) {
    for (std::size_t i = 0; i < radius.size(); ++i) {
      f << fmt::format("{:.9g},{},{:.9g},{:.9g},{:.9g}\n", t, i, x[stride * i], x[stride * i + 1],
                       radius[i]);
    }
  }
}

bool WritesSnapshots(const ParticleScenario& scenario) {
  return scenario.output.snapshots && scenario.dimension == 2;
}

void WriteFigures(const ParticleScenario& scenario, const particles::ParticleModel& model,
                  const ParticleRunResult& result, OutputDir& out) {
  if (result.evacuated) {
    RunPlotScript("plot_particles.py",
                  {"--series", out.Stage("evacuation.png").string(),
                   out.StagedPath("evacuation.csv").string(), "time", "people out"});
  }
  if (WritesSnapshots(scenario)) {
    const std::filesystem::path csv = out.StagedPath(".snapshots.csv");
    WriteFramesCsv(csv, model.dimension, model.radius, result.snapshots);
    RunPlotScript("plot_particles.py", {out.Stage("snapshots.png").string(), csv.string()});
    std::filesystem::remove(csv);
  }
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

}  // namespace

nlohmann::json ParticleRunJson(const ParticleScenario& scenario, const ParticleSetup& setup,
                               const ParticleRunResult& result, const std::string& scenario_file) {
  const particles::EngineSummary& summary = result.summary;
  const particles::Engine& engine = setup.engine;
  nlohmann::json j = summary.ToJson();
  j["method"] = "pbd";
  j["engine"] = "particles";
  j["h"] = summary.settings.h;
  j["particles"] = engine.count();
  j["dimension"] = engine.dimension();
  j["threads"] = engine.threads();
  j["sweep_order"] = particles::SweepOrderName(summary.settings.order);
  j["max_violation"] = summary.stats.max_overlap;
  j["fix_overlaps_sweeps"] = setup.fix_overlaps_sweeps;
  j["scenario_file"] = scenario_file;
  j["positions_hash"] = HashDoublesHex(result.x);  // final positions, id order (FNV-1a of bits)
  j["msd"] = MeanSquaredDisplacement(setup.x0, result.x, engine.count());
  if (result.evacuated) {
    j["evacuated"] = *result.evacuated;
    j["evacuation_time"] = EvacuationTime(result.evacuation_csv, engine.count());
  }
  j["settings"] = EchoParticleScenario(scenario);
  return j;
}

std::string ReportParticleRun(const ParticleScenario& scenario, const ParticleSetup& setup,
                              const ParticleRunResult& result, const nlohmann::json& summary,
                              OutputDir& out, bool figures) {
  if (result.evacuated) out.WriteText("evacuation.csv", result.evacuation_csv);
  if (!result.exits_csv.empty()) out.WriteText("exits.csv", result.exits_csv);
  out.WriteText("summary.json", JsonText(summary) + "\n");
  if (figures) WriteFigures(scenario, setup.engine.model(), result, out);
  out.Commit(WhenStopped::kPublish);  // a run stopped on request is a result

  std::string report = result.summary.BriefReport() + "\n";
  if (result.evacuated) {
    report += fmt::format("people out at t = {:g}: {} of {}\n", setup.engine.time(),
                          *result.evacuated, setup.engine.count());
  }
  report += fmt::format("wrote {}/summary.json{}{}{}{}{}\n", out.dir().string(),
                        result.hdf5 ? ", trajectory.h5 + .xdmf" : "",
                        result.txt ? ", trajectory.txt" : "", result.vtu ? ", vtu/frame.pvd" : "",
                        result.geometry ? ", geometry.vtp" : "",
                        figures && WritesSnapshots(scenario) ? ", snapshots.png" : "");
  return report;
}

}  // namespace moreau::cli
