#include "run/population_run.h"

#include <filesystem>
#include <optional>

#include <fmt/format.h>

#include "field_table.h"
#include "moreau/common/summary_json.h"
#include "moreau/common/error.h"
#include "moreau/common/hash.h"
#include "moreau/common/steps.h"
#include "progress.h"
#include "run/particles_run.h"
#include "run/population_frames.h"
#include "run/scene_geometry.h"
#include "signals.h"

namespace moreau::cli {
namespace {

std::string CsvHeader(const particles::PopulationRules& rules) {
  std::string h = "step,t,count";
  for (const particles::AgentType& t : rules.types) h += ",count_" + t.name;
  return h +
         ",mean_radius,contacts,overlap_before,overlap,colony_radius,births,deaths,removals,"
         "segregation\n";
}

std::string CsvRow(const particles::PopulationObservables& o) {
  std::string row = fmt::format("{},{:.9g},{}", o.step, o.time, o.count);
  for (std::int64_t c : o.count_per_type) row += fmt::format(",{}", c);
  return row + fmt::format(",{:.9g},{},{:.9g},{:.9g},{:.9g},{},{},{},{:.9g}\n", o.mean_radius,
                           o.contacts, o.overlap_before, o.overlap, o.colony_radius, o.births,
                           o.deaths, o.removals, o.segregation);
}

// "id,type,generation,x,y[,z],r", one row per agent.
std::string AgentsCsv(const particles::Population& p) {
  const int k = p.engine().dimension();
  std::string csv = k == 2 ? "id,type,generation,x,y,r\n" : "id,type,generation,x,y,z,r\n";
  const std::vector<double> x = p.count() > 0 ? p.Positions() : std::vector<double>{};
  for (std::size_t i = 0; i < p.agents().size(); ++i) {
    const particles::Agent& a = p.agents()[i];
    csv += fmt::format("{},{},{}", a.id, a.type, a.generation);
    for (int c = 0; c < k; ++c)
      csv +=
          fmt::format(",{:.9g}", x[static_cast<std::size_t>(k) * i + static_cast<std::size_t>(c)]);
    csv += fmt::format(",{:.9g}\n", a.radius);
  }
  return csv;
}

}  // namespace

particles::Population SetUpPopulationRun(const ParticleScenario& scenario, const Scenario& file) {
  particles::ParticleModel model = scenario.MakeModel();
  WithKey(file, "problem", [&] { model.Validate(); });
  std::vector<double> x0 = InitialPositions(scenario, model, file);
  if (scenario.fix_overlaps) WithKey(file, "initial", [&] { particles::FixOverlaps(model, x0); });
  std::optional<particles::Population> population;
  WithKey(file, "initial", [&] {
    population.emplace(std::move(model), scenario.MakeForces(), scenario.MakeEngineOptions(),
                       scenario.MakeRules(), scenario.InitialTypes(), x0);
  });
  if (scenario.fields.enabled()) {
    WithKey(file, "", [&] {
      population->CoupleFields(scenario.MakeFields(population->engine().threads()),
                               scenario.fields.coupling);
    });
  }
  return std::move(*population);
}

namespace {

// What a population run records as it goes: population.csv every record_every observations,
// the lineage and the trajectory frames; State/Resume for checkpoints.
class PopulationRecorder {
 public:
  PopulationRecorder(OutputDir& out, const ParticleScenario& scenario,
                     const particles::Population& population, std::int64_t steps)
      : scenario_(scenario),
        frames_(out, scenario,
                scenario.output.stride > 0 ? scenario.output.stride
                                           : std::max<std::int64_t>(1, steps / 100)),
        geometry_(WriteSceneGeometry(population.engine().model(), scenario, out)),
        csv_(CsvHeader(population.rules())) {}

  void Observe(const particles::Population& p) {
    if (observed_++ % scenario_.population.record_every == 0) {
      csv_ += CsvRow(p.Observe());
      recorded_step_ = p.engine().step();
    }
    lineage_.Observe(p);
    frames_.Write(p, lineage_, false);
  }

  void KeepFrames() { frames_.KeepFrames(); }
  nlohmann::json State() const {
    return {{"csv", csv_},
            {"observed", observed_},
            {"recorded_step", recorded_step_},
            {"lineage", lineage_.State()},
            {"frames", frames_.State()}};
  }
  void Resume(const nlohmann::json& run) {
    try {
      const nlohmann::json& state = run.at("recorder");
      state.at("csv").get_to(csv_);
      state.at("observed").get_to(observed_);
      state.at("recorded_step").get_to(recorded_step_);
      lineage_.Resume(state.at("lineage"));
      frames_.Resume(state.at("frames"));
    } catch (const nlohmann::json::exception&) {
      throw InputError("checkpoint: the run's population records are malformed");
    }
  }

