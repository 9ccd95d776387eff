// The scenario of `moreau run` for particles at scale (problem.kind = "particles"): [problem],
// [domain], [initial], [[walls]], [[spheres]], [[segments]], [room], [forces], [solver],
// [output] (docs/particles.md "Scenario keys"), read through one field table.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "field_table.h"
#include "moreau/io/trajectory.h"
#include "moreau/particles/engine.h"
#include "moreau/particles/population.h"
#include "moreau/particles/room.h"
#include "moreau/particles/routing.h"
#include "scenario.h"

namespace moreau::cli {

// [forces] as written; MakeForces() turns them into the engine's drift.
struct ParticleForceSettings {
  std::optional<double> trap_gamma;  // a harmonic trap when set
  particles::Vec3 trap_center{0.0, 0.0, 0.0};
  particles::Vec3 constant{0.0, 0.0, 0.0};     // a constant force f
  std::optional<double> propulsion_speed;      // self-propulsion when set (or with a room)
  double propulsion_speed_sd = 0.0;            // σ_v of the desired speeds (a crowd)
  std::optional<double> density_radius;        // R: Weidmann's speed–density law when set
  std::optional<double> density_gamma;         // γ, default 1.913 /m²
  std::optional<double> density_max;           // ρ_max, default 5.4 /m²
  std::optional<particles::Vec3> target;       // default: the origin
  std::optional<particles::Vec3> target_end;   // the target is a segment when set
  std::optional<particles::Vec3> direction;    // one desired direction everywhere when set
  // "propulsion" (v0,i, optionally × Weidmann's φ) or "collision_free" (Tordeux et al. 2016).
  std::string pedestrian_model = "propulsion";
  particles::CollisionFreeSpeed collision_free;  // forces.collision_free.*
  std::optional<double> attraction_stiffness;  // pair attraction when set
  std::optional<double> attraction_range;      // default 0
  double diffusion = 0.0;
};

// [output].
struct ParticleOutputSettings {
  std::int64_t stride = 0;  // a trajectory frame every stride steps (and the last); 0: ~100 frames
  bool hdf5 = true;
  bool vtu = true;                     // default: count ≤ 100000
  bool trajectory_txt = false;         // trajectory.txt (PedPy's text format, docs/io.md)
  bool snapshots = true;               // snapshots.png, 2D only; default: count ≤ 200000
  std::vector<double> snapshot_times;  // at most four; empty: the first and the last frame
  // output.precision and output.compression: how trajectory.h5 stores its data.
  io::Hdf5TrajectoryOptions trajectory;
};

// [[types]], [population] and initial.types: an agent-based model (docs/abm.md) when types are
// given.
struct PopulationSettings {
  particles::PopulationRules rules;        // types and rules
  std::vector<std::string> initial_types;  // one name per agent, or one for all; empty: the first
  std::int64_t record_every = 1;           // rule steps between rows of population.csv
  std::optional<double> exit_offset;       // removal past ⟨exit_normal, X⟩ > exit_offset
  particles::Vec3 exit_normal{1.0, 0.0, 0.0};
};

// [fields] and the types' tables per substrate: diffusing fields the agents are coupled to
// (docs/fields.md "Agents and fields"); none when no substrate is given.
struct FieldSettings {
  std::optional<double> spacing;              // h of the grid over the domain box
  std::vector<fields::Substrate> substrates;  // [fields.<name>], in the order of their names
  particles::FieldCouplingOptions coupling;   // interpolation, substeps, the types' responses
  bool enabled() const { return !substrates.empty(); }
};

struct ParticleScenario {
  std::string kind = "particles";
  int dimension = 2;             // 2 or 3
  std::int64_t count = 0;        // N
  std::optional<double> radius;  // one radius, or uniform in [radius_min, radius_max]
  std::optional<double> radius_min;
  std::optional<double> radius_max;
  double mobility = 1.0;
  double T = 0.0;
  std::int64_t seed = 1;      // radii, random start and noise
  bool fix_overlaps = false;  // project an overlapping start to a feasible one
  particles::Vec3 domain_lo{0.0, 0.0, 0.0};
  particles::Vec3 domain_hi{1.0, 1.0, 1.0};
  std::array<bool, 3> periodic{false, false, false};
  bool box_walls = false;                        // walls on the box faces of the non-periodic axes
  std::optional<std::vector<double>> positions;  // [initial] positions, k·N, id order
  std::optional<particles::Vec3> initial_lo;     // random start box (default: the domain)
  std::optional<particles::Vec3> initial_hi;
  std::vector<particles::Wall> walls;
  std::vector<particles::SphereObstacle> spheres;
  std::vector<particles::SegmentObstacle> segments;
  std::optional<particles::Room> room;
  // [geometry] (crowd_geometry.h): the walkable area, its obstacles and exits, and the distance
  // field to the exits built from them with `routing`.
  std::string geometry_file;  // geometry.file as written; empty: inline or none
  std::optional<particles::CrowdGeometry> geometry;
  particles::RoutingOptions routing;
  std::shared_ptr<const particles::DistanceField> route;
  ParticleForceSettings forces;
  particles::EngineOptions solver;  // seed comes from problem.seed
  std::string method = "pbd";       // the particle engine runs pbd only
  ParticleOutputSettings output;
  PopulationSettings population;
  FieldSettings fields;

  bool is_population() const { return !population.rules.types.empty(); }
  // The rules with the exit plane and, unless population.seed is given, the problem's seed.
  particles::PopulationRules MakeRules() const;
  // The initial agents' type indices (InputError for an unknown name).
  std::vector<int> InitialTypes() const;

  int n() const { return static_cast<int>(count); }
  // The model's radii, mobilities, domain, walls and obstacles (room and geometry walls
  // included).
  // Throws InputError from AddRoom.
  particles::ParticleModel MakeModel() const;
  // The drift; with a room everybody walks to the door, with a geometry to the nearest exit. Throws InputError from Validate.
  particles::Forces MakeForces() const;
  // The engine options with the seed of [problem].
  particles::EngineOptions MakeEngineOptions() const;
  // The fields over the domain box (periodic faces on the periodic axes), on `threads` threads.
  // Throws InputError naming the scenario key (fields.spacing, fields.<substrate>.<key>).
  fields::FieldSet MakeFields(int threads) const;
  fields::Grid FieldGrid() const;  // the grid of MakeFields
};

// The checks of sizes and geometry (particles_limits.cpp): frames and in-memory series against
// the stated maxima and the available memory, the start region inside the room.
void AddParticleLimitChecks(FieldTable<ParticleScenario>& table);

// Reads and validates every key (throws InputError "FILE: KEY: REASON"); --fix-overlaps is
// `fix_overlaps_flag`. Call scenario.CheckAllKeysUsed() after.
// Every key of a particle (and agent-based) scenario.
const FieldTable<ParticleScenario>& ParticleFields();

ParticleScenario ReadParticleScenario(Scenario& scenario, bool fix_overlaps_flag);

// The settings used, keyed like the scenario file: {"problem": {…}, "domain": {…}, …}.
nlohmann::json EchoParticleScenario(const ParticleScenario& scenario);

}  // namespace moreau::cli
