// What `moreau run` writes for particles at scale, besides the trajectory the run streams:
// summary.json, evacuation.csv + evacuation.png (a room), snapshots.png (2D), the lines printed.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "output.h"
#include "run/particles_run.h"
#include "run/particles_scenario.h"

namespace moreau::cli {

// The engine's summary (counters, *_seconds) with the run's context, the final positions' hash
// and the scenario's settings.
nlohmann::json ParticleRunJson(const ParticleScenario& scenario, const ParticleSetup& setup,
                               const ParticleRunResult& result, const std::string& scenario_file);

// Writes the rest of DIR, commits it and prints the brief report. Returns the exit code: 0, or 3
// after a numerical failure (the last good frame is written).
int ReportParticleRun(const ParticleScenario& scenario, const ParticleSetup& setup,
                      const ParticleRunResult& result, const std::string& scenario_file,
                      OutputDir& out);

}  // namespace moreau::cli
