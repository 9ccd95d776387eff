// What `moreau run` writes for particles at scale, besides the trajectory the run streams:
// summary.json, evacuation.csv + evacuation.png (a room), snapshots.png (2D), the lines printed.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "output.h"
#include "run/particles_run.h"
#include "run/particles_scenario.h"

namespace moreau::cli {

// The engine's summary (counters, *_seconds) with the run's context, the final positions' hash,
// "msd" (mean squared displacement from the initial to the final positions), with a room
// "evacuated" and "evacuation_time" (when the last person went out; null when some are still
// in), and the scenario's settings: summary.json.
nlohmann::json ParticleRunJson(const ParticleScenario& scenario, const ParticleSetup& setup,
                               const ParticleRunResult& result, const std::string& scenario_file);

// Writes the rest of DIR (evacuation.csv, SUMMARY as summary.json and, with `figures`,
// evacuation.png and snapshots.png) and commits it. Returns the brief report `moreau run` prints.
std::string ReportParticleRun(const ParticleScenario& scenario, const ParticleSetup& setup,
                              const ParticleRunResult& result, const nlohmann::json& summary,
                              OutputDir& out, bool figures);

}  // namespace moreau::cli
