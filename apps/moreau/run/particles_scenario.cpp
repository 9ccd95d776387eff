#include "run/particles_scenario.h"

#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "moreau/common/error.h"
#include "moreau/common/random.h"
#include "moreau/common/steps.h"
#include "run/crowd_geometry.h"
#include "run/fields_scenario.h"
#include "run/force_fields.h"
#include "run/population_scenario.h"

namespace moreau::cli {
namespace {

using particles::Vec3;
using PS = ParticleScenario;

// k numbers from a TOML array node (k: the problem's dimension).
Vec3 VecFromNode(const Scenario& sc, const std::string& key, const toml::node* node, int k) {
  const toml::array* arr = node ? node->as_array() : nullptr;
  if (arr == nullptr || static_cast<int>(arr->size()) != k) {
    sc.Fail(key, fmt::format("expected an array of {} numbers", k));
  }
  Vec3 out{0.0, 0.0, 0.0};
  for (int a = 0; a < k; ++a) {
    const auto v = (*arr)[static_cast<std::size_t>(a)].value<double>();
    if (!v || !std::isfinite(*v)) sc.Fail(key, "entries must be finite numbers");
    out[static_cast<std::size_t>(a)] = *v;
  }
  return out;
}

// A flag whose default depends on fields read before it.
template <class A, class D>
void AddFlag(FieldTable<PS>& t, std::string key, A ref, D fallback, std::string help) {
  t.Custom(
      std::move(key), "boolean",
      [ref, fallback](Scenario& sc, PS& s, const std::string& k) {
        std::invoke(ref, s) = sc.GetBool(k, fallback(s));
      },
      [ref](const PS& s) { return nlohmann::json(std::invoke(ref, s)); }, std::move(help));
}

// The tables of an array of tables ([[walls]]); empty when absent.
std::vector<const toml::table*> Tables(Scenario& sc, const std::string& key) {
  std::vector<const toml::table*> out;
  const toml::node* node = sc.GetNode(key);
  if (node == nullptr) return out;
  const toml::array* arr = node->as_array();
  if (arr == nullptr) sc.Fail(key, "expected an array of tables ([[" + key + "]])");
  for (const toml::node& item : *arr) {
    if (item.as_table() == nullptr) sc.Fail(key, "expected an array of tables");
    out.push_back(item.as_table());
  }
  return out;
}

double NumberFromTable(const Scenario& sc, const std::string& key, const toml::table& t,
                       const char* field) {
  const auto v = t[field].value<double>();
  if (!v || !std::isfinite(*v)) sc.Fail(key + "." + field, "expected a finite number");
  return *v;
}

// [[KEY]]: one entry of `list` per table, made by make(scenario, settings, "KEY[i]", table).
template <class T, class Make>
auto ReadEach(std::vector<T> PS::*list, Make make) {
  return [list, make](Scenario& sc, PS& s, const std::string& key) {
    const auto tables = Tables(sc, key);
    for (std::size_t i = 0; i < tables.size(); ++i) {
      (s.*list).push_back(make(sc, s, fmt::format("{}[{}]", key, i), *tables[i]));
    }
  };
}

particles::Wall MakeWall(const Scenario& sc, const PS& s, const std::string& at,
                         const toml::table& t) {
  sc.CheckTableKeys(at, t, {"normal", "offset"});
  return {VecFromNode(sc, at + ".normal", t.get("normal"), s.dimension),
          NumberFromTable(sc, at, t, "offset")};
}

particles::SphereObstacle MakeSphere(const Scenario& sc, const PS& s, const std::string& at,
                                     const toml::table& t) {
  sc.CheckTableKeys(at, t, {"center", "radius"});
  return {VecFromNode(sc, at + ".center", t.get("center"), s.dimension),
          NumberFromTable(sc, at, t, "radius")};
}

particles::SegmentObstacle MakeSegment(const Scenario& sc, const PS& s, const std::string& at,
                                       const toml::table& t) {
  sc.CheckTableKeys(at, t, {"a", "b"});
  if (s.dimension != 2) sc.Fail(at, "segments need dimension 2");
  const Vec3 a = VecFromNode(sc, at + ".a", t.get("a"), 2);
  const Vec3 b = VecFromNode(sc, at + ".b", t.get("b"), 2);
  return {{a[0], a[1]}, {b[0], b[1]}};
}

nlohmann::json EchoWalls(const PS& s) {
  nlohmann::json j;
  for (const particles::Wall& w : s.walls) {
    j.push_back({{"normal", EchoVec(w.normal, s.dimension)}, {"offset", w.offset}});
  }
  return j;
}

nlohmann::json EchoSpheres(const PS& s) {
  nlohmann::json j;
  for (const particles::SphereObstacle& o : s.spheres) {
    j.push_back({{"center", EchoVec(o.center, s.dimension)}, {"radius", o.radius}});
  }
  return j;
}

nlohmann::json EchoSegments(const PS& s) {
  nlohmann::json j;
  for (const particles::SegmentObstacle& g : s.segments) j.push_back({{"a", g.a}, {"b", g.b}});
  return j;
}

// [room] width, height, door_width, all three required when the table is there, and the
// optional door_length (a passage; 0: none, not echoed).
void ReadRoom(Scenario& sc, PS& s, const std::string& key) {
  if (!sc.Has(key)) {
    (void)sc.GetNode(key);
    return;
  }
  s.room = particles::Room{sc.RequireDouble(key + ".width"), sc.RequireDouble(key + ".height"),
                           sc.RequireDouble(key + ".door_width"),
                           sc.GetDouble(key + ".door_length", 0.0)};
}

nlohmann::json EchoRoom(const PS& s) {
  if (!s.room) return nullptr;
  nlohmann::json j = {
      {"width", s.room->width}, {"height", s.room->height}, {"door_width", s.room->door_width}};
  if (s.room->door_length > 0.0) j["door_length"] = s.room->door_length;
  return j;
}

// [initial] positions = [[x, y], …]: problem.count rows of k numbers.
void ReadParticlePositions(Scenario& sc, PS& s, const std::string& key) {
  const toml::node* node = sc.GetNode(key);
  if (node == nullptr) return;
  const toml::array* rows = node->as_array();
  if (rows == nullptr || static_cast<std::int64_t>(rows->size()) != s.count) {
    sc.Fail(key, fmt::format("expected an array of {} positions (problem.count)", s.count));
  }
  const auto k = static_cast<std::size_t>(s.dimension);
  std::vector<double> x(k * rows->size());
  for (std::size_t i = 0; i < rows->size(); ++i) {
    const Vec3 p = VecFromNode(sc, fmt::format("{}[{}]", key, i), &(*rows)[i], s.dimension);
    std::copy(p.begin(), p.begin() + s.dimension, x.begin() + static_cast<std::ptrdiff_t>(k * i));
  }
  s.positions = std::move(x);
}

void ReadPeriodic(Scenario& sc, PS& s, const std::string& key) {
  const toml::node* node = sc.GetNode(key);
  if (node == nullptr) return;
  const toml::array* arr = node->as_array();
  if (arr == nullptr || static_cast<int>(arr->size()) != s.dimension) {
    sc.Fail(key, fmt::format("expected {} booleans", s.dimension));
  }
  for (std::size_t a = 0; a < arr->size(); ++a) {
    const auto b = (*arr)[a].value_exact<bool>();
    if (!b) sc.Fail(key, "entries must be true or false");
    s.periodic[a] = *b;
  }
}

void ReadDimension(Scenario& sc, PS& s, const std::string& key) {
  const std::int64_t d = sc.GetInt(key, s.dimension);
  if (d != 2 && d != 3) sc.Fail(key, fmt::format("must be 2 or 3 (got {})", d));
  s.dimension = static_cast<int>(d);
}

void AddProblemFields(FieldTable<PS>& t) {
  t.Text("problem.kind", &PS::kind, "particles (sliding, disks: docs/paper.md)")
      .Custom(
          "problem.dimension", "2 or 3", ReadDimension,
          [](const PS& s) { return nlohmann::json(s.dimension); }, "dimension k")
      .Integer("problem.count", &PS::count, Range::AtLeast(1), "number of particles N")
      .Required()
      .OptionalNumber("problem.radius", &PS::radius, Range::Positive(), "radius of every particle")
      .OptionalNumber("problem.radius_min", &PS::radius_min, Range::Positive(),
                      "polydisperse: radii uniform in [radius_min, radius_max] (seeded)")
      .OptionalNumber("problem.radius_max", &PS::radius_max, Range::Any(), "polydisperse")
      .Number("problem.mobility", &PS::mobility, Range::Positive(), "mobility of every particle")
      .Number("problem.T", &PS::T, Range::Positive(), "final time")
      .Required()
      .Integer("problem.seed", &PS::seed, Range::Any(), "radii, random start and noise")
      .Flag("problem.fix_overlaps", &PS::fix_overlaps, "project an overlapping start (sweeps)");
  AddVec(t, "domain.lo", &PS::domain_lo, "box of the random start; periodic axes' domain");
  AddVec(t, "domain.hi", &PS::domain_hi, "the other corner");
  t.Custom(
       "domain.periodic", "k booleans", ReadPeriodic,
       [](const PS& s) {
         return nlohmann::json(
             std::vector<bool>(s.periodic.begin(), s.periodic.begin() + s.dimension));
       },
       "periodic axes")
      .Flag("domain.box_walls", &PS::box_walls, "walls on the faces of the non-periodic axes")
      .Custom("initial.positions", "array of k numbers", ReadParticlePositions, {},
              "explicit start (default: random sequential addition)");
  AddVec(t, "initial.lo", &PS::initial_lo, "box of the random start (default: the domain)");
  AddVec(t, "initial.hi", &PS::initial_hi, "the other corner");
  t.Custom("walls", "[[walls]] normal, offset", ReadEach(&PS::walls, MakeWall), EchoWalls,
           "half-spaces ⟨n, X⟩ ≥ offset + r")
      .Custom("spheres", "[[spheres]] center, radius", ReadEach(&PS::spheres, MakeSphere),
              EchoSpheres, "obstacles")
      .Custom("segments", "[[segments]] a, b", ReadEach(&PS::segments, MakeSegment), EchoSegments,
              "segment obstacles (2D)")
      .Custom("room", "width, height, door_width, door_length", ReadRoom, EchoRoom,
              "a walled room with a door (a passage of door_length); everybody walks to it");
}

void AddOutputFields(FieldTable<PS>& t) {
  t.Integer(
      "output.stride", [](auto& s) -> auto& { return s.output.stride; }, Range::NonNegative(),
      "steps between trajectory frames (0: about 100 frames)");
  AddFlag(
      t, "output.hdf5", [](auto& s) -> auto& { return s.output.hdf5; },
      [](const PS&) { return true; }, "trajectory.h5 + trajectory.xdmf");
  t.Choice(
       "output.precision", [](auto& s) -> auto& { return s.output.trajectory.precision; },
       io::ParseTrajectoryPrecision, io::TrajectoryPrecisionName, "double, single",
       "positions in trajectory.h5 as float64 or float32")
      .Integer(
          "output.compression", [](auto& s) -> auto& { return s.output.trajectory.compression; },
          Range::Closed(0, 9), "deflate level of trajectory.h5 (0: none)")
      .Check("output.compression", [](const PS& s) { s.output.trajectory.Validate(); });
  AddFlag(
      t, "output.vtu", [](auto& s) -> auto& { return s.output.vtu; },
      [](const PS& s) { return s.count <= 100000; }, "vtu/frame.pvd");
  t.Flag(
      "output.trajectory_txt", [](auto& s) -> auto& { return s.output.trajectory_txt; },
      "trajectory.txt: id frame x y z per person and frame (PedPy, JuPedSim, PeTrack)");
  AddFlag(
      t, "output.snapshots", [](auto& s) -> auto& { return s.output.snapshots; },
      [](const PS& s) { return s.count <= 200000 && s.dimension == 2; }, "snapshots.png (2D only)");
  t.Custom(
      "output.snapshot_times", "numbers",
      [](Scenario& sc, PS& s, const std::string& k) {
        s.output.snapshot_times = sc.GetDoubleArray(k, s.output.snapshot_times);
      },
      [](const PS& s) { return nlohmann::json(s.output.snapshot_times); },
      "at most four snapshot times (default: the first and the last frame)");
}

void CheckRadii(FieldTable<PS>& t) {
  t.Check("problem.radius",
          [](const PS& s) {
            if (s.is_population()) {
              if (s.radius || s.radius_min || s.radius_max) {
                throw InputError("the agents' radii come from [[types]]; give no problem.radius");
              }
              return;
            }
            if (!s.radius && !s.radius_min && !s.radius_max) {
              throw InputError("required key is missing (or radius_min and radius_max)");
            }
            if (s.radius && (s.radius_min || s.radius_max)) {
              throw InputError("give radius or radius_min and radius_max, not both");
            }
          })
      .Check("problem.radius_min",
             [](const PS& s) {
               if (s.radius_max && !s.radius_min) throw InputError("required key is missing");
             })
      .Check("problem.radius_max", [](const PS& s) {
        if (s.radius_min && !s.radius_max) throw InputError("required key is missing");
        if (s.radius_min && s.radius_max && !(*s.radius_max >= *s.radius_min)) {
          throw InputError("must be ≥ problem.radius_min");
        }
      });
}

// The collision-free speed model's and the fixed direction's conditions on other keys.
void AddPedestrianModelChecks(FieldTable<PS>& t) {
  t.Check("forces.pedestrian_model", [](const PS& s) {
     const ParticleForceSettings& f = s.forces;
     if (f.pedestrian_model != "collision_free") return;
     if (!f.propulsion_speed && !s.room && !s.geometry) {
       throw InputError("collision_free needs forces.propulsion_speed, a [room] or a [geometry]");
     }
     if (f.density_radius) {
       throw InputError("collision_free does not go with forces.density_radius");
     }
     if (s.dimension != 2) throw InputError("collision_free needs dimension 2");
   }).Check("forces.direction", [](const PS& s) {
    if (s.forces.direction && (!s.forces.propulsion_speed || s.room || s.forces.target)) {
      throw InputError("needs forces.propulsion_speed (and no [room], no forces.target)");
    }
  });
}

// Checks over several fields; the memory check comes first, before anything of size N.
void AddChecks(FieldTable<PS>& t) {
  t.Check("problem.count", [](const PS& s) {
    particles::CheckParticleMemory(s.dimension, s.count, s.solver.memory_limit_bytes);
    if (s.count > std::numeric_limits<int>::max()) throw InputError("too many particles");
  });
  CheckRadii(t);
  AddPedestrianModelChecks(t);
  t.Check("domain.hi",
          [](const PS& s) {
            for (std::size_t a = 0; a < static_cast<std::size_t>(s.dimension); ++a) {
              if (!(s.domain_hi[a] > s.domain_lo[a])) {
                throw InputError(fmt::format("must exceed domain.lo on axis {}", a));
              }
            }
          })
      .Check("initial.lo",
             [](const PS& s) {
               if (s.positions && (s.initial_lo || s.initial_hi)) {
                 throw InputError("initial.lo and initial.hi do not go with initial.positions");
               }
             })
      .Check("room",
             [](const PS& s) {
               if (!s.room) return;
               if (s.dimension != 2) throw InputError("a room needs dimension 2");
               s.room->Validate();
             })
      .Check("forces.target",
             [](const PS& s) {
               if ((s.forces.target || s.forces.target_end) &&
                   (!s.forces.propulsion_speed || s.room)) {
                 throw InputError("needs forces.propulsion_speed (and no [room])");
               }
             })
      .Check("forces.density_radius",
             [](const PS& s) {
               const ParticleForceSettings& f = s.forces;
               if ((f.density_radius || f.propulsion_speed_sd != 0.0) && !f.propulsion_speed &&
                   !s.room && !s.geometry) {
                 throw InputError("needs forces.propulsion_speed, a [room] or a [geometry]");
               }
               if ((f.density_gamma || f.density_max) && !f.density_radius) {
                 throw InputError("required by forces.density_gamma and forces.density_max");
               }
               if (f.density_radius && s.dimension != 2) throw InputError("needs dimension 2");
             })
      .Check("forces.attraction_range",
             [](const PS& s) {
               if (s.forces.attraction_range && !s.forces.attraction_stiffness &&
                   s.population.rules.adhesion.empty()) {
                 throw InputError("needs forces.attraction_stiffness or population.adhesion");
               }
             })
      .Check("forces", [](const PS& s) { (void)s.MakeForces(); })
      .Check("solver.method",
             [](const PS& s) {
               if (s.method != "pbd") throw InputError("the particle engine runs pbd");
             })
      .Check("solver.h", [](const PS& s) { (void)StepCount(s.T, s.solver.h); })
      .Check("output.trajectory_txt",
             [](const PS& s) {
               if (s.output.trajectory_txt && s.is_population()) {
                 throw InputError("not written for agent-based runs ([[types]])");
               }
             })
      .Check("output.snapshot_times", [](const PS& s) {
        if (s.output.snapshot_times.size() > 4) throw InputError("at most four times");
        for (double time : s.output.snapshot_times) {
          if (time < 0.0 || time > s.T) {
            throw InputError(fmt::format("{} is outside [0, T]", time));
          }
        }
      });
}

FieldTable<PS> MakeParticleFields() {
  FieldTable<PS> t;
  AddProblemFields(t);
  AddGeometryFields(t);
  AddForceFields(t);
  t.Mount("solver", &PS::solver, particles::EngineOptions::Fields(), {{"seed", ""}})
      .Require("solver.h")
      .CapThreads("solver.threads")
      .Text("solver.method", &PS::method, "pbd (the only method of the particle engine)");
  AddPopulationFields(t);
  AddFieldCouplingFields(t);
  AddOutputFields(t);
  AddChecks(t);
  AddParticleLimitChecks(t);
  return t;
}

}  // namespace

const FieldTable<PS>& ParticleFields() {
  static const FieldTable<PS> table = MakeParticleFields();
  return table;
}

particles::ParticleModel ParticleScenario::MakeModel() const {
  particles::ParticleModel model;
  model.dimension = dimension;
  const auto n = static_cast<std::size_t>(count);
  if (is_population()) {
    const std::vector<int> types = InitialTypes();
    model.radius.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      model.radius[i] = population.rules.types[static_cast<std::size_t>(types[i])].radius;
    }
  } else if (radius) {
    model.radius.assign(n, *radius);
  } else {
    SplitMix64 rng(static_cast<std::uint64_t>(seed) ^ 0x5DEECE66DULL);
    model.radius.resize(n);
    for (double& r : model.radius) r = *radius_min + (*radius_max - *radius_min) * rng.Uniform01();
  }
  if (mobility != 1.0) model.mobility.assign(n, mobility);
  model.domain_lo = domain_lo;
  model.domain_hi = domain_hi;
  model.periodic = periodic;
  if (box_walls) model.AddBoxWalls(domain_lo, domain_hi);
  model.walls.insert(model.walls.end(), walls.begin(), walls.end());
  model.spheres.insert(model.spheres.end(), spheres.begin(), spheres.end());
  model.segments.insert(model.segments.end(), segments.begin(), segments.end());
  if (room) particles::AddRoom(*room, &model);
  if (geometry) {
    for (const particles::SegmentObstacle& w : geometry->Walls()) model.segments.push_back(w);
  }
  return model;
}

particles::EngineOptions ParticleScenario::MakeEngineOptions() const {
  particles::EngineOptions options = solver;
  options.seed = static_cast<std::uint64_t>(seed);
  return options;
}

ParticleScenario ReadParticleScenario(Scenario& scenario, bool fix_overlaps_flag) {
  ParticleScenario out;
  ParticleFields().Read(scenario, out);
  out.fix_overlaps = out.fix_overlaps || fix_overlaps_flag;
  return out;
}

nlohmann::json EchoParticleScenario(const ParticleScenario& scenario) {
  return ParticleFields().Echo(scenario);
}

}  // namespace moreau::cli
