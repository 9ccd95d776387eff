// `moreau run` for an agent-based model (a particle scenario with [[types]], docs/abm.md): the
// population on its initial state, the run with the observables recorded every
// population.record_every rule steps and the trajectory written as HDF5 and VTU frames (the
// agent count changes), and what the run writes besides: population.csv, agents.csv,
// lineage.csv, geometry.vtp (walls and obstacles), summary.json.
#pragma once

#include <cstdint>
#include <string>

#include <nlohmann/json.hpp>

#include "moreau/particles/population.h"
#include "output.h"
#include "run/particles_checkpoint.h"
#include "run/particles_scenario.h"
#include "scenario.h"

namespace moreau::cli {

// The population on its initial state (random sequential addition unless given). Throws
// InputError "FILE: KEY: REASON" before anything is written.
particles::Population SetUpPopulationRun(const ParticleScenario& scenario, const Scenario& file);

struct PopulationRunResult {
  particles::PopulationSummary summary;
  std::string series_csv;   // population.csv
  std::string lineage_csv;  // lineage.csv
  bool hdf5 = false;        // trajectory.h5 + .xdmf written
  bool vtu = false;         // vtu/frame.pvd written
  bool geometry = false;    // geometry.vtp written
};

// Runs over [0, T] (with a progress bar on a terminal), writing the trajectory frames into
// `out` (staged) and recording the observables every population.record_every rule steps and at
// the end. After a numerical failure the population keeps the last good state. With
// checkpoints.every > 0 a checkpoint at the first rule step at or past every multiple of it (the
// frames so far are kept in memory for it); with checkpoints.resumed the population is on the
// checkpoint's step already, and the records and frames it holds are taken first.
PopulationRunResult RunPopulation(const ParticleScenario& scenario,
                                  particles::Population& population, OutputDir& out,
                                  const CheckpointPlan& checkpoints = {});

// The population's summary with the run's context, the final positions' hash ("positions_hash")
// and the scenario's settings: summary.json.
nlohmann::json PopulationRunJson(const ParticleScenario& scenario,
                                 const particles::Population& population,
                                 const PopulationRunResult& result,
                                 const std::string& scenario_file);

// Writes population.csv, agents.csv, lineage.csv and SUMMARY as summary.json into OUT and commits
// it. Returns the brief report `moreau run` prints.
std::string ReportPopulationRun(const particles::Population& population,
                                const PopulationRunResult& result, const nlohmann::json& summary,
                                OutputDir& out);

}  // namespace moreau::cli
