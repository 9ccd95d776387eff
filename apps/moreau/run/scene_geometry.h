// The fixed scene of a particle or population run as the geometry.vtp that ParaView opens beside
// the trajectory (docs/io.md, "Walls, obstacles and the door").
#pragma once

#include <optional>

#include "moreau/io/geometry.h"
#include "moreau/particles/model.h"
#include "moreau/particles/room.h"
#include "output.h"
#include "run/particles_scenario.h"

namespace moreau::cli {

// Cells of kind "wall" (each half-space wall where its boundary crosses the scene's box: a line
// in 2D, a polygon in 3D), "segment" (each segment obstacle, the room's and the geometry's walls among them),
// "sphere" (each sphere obstacle: a 64-gon in 2D, a 12 × 24 latitude–longitude mesh in 3D) and
// "door" (the room's door line, or each exit of a [geometry]), each with its index in the
// model's list (walls, segments, spheres; 0 for the room's door, the exit's index for an exit). The scene's box holds the domain, the initial box, the obstacles and
// the point of every wall nearest the box's centre, widened by 5 % of its diagonal.
io::SceneGeometry SceneOf(const particles::ParticleModel& model,
                          const std::optional<particles::Room>& room,
                          const ParticleScenario& scenario);

// Writes geometry.vtp into `out` (staged) when the run writes a trajectory (HDF5 or VTU) and the
// model has walls or obstacles; returns whether it did.
bool WriteSceneGeometry(const particles::ParticleModel& model, const ParticleScenario& scenario,
                        OutputDir& out);

}  // namespace moreau::cli
