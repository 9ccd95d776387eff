// moreau.particles: the particle model, forces and the engine at scale.
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include "bindings.h"
#include "moreau/common/error.h"
#include "moreau/common/steps.h"
#include "moreau/particles/engine.h"
#include "moreau/particles/population.h"
#include "moreau/particles/room.h"
#include "moreau/particles/routing.h"

namespace moreau::python {

// Engine.run's observer: any Python object (None: no observer), typed in the signature (and so
// in the stubs) as the callable it must be.
struct EngineObserverArgument {
  py::object callable;
};

}  // namespace moreau::python

namespace pybind11::detail {
template <>
struct type_caster<moreau::python::EngineObserverArgument> {
  PYBIND11_TYPE_CASTER(moreau::python::EngineObserverArgument,
                       const_name("Optional[Callable[[Engine], Optional[bool]]]"));
  bool load(handle source, bool) {
    value.callable = reinterpret_borrow<object>(source);
    return true;
  }
};
}  // namespace pybind11::detail

namespace moreau::python {
namespace {

using namespace moreau::particles;
using Positions = py::array_t<double, py::array::c_style | py::array::forcecast>;

// Positions of n particles in k dimensions, given as (n, k) or flat k·n.
std::span<const double> PositionSpan(const Positions& x) {
  return {x.data(), static_cast<std::size_t>(x.size())};
}

// (n, k) array of a copy of values.
py::array_t<double> Matrix(const std::vector<double>& values, int k) {
  py::array_t<double> out(
      {static_cast<py::ssize_t>(values.size()) / k, static_cast<py::ssize_t>(k)});
  std::copy(values.begin(), values.end(), out.mutable_data());
  return out;
}

// A read-only numpy view of C++ memory owned by `owner` (kept alive by the array).
template <typename T>
py::array ReadOnlyView(const T* data, std::vector<py::ssize_t> shape, py::handle owner) {
  py::array view(py::dtype::of<T>(), std::move(shape), {}, data, owner);
  view.attr("setflags")(py::arg("write") = false);
  return view;
}

void BindModel(py::module_& m) {
  py::class_<Wall> wall(m, "Wall", "Half-space ⟨normal, X⟩ ≥ offset + r_i for particle centres.");
  wall.def(py::init(&FromKwargs<Wall>))
      .def_readwrite("normal", &Wall::normal)
      .def_readwrite("offset", &Wall::offset);
  py::class_<SphereObstacle> sphere(m, "SphereObstacle", "‖X_i − center‖ ≥ radius + r_i.");
  sphere.def(py::init(&FromKwargs<SphereObstacle>))
      .def_readwrite("center", &SphereObstacle::center)
      .def_readwrite("radius", &SphereObstacle::radius);
  py::class_<SegmentObstacle> segment(m, "SegmentObstacle", "dist(X_i, [a, b]) ≥ r_i (2D).");
  segment.def(py::init(&FromKwargs<SegmentObstacle>))
      .def_readwrite("a", &SegmentObstacle::a)
      .def_readwrite("b", &SegmentObstacle::b);

  py::class_<ParticleModel> particle_model(
      m, "ParticleModel",
      "N particles in R^k: radii, mobilities, walls, obstacles, "
      "periodic axes. Keyword arguments name the fields; validated.");
  particle_model.def(py::init(&FromKwargs<ParticleModel>))
      .def_readwrite("dimension", &ParticleModel::dimension)
      .def_readwrite("radius", &ParticleModel::radius)
      .def_readwrite("mobility", &ParticleModel::mobility)
      .def_readwrite("adhesion_class", &ParticleModel::adhesion_class)
      .def_readwrite("walls", &ParticleModel::walls)
      .def_readwrite("spheres", &ParticleModel::spheres)
      .def_readwrite("segments", &ParticleModel::segments)
      .def_readwrite("periodic", &ParticleModel::periodic)
      .def_readwrite("domain_lo", &ParticleModel::domain_lo)
      .def_readwrite("domain_hi", &ParticleModel::domain_hi)
      .def_property_readonly("count", &ParticleModel::count)
      .def("add_box_walls", &ParticleModel::AddBoxWalls, py::arg("lo"), py::arg("hi"))
      .def("validate", &ParticleModel::Validate);

  m.def(
      "check_initial_state",
      [](const ParticleModel& model, const Positions& x, double tol) {
        CheckInitialState(model, PositionSpan(x), tol);
      },
      py::arg("model"), py::arg("positions"), py::arg("tol") = 1e-9);
  m.def(
      "random_sequential_addition",
      [](const ParticleModel& model, const Vec3& lo, const Vec3& hi, std::uint64_t seed,
         std::int64_t max_attempts) {
        std::vector<double> x;
        {
          const py::gil_scoped_release release;
          x = RandomSequentialAddition(model, lo, hi, seed, max_attempts);
        }
        return Matrix(x, model.dimension);
      },
      py::arg("model"), py::arg("lo"), py::arg("hi"), py::arg("seed"),
      py::arg("max_attempts") = 1000000, "A random non-overlapping (N, k) state.");
  m.def(
      "fix_overlaps",
      [](const ParticleModel& model, const Positions& x, double tolerance, int max_sweeps) {
        std::vector<double> y(x.data(), x.data() + x.size());
        FixOverlapsOptions options;
        options.tolerance = tolerance;
        options.max_sweeps = max_sweeps;
        int sweeps = 0;
        {
          const py::gil_scoped_release release;
          sweeps = FixOverlaps(model, y, options);
        }
        return py::make_tuple(Matrix(y, model.dimension), sweeps);
      },
      py::arg("model"), py::arg("positions"), py::arg("tolerance") = 1e-10,
      py::arg("max_sweeps") = 100000, "(feasible positions, sweeps): a copy, projected.");
}

void BindRoomAndForces(py::module_& m) {
  py::class_<HarmonicTrap>(m, "HarmonicTrap", "F = −gamma (X − center).")
      .def(py::init(&FromKwargs<HarmonicTrap>))
      .def_readwrite("gamma", &HarmonicTrap::gamma)
      .def_readwrite("center", &HarmonicTrap::center);
  py::class_<SelfPropulsion>(m, "SelfPropulsion", "Walking at speed toward a point or segment.")
      .def(py::init(&FromKwargs<SelfPropulsion>))
      .def_readwrite("speed", &SelfPropulsion::speed)
      .def_readwrite("target", &SelfPropulsion::target)
      .def_readwrite("target_end", &SelfPropulsion::target_end)
      .def_readwrite("exit_direction", &SelfPropulsion::exit_direction)
      .def_readwrite("direction", &SelfPropulsion::direction)
      .def_property(
          "route",
          [](const SelfPropulsion& p) { return std::const_pointer_cast<DistanceField>(p.route); },
          [](SelfPropulsion& p, std::shared_ptr<DistanceField> route) {
            p.route = std::move(route);
          },
          "A DistanceField: the desired direction is its −∇d toward the nearest exit (2D).");
  py::class_<PairAttraction>(m, "PairAttraction", "Short-range attraction between surfaces.")
      .def(py::init(&FromKwargs<PairAttraction>))
      .def_readwrite("stiffness", &PairAttraction::stiffness)
      .def_readwrite("range", &PairAttraction::range)
      .def_readwrite("class_stiffness", &PairAttraction::class_stiffness,
                     "C × C stiffnesses between adhesion classes, row-major (empty: stiffness)");
  py::class_<Forces>(m, "Forces", "The engine's drift and noise (keys of [forces]).")
      .def(py::init(&FromKwargs<Forces>))
      .def_readwrite("trap", &Forces::trap)
      .def_readwrite("constant_force", &Forces::constant_force)
      .def_readwrite("propulsion", &Forces::propulsion)
      .def_readwrite("walking", &Forces::walking)
      .def_readwrite("attraction", &Forces::attraction)
      .def_readwrite("diffusion", &Forces::diffusion)
      .def("validate", &Forces::Validate);
  py::class_<Room>(m, "Room", "A room [0, width] × [0, height] with a door in the right wall.")
      .def(py::init(&FromKwargs<Room>))
      .def_readwrite("width", &Room::width)
      .def_readwrite("height", &Room::height)
      .def_readwrite("door_width", &Room::door_width)
      .def("walls", &Room::Walls)
      .def("walk_to_the_door", &Room::WalkToTheDoor, py::arg("speed"), py::arg("clearance") = 0.0);
  m.def(
      "add_room", [](const Room& room, ParticleModel& model) { AddRoom(room, &model); },
      py::arg("room"), py::arg("model"), "Appends the room's walls to model.segments.");
  py::class_<EvacuationCount>(m, "EvacuationCount")
      .def(py::init<const Room&, int>(), py::arg("room"), py::arg("count"))
      .def(py::init<const CrowdGeometry&, int>(), py::arg("geometry"), py::arg("count"))
      .def(
          "update",
          [](EvacuationCount& c, const Positions& x) { return c.Update(PositionSpan(x)); },
          py::arg("positions"), "People out so far, from (N, 2) positions in id order.")
      .def(
          "update_stored",
          [](EvacuationCount& c,
             const py::array_t<int, py::array::c_style | py::array::forcecast>& ids,
             const Positions& x) {
            return c.Update(std::span<const int>(ids.data(), static_cast<std::size_t>(ids.size())),
                            PositionSpan(x));
          },
          py::arg("ids"), py::arg("positions"),
          "The same from Engine.stored_ids and Engine.stored_positions (views, no copy).")
      .def_property_readonly("out", &EvacuationCount::out)
      .def_property_readonly("out_per_exit", &EvacuationCount::OutPerExit,
                             "People out through each exit (one entry for a room).");

  m.def(
      "gaussian_noise",
      [](std::uint64_t seed, std::int64_t id, std::int64_t step, int k) {
        if (k != 2 && k != 3) throw InputError("k must be 2 or 3 (got " + std::to_string(k) + ")");
        std::vector<double> xi(static_cast<std::size_t>(k));
        GaussianNoise(seed, id, step, k, xi.data());
        return xi;
      },
      py::arg("seed"), py::arg("id"), py::arg("step"), py::arg("k"));
}

void BindEngineOptions(py::module_& m) {
  BindOptionsClass<EngineOptions>(m, "EngineOptions", "Keys of [solver] for the particle engine.");
  BindOptionsClass<AgentType>(m, "AgentType", "One agent type: the keys of a [[types]] table.");
  BindOptionsClass<PopulationRules>(m, "PopulationRules",
                                    "The population's rules: keys of [population]; types by name.")
      .def_readwrite("types", &PopulationRules::types)
      .def_readwrite("variables", &PopulationRules::variables)
      .def_readwrite("adhesion", &PopulationRules::adhesion,
                     "{(type a, type b): k_ab}: the attraction's stiffness per pair of types");
  BindSummary<EngineSummary>(m, "EngineSummary",
                             "How a run ended: termination, message, counters, *_seconds.")
      .def("brief_report", &EngineSummary::BriefReport);
}

// Raises moreau.NumericalError for a failed step or run, with the last good state.
[[noreturn]] void RaiseEngineFailure(const Engine& engine) {
  const EngineSummary s = engine.summary();
  py::dict attributes;
  attributes["summary"] = py::cast(s);
  attributes["state"] = Matrix(engine.Positions(), engine.dimension());
  attributes["step"] = engine.step();
  RaiseNumericalError(s.message, attributes);
}

// Steps with the GIL released, checking Ctrl-C between steps (KeyboardInterrupt).
void StepEngine(Engine& engine, std::int64_t n) {
  bool ok = true;
  try {
    const py::gil_scoped_release release;
    InterruptCheck check;
    for (std::int64_t i = 0; i < n && ok; ++i) {
      if (i > 0) check.Tick(false, [] {});
      ok = engine.Step();
    }
  } catch (const PythonErrorPending&) {
    throw py::error_already_set();
  }
  if (!ok) RaiseEngineFailure(engine);
}

EngineSummary RunEngine(py::object self, Engine& engine, double T,
                        const EngineObserverArgument& argument, std::int64_t every) {
  const py::object& observer = argument.callable;
  (void)StepCount(T, engine.options().h);  // InputError before anything runs
  if (every < 1) throw InputError("every must be ≥ 1 (got " + std::to_string(every) + ")");
  const bool has_observer = !observer.is_none();
  EngineSummary summary;
  try {
    const py::gil_scoped_release release;
    InterruptCheck check;
    std::int64_t index = 0;  // observer calls so far: step 0, then one per step
    summary = engine.Run(T, [&](const Engine&) {
      bool go_on = true;  // False stops; anything else (None: no return value) continues
      check.Tick(has_observer && index++ % every == 0,
                 [&] { go_on = observer(self).ptr() != Py_False; });
      return go_on;
    });
  } catch (const PythonErrorPending&) {
    throw py::error_already_set();
  }
  if (!summary.ok() && summary.termination != Termination::kInterrupted) {
    RaiseEngineFailure(engine);
  }
  return summary;
}

void BindEngine(py::module_& m) {
  py::class_<Engine>(m, "Engine",
                     "First-order PBD for many overdamped particles (particles/engine.h).")
      .def(py::init([](const ParticleModel& model, const Positions& positions,
                       std::optional<Forces> forces, std::optional<EngineOptions> options,
                       const py::kwargs& kw) {
             EngineOptions o = WithKwargs(options, kw);
             const std::span<const double> x = PositionSpan(positions);
             const py::gil_scoped_release release;
             return std::make_unique<Engine>(model, forces.value_or(Forces{}), o, x);
           }),
           py::arg("model"), py::arg("positions"), py::arg("forces") = py::none(),
           py::arg("options") = py::none(),
           "positions: (N, k) or k·N floats in particle-id order (copied). Keyword arguments "
           "are EngineOptions fields (h=…, seed=…, order=…).")
      .def(
          "step", [](Engine& e, std::int64_t n) { StepEngine(e, n); }, py::arg("n") = 1,
          "n steps, the GIL released; NumericalError (last good state) on a non-finite state, "
          "KeyboardInterrupt between steps on Ctrl-C.")
      .def(
          "run",
          [](py::object self, double T, const EngineObserverArgument& observer,
             std::int64_t every) {
            return RunEngine(self, self.cast<Engine&>(), T, observer, every);
          },
          py::arg("T"), py::arg("observer") = py::none(), py::arg("every") = 1,
          "T/h steps; observer(engine) at step 0 and every `every` steps: returning False stops "
          "the run (summary termination 'interrupted', the engine usable), any other value "
          "(None) goes on. "
          "Ctrl-C raises KeyboardInterrupt with the engine at its last completed step.")
      .def(
          "positions", [](const Engine& e) { return Matrix(e.Positions(), e.dimension()); },
          "(N, k) positions in id order, wrapped into the periodic domain: a copy.")
      .def_property_readonly(
          "stored_positions",
          [](py::object self) {
            const Engine& e = self.cast<const Engine&>();
            const StoredPositions s = e.Stored();
            return ReadOnlyView(s.positions.data(), {e.count(), e.dimension()}, self);
          },
          "(N, k) read-only view of the stored positions (storage order, unwrapped): no copy; "
          "its contents are those of the step it was taken at.")
      .def_property_readonly(
          "stored_ids",
          [](py::object self) {
            const Engine& e = self.cast<const Engine&>();
            return ReadOnlyView(e.Stored().ids.data(), {e.count()}, self);
          },
          "(N,) read-only view: the particle id of each storage slot, no copy.")
      .def_property_readonly(
          "radii",
          [](py::object self) {
            const Engine& e = self.cast<const Engine&>();
            return ReadOnlyView(e.model().radius.data(), {e.count()}, self);
          },
          "(N,) read-only view of the radii in id order, no copy.")
      .def("_addresses",
           [](const Engine& e) {
             py::dict d;
             d["stored_positions"] = reinterpret_cast<std::uintptr_t>(e.Stored().positions.data());
             d["stored_ids"] = reinterpret_cast<std::uintptr_t>(e.Stored().ids.data());
             d["radii"] = reinterpret_cast<std::uintptr_t>(e.model().radius.data());
             return d;
           })
      .def_property_readonly("dimension", &Engine::dimension)
      .def_property_readonly("count", &Engine::count)
      .def_property_readonly("step_count", &Engine::step)
      .def_property_readonly("time", &Engine::time)
      .def_property_readonly("threads", &Engine::threads)
      .def_property_readonly("model", &Engine::model)
      .def_property_readonly("forces", &Engine::forces)
      .def_property_readonly("options", &Engine::options)
      .def("summary", &Engine::summary)
      .def("max_pair_overlap", &Engine::MaxPairOverlap)
      .def("max_violation", &Engine::MaxViolation)
      .def("candidate_pairs", &Engine::CandidatePairs);
}

}  // namespace

void RegisterParticles(py::module_& m) {
  BindModel(m);
  BindCrowdTypes(m);
  BindRoomAndForces(m);
  BindEngineOptions(m);
  BindEngine(m);
}

}  // namespace moreau::python
