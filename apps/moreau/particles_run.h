// `moreau run` for particle scenarios at scale ([problem] kind = "particles"), on the engine of
// include/moreau/particles/engine.h: trajectories in HDF5 (+ XDMF) and VTU, a summary, PNG
// snapshots, and for crowds the number of people out against time.
#pragma once

#include <string>

#include "scenario.h"

namespace moreau::cli {

struct ParticleRunFlags {
  std::string out;
  bool fix_overlaps = false;
};

// Reads the rest of the scenario (throws InputError "FILE: KEY: REASON"), runs, writes DIR.
// Returns the exit code: 0, or 3 after a numerical failure (the last good frame is written).
int RunParticleScenario(Scenario& scenario, const ParticleRunFlags& flags);

}  // namespace moreau::cli
