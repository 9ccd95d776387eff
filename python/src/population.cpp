// moreau.particles.Population: agent-based models from Python, with numpy views of the agents'
// arrays and user code (a drift before every step, a rule at every rule step) that sees the whole
// population at once.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include "bindings.h"
#include "moreau/common/error.h"
#include "moreau/common/steps.h"
#include "moreau/particles/population.h"

namespace moreau::python {
namespace {

using namespace moreau::particles;

using Positions = py::array_t<double, py::array::c_style | py::array::forcecast>;

// A numpy view of `n` values of type T spaced `stride` bytes apart from `data`, owned by `owner`
// (kept alive by the array; None: valid only during a call of user code).
template <typename T>
py::array View(T* data, std::vector<py::ssize_t> shape, std::vector<py::ssize_t> strides,
               py::handle owner, bool writable) {
  py::array view(py::dtype::of<T>(), std::move(shape), std::move(strides), data, owner);
  if (!writable) {  // as pybind11's Eigen casters do: no Python call (setflags) per view
    py::detail::array_proxy(view.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
  }
  return view;
}

// The byte offset of a member of Agent, for strided views of one field over the agents.
template <typename M>
std::ptrdiff_t Offset(M Agent::*member) {
  const Agent a;
  return reinterpret_cast<const char*>(&(a.*member)) - reinterpret_cast<const char*>(&a);
}

// One field of every agent as an (N,) view (or (N, k) for the polarity).
template <typename M>
py::array AgentField(Population& p, M Agent::*member, py::handle owner, bool writable) {
  const std::span<Agent> agents = p.MutableAgents();
  auto* base = reinterpret_cast<char*>(agents.data()) + Offset(member);
  constexpr auto stride = static_cast<py::ssize_t>(sizeof(Agent));
  const auto n = static_cast<py::ssize_t>(agents.size());
  if constexpr (std::is_same_v<M, Vec3>) {
    return View(reinterpret_cast<double*>(base), {n, p.engine().dimension()},
                {stride, static_cast<py::ssize_t>(sizeof(double))}, owner, writable);
  } else {
    return View(reinterpret_cast<M*>(base), {n}, {stride}, owner, writable);
  }
}

// The initial agents' types: indices, or names of the rules' types.
std::vector<int> TypeIndices(const PopulationRules& rules, const py::sequence& types) {
  std::vector<int> out;
  for (const py::handle t : types) {
    out.push_back(py::isinstance<py::str>(t) ? rules.TypeIndex(t.cast<std::string>())
                                             : t.cast<int>());
  }
  return out;
}

// Calls Python user code from the engine's loop (the GIL released there): takes the GIL, and
// turns a Python exception into PythonErrorPending (the error stays set for the binding).
template <typename Call>
void CallPython(Call&& call) {
  const py::gil_scoped_acquire gil;
  try {
    std::forward<Call>(call)();
  } catch (py::error_already_set& e) {
    e.restore();
    throw PythonErrorPending{};
  }
}

// The Python drift(population, velocity): velocity an (N, k) writable view, zero on entry.
// `self` is borrowed: the C++ population that holds this function lives inside it.
struct PythonDriftCall {
  py::object callable;
  PyObject* self;
  void operator()(const PopulationView& view, std::span<double> v) const {
    CallPython([&] {
      const auto n = static_cast<py::ssize_t>(view.agents.size());
      const auto k = static_cast<py::ssize_t>(view.dimension);
      callable(py::handle(self), View(v.data(), {n, k}, {}, py::none(), true));
    });
  }
};

// The Python rule(population, divide, die): divide and die (N,) writable bool views, False on
// entry.
struct PythonRuleCall {
  py::object callable;
  PyObject* self;
  void operator()(PopulationView& view, std::span<std::uint8_t> divide,
                  std::span<std::uint8_t> die) const {
    CallPython([&] {
      const auto n = static_cast<py::ssize_t>(view.agents.size());
      auto flags = [&](std::span<std::uint8_t> f) {
        return py::array(py::dtype("bool"), {n}, {}, f.data(), py::none());
      };
      callable(py::handle(self), flags(divide), flags(die));
    });
  }
};

// The Python callable behind a user drift or rule set from Python; None for none.
template <typename Call, typename F>
py::object PythonCallable(const F& f) {
  const Call* call = f.template target<Call>();
  return call != nullptr ? call->callable : py::none();
}

// Runs `steps` with the GIL released, checking Ctrl-C between steps; the observer at rule steps.
PopulationSummary RunSteps(py::object self, Population& p, std::optional<double> T,
                           std::int64_t steps, const py::object& observer) {
  const bool has_observer = !observer.is_none();
  PopulationSummary summary;
  try {
    const py::gil_scoped_release release;
    InterruptCheck check;
    if (T) {
      summary = p.Run(*T, [&](const Population&) {
        bool go_on = true;
        check.Tick(has_observer, [&] { go_on = observer(self).ptr() != Py_False; });
        return go_on;
      });
    } else {
      for (std::int64_t i = 0; i < steps && p.Step(); ++i) check.Tick(false, [] {});
      summary = p.summary();
    }
  } catch (const PythonErrorPending&) {
    throw py::error_already_set();
  }
  return summary;
}

void BindVariable(py::module_& m) {
  py::enum_<Inheritance>(m, "Inheritance", "How daughters inherit a user variable.")
      .value("copy", Inheritance::kCopy)
      .value("split", Inheritance::kSplit);
  py::class_<AgentVariable>(m, "AgentVariable",
                            "A user variable: one number per agent, inherited at division.")
      .def(py::init([](std::string name, double initial, const std::string& inherit) {
             return AgentVariable{std::move(name), initial,
                                  ParseEnumName(kInheritanceNames, inherit, "inheritance")};
           }),
           py::arg("name"), py::arg("initial") = 0.0, py::arg("inherit") = "copy",
           "inherit: 'copy' (both daughters keep the value) or 'split' (half each).")
      .def_readwrite("name", &AgentVariable::name)
      .def_readwrite("initial", &AgentVariable::initial)
      .def_readwrite("inherit", &AgentVariable::inherit);
  BindSummary<PopulationSummary>(m, "PopulationSummary",
                                 "How a population run ended: termination, counts, *_seconds.");
}

// Steps, runs and the user code.
void BindRuns(py::class_<Population>& c) {
  c.def(
       "step",
       [](py::object self, std::int64_t n) {
         return RunSteps(self, self.cast<Population&>(), std::nullopt, n, py::none());
       },
       py::arg("n") = 1,
       "n engine steps (rules at every interval-th); stops early when the population stops "
       "(see summary()). KeyboardInterrupt between steps on Ctrl-C.")
      .def(
          "run",
          [](py::object self, double T, py::object observer) {
            return RunSteps(self, self.cast<Population&>(), T, 0, observer);
          },
          py::arg("T"), py::arg("observer") = py::none(),
          "T/h steps; observer(population) at step 0 and after every rule step: False stops.")
      .def_property(
          "drift", [](const Population& p) { return PythonCallable<PythonDriftCall>(p.drift()); },
          [](py::object self, py::object f) {
            Population& p = self.cast<Population&>();
            p.SetDrift(f.is_none() ? UserDrift{} : UserDrift(PythonDriftCall{f, self.ptr()}));
          },
          "drift(population, velocity) before every step fills velocity (N, k), zero on entry, "
          "added to the agents' drift. None removes it.")
      .def_property(
          "rule", [](const Population& p) { return PythonCallable<PythonRuleCall>(p.rule()); },
          [](py::object self, py::object f) {
            Population& p = self.cast<Population&>();
            p.SetRule(f.is_none() ? UserRule{} : UserRule(PythonRuleCall{f, self.ptr()}));
          },
          "rule(population, divide, die) at every rule step, before the built-in rules; may "
          "change radii, types, polarities and variables, and set divide[i] or die[i]. None "
          "removes it.");
}

// The numpy views of the agents' arrays (owned by the population, valid until its next step).
void BindViews(py::class_<Population>& c) {
  c.def_property_readonly(
       "positions",
       [](py::object self) {
         Population& p = self.cast<Population&>();
         const std::span<const double> x = p.CurrentPositions();
         return View(x.data(), {static_cast<py::ssize_t>(p.count()), p.engine().dimension()}, {},
                     self, false);
       },
       "(N, k) read-only view of the positions (index order, wrapped), gathered once per step: "
       "valid until the next step.")
      .def_property_readonly(
          "ids",
          [](py::object self) {
            return AgentField(self.cast<Population&>(), &Agent::id, self, false);
          },
          "(N,) int64 read-only view of the stable ids.")
      .def_property_readonly(
          "types",
          [](py::object self) {
            return AgentField(self.cast<Population&>(), &Agent::type, self, true);
          },
          "(N,) int32 view of the type indices (writable; taken at the next rule step).")
      .def_property_readonly(
          "radii",
          [](py::object self) {
            return AgentField(self.cast<Population&>(), &Agent::radius, self, true);
          },
          "(N,) view of the radii (writable; taken at the next rule step).")
      .def_property_readonly(
          "generations",
          [](py::object self) {
            return AgentField(self.cast<Population&>(), &Agent::generation, self, false);
          },
          "(N,) int32 read-only view: divisions since the initial agent of the lineage.")
      .def_property_readonly(
          "ages",
          [](py::object self) {
            return AgentField(self.cast<Population&>(), &Agent::age, self, false);
          },
          "(N,) read-only view: time since the last division or the start.")
      .def_property_readonly(
          "polarities",
          [](py::object self) {
            return AgentField(self.cast<Population&>(), &Agent::polarity, self, true);
          },
          "(N, k) view of the unit polarities (writable).")
      .def(
          "variable",
          [](py::object self, const std::string& name) {
            Population& p = self.cast<Population&>();
            const std::span<double> v = p.MutableVariable(p.VariableIndex(name));
            return View(v.data(), {static_cast<py::ssize_t>(v.size())}, {}, self, true);
          },
          py::arg("name"), "(N,) writable view of the user variable `name`.");
}

}  // namespace

void BindPopulationFields(py::class_<Population>& c);  // population_fields.cpp

void RegisterPopulation(py::module_& m) {
  BindVariable(m);
  py::class_<Population> c(m, "Population",
                           "Agents on the particle engine (particles/population.h): the rules' "
                           "types and rules, user variables, and user code.");
  c.def(py::init([](const PopulationRules& rules, const py::sequence& types,
                    const Positions& positions, std::optional<ParticleModel> geometry,
                    std::optional<Forces> forces, std::optional<EngineOptions> options,
                    const py::kwargs& kw) {
          const EngineOptions o = WithKwargs(options, kw);
          const std::vector<int> t = TypeIndices(rules, types);
          if (!geometry) {
            if (positions.ndim() != 2) {
              throw InputError("positions", "must be (N, k) when no geometry gives k");
            }
            geometry.emplace();
            geometry->dimension = static_cast<int>(positions.shape(1));
          }
          const std::span<const double> x(positions.data(),
                                          static_cast<std::size_t>(positions.size()));
          const py::gil_scoped_release release;
          return std::make_unique<Population>(*geometry, forces.value_or(Forces{}), o, rules, t, x);
        }),
        py::arg("rules"), py::arg("types"), py::arg("positions"), py::arg("geometry") = py::none(),
        py::arg("forces") = py::none(), py::arg("options") = py::none(),
        "types: per initial agent a type index or name; positions: (N, k) (or k·N with a "
        "geometry); geometry: a ParticleModel for the dimension, walls, obstacles and periodic "
        "domain (its radii are the agents'). Keyword arguments are EngineOptions fields.");
  BindRuns(c);
  BindViews(c);
  BindPopulationFields(c);
  c.def_property_readonly("count", &Population::count)
      .def_property_readonly("dimension",
                             [](const Population& p) { return p.engine().dimension(); })
      .def_property_readonly("step_count", [](const Population& p) { return p.engine().step(); })
      .def_property_readonly("time", [](const Population& p) { return p.engine().time(); })
      .def_property_readonly("rules", &Population::rules)
      .def("summary", &Population::summary)
      .def("max_pair_overlap", [](const Population& p) { return p.engine().MaxPairOverlap(); })
      .def(
          "observe",
          [](const Population& p) {
            const PopulationObservables o = p.Observe();
            py::dict d;
            d["step"] = o.step;
            d["time"] = o.time;
            d["count"] = o.count;
            d["count_per_type"] = o.count_per_type;
            d["mean_radius"] = o.mean_radius;
            d["contacts"] = o.contacts;
            d["overlap"] = o.overlap;
            d["colony_radius"] = o.colony_radius;
            d["segregation"] = o.segregation;
            d["births"] = o.births;
            d["deaths"] = o.deaths;
            d["removals"] = o.removals;
            return d;
          },
          "The observables now, as a dict (the columns of population.csv).");
}

}  // namespace moreau::python
