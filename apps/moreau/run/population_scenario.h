// The agent-based keys of a particle scenario (docs/abm.md "Scenario keys"): [[types]] (one table
// per agent type), [population] (the rules) and initial.types, read through the particle
// scenario's field table.
#pragma once

#include "field_table.h"
#include "run/particles_scenario.h"

namespace moreau::cli {

// Adds the fields and checks of [[types]], [population] and initial.types to `table`.
void AddPopulationFields(FieldTable<ParticleScenario>& table);

}  // namespace moreau::cli
