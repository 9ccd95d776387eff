// `moreau run` for an agent-based model (a particle scenario with [[types]], docs/abm.md): the
// population on its initial state, the run with the observables recorded every
// population.record_every rule steps and the trajectory written as VTU frames (the agent count
// changes), and what the run writes besides: population.csv, agents.csv, summary.json.
#pragma once

#include <cstdint>
#include <string>

#include "moreau/particles/population.h"
#include "output.h"
#include "run/particles_scenario.h"
#include "scenario.h"

namespace moreau::cli {

// The population on its initial state (random sequential addition unless given). Throws
// InputError "FILE: KEY: REASON" before anything is written.
particles::Population SetUpPopulationRun(const ParticleScenario& scenario, const Scenario& file);

// Runs over [0, T], writes DIR (population.csv, agents.csv, summary.json, vtu/frame.pvd) and
// prints the brief report. Returns 0, or 3 after a numerical failure (the last good state kept).
int RunPopulation(const ParticleScenario& scenario, particles::Population& population,
                  const std::string& scenario_file, OutputDir& out);

}  // namespace moreau::cli