  // The final state (the last step, or the step at which the last agent left) when not yet in.
  PopulationRunResult Finish(particles::PopulationSummary summary,
                             const particles::Population& population) {
    if (recorded_step_ != population.engine().step() || population.count() == 0) {
      csv_ += CsvRow(population.Observe());
    }
    lineage_.Observe(population);
    frames_.Write(population, lineage_, false);
    frames_.Close();
    return {std::move(summary),    std::move(csv_),      lineage_.Csv(population.rules()),
            scenario_.output.hdf5, scenario_.output.vtu, geometry_};
  }

 private:
  const ParticleScenario& scenario_;
  PopulationFrames frames_;
  bool geometry_;
  Lineage lineage_;
  std::string csv_;
  std::int64_t observed_ = 0;
  std::int64_t recorded_step_ = -1;
};

}  // namespace

PopulationRunResult RunPopulation(const ParticleScenario& scenario,
                                  particles::Population& population, OutputDir& out,
                                  const CheckpointPlan& checkpoints) {
  const std::int64_t steps = StepCount(scenario.T, scenario.solver.h);
  PopulationRecorder recorder(out, scenario, population, steps);
  if (checkpoints.every > 0 || checkpoints.resumed) recorder.KeepFrames();
  if (checkpoints.resumed) recorder.Resume(*checkpoints.resumed);
  std::int64_t last_checkpoint = population.engine().step();
  ProgressBar progress("run", steps);
  const StopScope stop_on_signal;  // SIGINT/SIGTERM: stop after the current step
  // The observer runs after each rule step: a checkpoint at the first one past each multiple of
  // checkpoints.every.
  const auto observe = [&](const particles::Population& p) {
    recorder.Observe(p);
    progress.Update(p.engine().step());
    if (CheckpointDue(checkpoints, last_checkpoint, p.engine().step(), steps)) {
      last_checkpoint = p.engine().step();
      WriteRunCheckpoint(checkpoints, p, {{"recorder", recorder.State()}});
    }
    return !StopRequested();
  };
  particles::PopulationSummary summary = checkpoints.resumed
                                             ? population.Continue(scenario.T, observe)
                                             : population.Run(scenario.T, observe);
  progress.Finish();
  return recorder.Finish(std::move(summary), population);
}

nlohmann::json PopulationRunJson(const ParticleScenario& scenario,
                                 const particles::Population& population,
                                 const PopulationRunResult& result,
                                 const std::string& scenario_file) {
  nlohmann::json j = result.summary.ToJson();
  j["engine_kind"] = "particles";
  j["scenario_file"] = scenario_file;
  j["dimension"] = population.engine().dimension();
  j["positions_hash"] =
      HashDoublesHex(population.count() > 0 ? population.Positions() : std::vector<double>{});
  j["scenario"] = EchoParticleScenario(scenario);
  return j;
}

std::string ReportPopulationRun(const particles::Population& population,
                                const PopulationRunResult& result, const nlohmann::json& summary,
                                OutputDir& out) {
  out.WriteText("population.csv", result.series_csv);
  out.WriteText("agents.csv", AgentsCsv(population));
  out.WriteText("lineage.csv", result.lineage_csv);
  out.WriteText("summary.json", JsonText(summary) + "\n");
  out.Commit(WhenStopped::kPublish);
  const particles::PopulationSummary& s = result.summary;
  return fmt::format(
      "{}\nagents: {} (births {}, deaths {}, removals {}){}{}\n"
      "wrote {}/summary.json, population.csv, agents.csv, lineage.csv{}{}{}{}\n",
      s.engine.BriefReport(), population.count(), s.births, s.deaths, s.removals,
      s.message.empty() ? "" : " — ", s.message, out.dir().string(),
      result.hdf5 ? ", trajectory.h5 + .xdmf" : "", result.vtu ? ", vtu/frame.pvd" : "",
      result.geometry ? ", geometry.vtp" : "",
      population.fields() == nullptr ? ""
      : result.hdf5 && result.vtu    ? ", fields.h5 + .xdmf, vti/fields.pvd"
      : result.hdf5                  ? ", fields.h5 + .xdmf"
      : result.vtu                   ? ", vti/fields.pvd"
                                     : "");
}

}  // namespace moreau::cli
