// [geometry] of the particle scenario (`moreau run`, problem.kind = "particles"): a crowd's
// walkable polygon, obstacles and exits from a file (geometry.file, the format of
// moreau/particles/geometry.h) or inline (geometry.walkable, geometry.obstacles,
// geometry.exits), and the routing grid (geometry.spacing, geometry.clearance) of the distance
// field that gives everybody's desired direction (docs/crowds.md "Geometry and routing").
#pragma once

#include "field_table.h"
#include "run/particles_scenario.h"

namespace moreau::cli {

// geometry.*: the keys, read into ParticleScenario::geometry and ::route, and the checks against
// the other keys (dimension 2; not with [room], forces.target or forces.direction; the start
// inside the walkable area).
void AddGeometryFields(FieldTable<ParticleScenario>& table);

}  // namespace moreau::cli
