#include "run/particles_checkpoint.h"

#include <fstream>
#include <iterator>

#include <fmt/format.h>

#include "moreau/common/error.h"
#include "moreau/common/hash.h"

namespace moreau::cli {

std::string ScenarioFingerprint(const std::string& scenario_path,
                                const std::vector<std::string>& overrides, bool fix_overlaps) {
  std::ifstream in(scenario_path, std::ios::binary);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  for (const std::string& o : overrides) {
    if (o.rfind("solver.threads=", 0) != 0) text += "\n--set " + o;
  }
  if (fix_overlaps) text += "\n--fix-overlaps";
  return fmt::format("{:016x}", HashBytes(text));
}

CheckpointPlan PlanCheckpoints(std::int64_t every, const std::string& resume_dir,
                               const std::string& out_dir, std::string fingerprint,
                               const CheckpointRestore& restore) {
  if (every < 0) {
    throw InputError(fmt::format("--checkpoint-every must be ≥ 0 steps (got {})", every));
  }
  CheckpointPlan plan;
  if (every == 0 && resume_dir.empty()) return plan;
  plan.every = every;
  plan.fingerprint = std::move(fingerprint);
  const std::filesystem::path dir = resume_dir.empty() ? out_dir + ".checkpoint" : resume_dir;
  plan.file = dir / "checkpoint.bin";
  if (resume_dir.empty()) {
    std::filesystem::create_directories(dir);
    return plan;
  }
  if (!std::filesystem::is_directory(resume_dir)) {
    throw InputError(fmt::format("--resume: {} is not a directory", resume_dir));
  }
  nlohmann::json run;
  const particles::EngineState state = particles::ReadCheckpoint(plan.file, &run);
  if (!run.is_object() || run.value("fingerprint", "") != plan.fingerprint) {
    throw InputError(
        fmt::format("{}: checkpoint: made for another scenario (fingerprint {}, this run's {})",
                    plan.file.string(), run.is_object() ? run.value("fingerprint", "none") : "none",
                    plan.fingerprint));
  }
  try {
    restore(state, run);
  } catch (const InputError& e) {
    throw InputError(fmt::format("{}: {}", plan.file.string(), e.what()));
  } catch (const nlohmann::json::exception&) {
    throw InputError(
        fmt::format("{}: checkpoint: the run's state is malformed", plan.file.string()));
  }
  plan.resumed = std::move(run);
  return plan;
}

CheckpointPlan PlanCheckpoints(std::int64_t every, const std::string& resume_dir,
                               const std::string& out_dir, std::string fingerprint,
                               particles::Engine& engine) {
  return PlanCheckpoints(every, resume_dir, out_dir, std::move(fingerprint),
                         [&](const particles::EngineState& state, const nlohmann::json&) {
                           engine.RestoreState(state);
                         });
}

CheckpointPlan PlanCheckpoints(std::int64_t every, const std::string& resume_dir,
                               const std::string& out_dir, std::string fingerprint,
                               particles::Population& population) {
  return PlanCheckpoints(
      every, resume_dir, out_dir, std::move(fingerprint),
      [&](const particles::EngineState& state, const nlohmann::json& run) {
        if (!run.contains("population")) {
          throw InputError("checkpoint: it holds no population (made by a run without [[types]])");
        }
        population.RestoreState(particles::PopulationState::FromJson(run.at("population"), state));
      });
}

void WriteRunCheckpoint(const CheckpointPlan& plan, const particles::Engine& engine,
                        nlohmann::json recorder) {
  recorder["fingerprint"] = plan.fingerprint;
  particles::WriteCheckpoint(plan.file, engine.SaveState(), recorder);
}

void WriteRunCheckpoint(const CheckpointPlan& plan, const particles::Population& population,
                        nlohmann::json recorder) {
  const particles::PopulationState state = population.SaveState();
  recorder["fingerprint"] = plan.fingerprint;
  recorder["population"] = state.ToJson();
  particles::WriteCheckpoint(plan.file, state.engine, recorder);
}

}  // namespace moreau::cli
