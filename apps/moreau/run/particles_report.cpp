#include "run/particles_report.h"

#include <cstdio>
#include <filesystem>
#include <fstream>

#include <fmt/format.h>

#include "moreau/common/hash.h"
#include "signals.h"

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
  if (result.evacuated) j["evacuated"] = *result.evacuated;
  j["settings"] = EchoParticleScenario(scenario);
  return j;
}

int ReportParticleRun(const ParticleScenario& scenario, const ParticleSetup& setup,
                      const ParticleRunResult& result, const std::string& scenario_file,
                      OutputDir& out) {
  if (result.evacuated) out.WriteText("evacuation.csv", result.evacuation_csv);
  out.WriteText("summary.json",
                ParticleRunJson(scenario, setup, result, scenario_file).dump(2) + "\n");
  WriteFigures(scenario, setup.engine.model(), result, out);
  out.Commit();

  const particles::EngineSummary& summary = result.summary;
  std::printf("%s\n", summary.BriefReport().c_str());
  if (result.evacuated) {
    std::printf("people out at t = %g: %d of %d\n", setup.engine.time(), *result.evacuated,
                setup.engine.count());
  }
  std::printf("wrote %s/summary.json%s%s%s\n", out.dir().c_str(),
              result.hdf5 ? ", trajectory.h5 + .xdmf" : "", result.vtu ? ", vtu/frame.pvd" : "",
              WritesSnapshots(scenario) ? ", snapshots.png" : "");
  return RunExitCode(summary.termination, summary.message);
}

}  // namespace moreau::cli
