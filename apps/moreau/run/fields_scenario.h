// The diffusing fields of an agent-based scenario (docs/fields.md "Agents and fields"): [fields]
// (spacing, interpolation, substeps, a table per substrate) and the types' responses
// (types.<type>.<substrate>.<key>, a table inside a [[types]] entry), read through the particle
// scenario's field table.
#pragma once

#include <string>

#include "field_table.h"
#include "run/particles_scenario.h"
#include "scenario.h"

namespace moreau::cli {

// Adds [fields] and the rows of the responses' keys (read by the [[types]] reader) to `table`,
// and the check that builds the fields and validates the coupling against the types.
void AddFieldCouplingFields(FieldTable<ParticleScenario>& table);

// One table `name` of the [[types]] entry of type `type`: the type's response to that substrate,
// appended to out->coupling.responses. Fails "FILE: types.<type>.<name>.<key>: REASON".
void ReadSubstrateResponse(const Scenario& scenario, const std::string& type,
                           const std::string& name, const toml::table& table, FieldSettings* out);

}  // namespace moreau::cli
