// moreau.pbd: constraint sets, drifts, time steppers, the paper's two cases and studies.
#include <algorithm>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <pybind11/eigen.h>
#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include "bindings.h"
#include "moreau/common/error.h"
#include "moreau/common/steps.h"
#include "moreau/pbd/cases.h"
#include "moreau/pbd/constraint_set.h"
#include "moreau/pbd/constraints.h"
#include "moreau/pbd/drift.h"
#include "moreau/pbd/particle_constraints.h"
#include "moreau/pbd/stepper.h"
#include "moreau/pbd/study.h"

namespace moreau::python {
namespace {

using namespace moreau::pbd;

// A set shared with Python, added to a ConstraintSetList (which owns its sets).
class SharedSet final : public ConstraintSet {
 public:
  explicit SharedSet(std::shared_ptr<const ConstraintSet> set) : set_(std::move(set)) {}
  int dimension() const override { return set_->dimension(); }
  double Value(ConstVectorRef x) const override { return set_->Value(x); }
  void Gradient(ConstVectorRef x, VectorRef grad) const override { set_->Gradient(x, grad); }
  bool Project(VectorRef x) const override { return set_->Project(x); }
  double Distance(ConstVectorRef x) const override { return set_->Distance(x); }

 private:
  std::shared_ptr<const ConstraintSet> set_;
};

// A read-only numpy view of x for the duration of a Python call (no copy).
py::array View(ConstVectorRef x) {
  py::array view(py::dtype::of<double>(), {x.size()}, {}, x.data(), py::none());
  view.attr("setflags")(py::arg("write") = false);
  return view;
}

// Calls a Python function from C++ code that runs with the GIL released.
template <typename Call>
auto WithGil(Call&& call) {
  const py::gil_scoped_acquire gil;
  try {
    return call();
  } catch (py::error_already_set& e) {
    e.restore();
    throw PythonErrorPending{};
  }
}

// A Python callable f(x) -> array of size d as a drift: one GIL acquisition, one view of x and
// one copy of the result per evaluation.
std::shared_ptr<Drift> PythonDrift(py::function f) {
  auto holder = std::make_shared<py::function>(std::move(f));
  return std::make_shared<FunctionDrift>([holder](ConstVectorRef x, VectorRef out) {
    WithGil([&] {
      const Eigen::VectorXd v = (*holder)(View(x)).cast<Eigen::VectorXd>();
      if (v.size() != out.size()) {
        throw InputError("drift: the function returned " + std::to_string(v.size()) +
                         " values for a state of size " + std::to_string(out.size()));
      }
      out = v;
      return 0;
    });
  });
}

std::shared_ptr<const Drift> AsDrift(const py::object& drift) {
  if (py::isinstance<Drift>(drift)) return drift.cast<std::shared_ptr<Drift>>();
  if (PyCallable_Check(drift.ptr())) return PythonDrift(drift.cast<py::function>());
  throw InputError("drift must be a moreau.pbd drift or a callable f(x) -> array");
}

void BindSets(py::module_& m) {
  py::class_<ConstraintSet, std::shared_ptr<ConstraintSet>>(m, "ConstraintSet",
                                                            "A closed set {x : g(x) ≥ 0} ⊂ R^d.")
      .def_property_readonly("dimension", &ConstraintSet::dimension)
      .def("value", &ConstraintSet::Value, py::arg("x"))
      .def("gradient",
           [](const ConstraintSet& s, const Vector& x) {
             Vector g(x.size());
             s.Gradient(x, g);
             return g;
           })
      .def(
          "project",
          [](const ConstraintSet& s, Vector x) {
            const bool moved = s.Project(x);
            return py::make_tuple(x, moved);
          },
          py::arg("x"), "(P(x), moved): a copy.")
      .def("distance", &ConstraintSet::Distance, py::arg("x"));
  py::class_<BallInterior, ConstraintSet, std::shared_ptr<BallInterior>>(m, "BallInterior")
      .def(py::init<Vector, double>(), py::arg("center"), py::arg("radius"));
  py::class_<BallExterior, ConstraintSet, std::shared_ptr<BallExterior>>(m, "BallExterior")
      .def(py::init<Vector, double>(), py::arg("center"), py::arg("radius"));
  py::class_<HalfSpace, ConstraintSet, std::shared_ptr<HalfSpace>>(m, "HalfSpace")
      .def(py::init<Vector, double>(), py::arg("normal"), py::arg("offset"));
  py::class_<PairNonOverlap, ConstraintSet, std::shared_ptr<PairNonOverlap>>(m, "PairNonOverlap")
      .def(py::init<int, int, int, int, double>(), py::arg("dimension"),
           py::arg("spatial_dimension"), py::arg("i"), py::arg("j"), py::arg("contact_distance"));
  py::class_<FunctionSet, ConstraintSet, std::shared_ptr<FunctionSet>>(
      m, "FunctionSet", "{x : g(x) ≥ 0} from Python callables g(x) and grad(x).")
      .def(py::init([](int dimension, py::function g, py::function grad) {
             auto gh = std::make_shared<py::function>(std::move(g));
             auto dh = std::make_shared<py::function>(std::move(grad));
             return std::make_shared<FunctionSet>(
                 dimension,
                 [gh](ConstVectorRef x) {
                   return WithGil([&] { return (*gh)(View(x)).cast<double>(); });
                 },
                 [dh](ConstVectorRef x, VectorRef out) {
                   WithGil([&] {
                     out = (*dh)(View(x)).cast<Eigen::VectorXd>();
                     return 0;
                   });
                 });
           }),
           py::arg("dimension"), py::arg("g"), py::arg("grad"));

  py::class_<Constraints, std::shared_ptr<Constraints>>(m, "Constraints",
                                                        "S = S_1 ∩ … ∩ S_m as steppers see it.")
      .def_property_readonly("state_size", &Constraints::state_size)
      .def_property_readonly("num_sets", &Constraints::num_sets)
      .def("sweep",
           [](Constraints& c, Vector x) {
             c.Sweep(x);
             return x;
           })
      .def("max_violation", [](Constraints& c, const Vector& x) { return c.MaxViolation(x); });
  py::class_<ConstraintSetList, Constraints, std::shared_ptr<ConstraintSetList>>(
      m, "ConstraintSetList", "Sets visited in list order.")
      .def(py::init([](int state_size, const std::vector<std::shared_ptr<ConstraintSet>>& sets) {
             auto list = std::make_shared<ConstraintSetList>(state_size);
             for (const auto& s : sets) list->Add(std::make_unique<SharedSet>(s));
             return list;
           }),
           py::arg("state_size"), py::arg("sets") = std::vector<std::shared_ptr<ConstraintSet>>{})
      .def(
          "add",
          [](ConstraintSetList& l, std::shared_ptr<ConstraintSet> s) {
            l.Add(std::make_unique<SharedSet>(std::move(s)));
          },
          py::arg("set"));
  py::class_<ParticleConstraints, Constraints, std::shared_ptr<ParticleConstraints>>(
      m, "ParticleConstraints", "Non-overlap and walls of a particle model (the particle core).")
      .def(py::init([](const particles::ParticleModel& model) {
             return std::make_shared<ParticleConstraints>(model);
           }),
           py::arg("model"));
}

void BindDrifts(py::module_& m) {
  py::class_<Drift, std::shared_ptr<Drift>>(m, "Drift", "f in x' ∈ f(x) − N(S, x).")
      .def("__call__", [](const Drift& d, const Vector& x) {
        Vector out(x.size());
        d.Evaluate(x, out);
        return out;
      });
  py::class_<ConstantDrift, Drift, std::shared_ptr<ConstantDrift>>(m, "ConstantDrift")
      .def(py::init<Vector>(), py::arg("c"));
  py::class_<HarmonicDrift, Drift, std::shared_ptr<HarmonicDrift>>(m, "HarmonicDrift")
      .def(py::init<double, Vector>(), py::arg("gamma"), py::arg("center") = Vector());
  m.def("function_drift", &PythonDrift, py::arg("f"),
        "A drift from a Python callable f(x) -> array (one GIL acquisition per evaluation).");
}

void BindStepper(py::module_& m) {
  BindOptionsClass<StepperOptions>(m, "StepperOptions", "Keys of [solver] of run and study.");
  BindSummary<SimulationSummary>(m, "SimulationSummary", "How a simulation ended.")
      .def("brief_report", &SimulationSummary::BriefReport);

  m.def(
      "simulate",
      [](const py::object& drift_object, std::shared_ptr<Constraints> constraints, const Vector& x0,
         double T, std::optional<StepperOptions> options_in, const py::object& observer,
         std::int64_t every, const py::kwargs& kw) {
        StepperOptions options = WithKwargs(options_in, kw);
        if (every < 1) throw InputError("every must be ≥ 1 (got " + std::to_string(every) + ")");
        const std::shared_ptr<const Drift> drift = AsDrift(drift_object);
        const bool has_observer = !observer.is_none();
        Vector x;
        SimulationSummary summary;
        try {
          const py::gil_scoped_release release;
          InterruptCheck check;
          summary = Simulate(
              *drift, *constraints, options, x0, T,
              [&](std::int64_t k, double t, ConstVectorRef xk) {
                bool go_on = true;
                check.Tick(has_observer && k % every == 0,
                           [&] { go_on = observer(k, t, View(xk)).ptr() != Py_False; });
                return go_on;
              },
              &x);
        } catch (const PythonErrorPending&) {
          throw py::error_already_set();
        }
        if (summary.termination == Termination::kNonFinite) {
          py::dict attributes;
          attributes["summary"] = py::cast(summary);
          attributes["state"] = py::cast(x);
          RaiseNumericalError(summary.message, attributes);
        }
        return py::make_tuple(x, summary);
      },
      py::arg("drift"), py::arg("constraints"), py::arg("x0"), py::arg("T"),
      py::arg("options") = py::none(), py::arg("observer") = py::none(), py::arg("every") = 1,
      "Runs T/h steps of x' ∈ f(x) − N(S, x): (final state, summary). drift: a Drift or a "
      "callable f(x) -> array. observer(k, t, x) every `every` steps (x a read-only view, valid "
      "during the call; returning False stops the run, summary.termination \"interrupted\"). "
      "Keyword arguments are StepperOptions fields. NumericalError carries "
      "the last finite state; Ctrl-C raises KeyboardInterrupt between steps.");
}

void BindCases(py::module_& m) {
  py::class_<SlidingCase>(m, "SlidingCase", "The sliding case of paper 000, section 4.2.")
      .def(py::init(&FromKwargs<SlidingCase>))
      .def_readwrite("dimension", &SlidingCase::dimension)
      .def_readwrite("C", &SlidingCase::C)
      .def_readwrite("alpha", &SlidingCase::alpha)
      .def_readwrite("T", &SlidingCase::T)
      .def_property_readonly("radius", &SlidingCase::radius)
      .def_property_readonly("c1", &SlidingCase::c1)
      .def_property_readonly("sliding_end_time", &SlidingCase::sliding_end_time)
      .def("make_constraints",
           [](const SlidingCase& c) {
             return std::shared_ptr<Constraints>(c.MakeConstraints().release());
           })
      .def("make_drift", [](const SlidingCase& c) { return std::shared_ptr<Drift>(c.MakeDrift()); })
      .def("initial_state", &SlidingCase::InitialState)
      .def("exact_solution", &SlidingCase::ExactSolution, py::arg("t"))
      .def("exact_velocity", &SlidingCase::ExactVelocity, py::arg("t"));
  py::class_<DisksCase>(m, "DisksCase", "The disks case of paper 000, section 4.3.")
      .def(py::init(&FromKwargs<DisksCase>))
      .def_readwrite("count", &DisksCase::count)
      .def_readwrite("radius", &DisksCase::radius)
      .def_readwrite("gamma", &DisksCase::gamma)
      .def_readwrite("T", &DisksCase::T)
      .def_readwrite("seed", &DisksCase::seed)
      .def_readwrite("wall", &DisksCase::wall)
      .def_readwrite("box", &DisksCase::box)
      .def_property_readonly("box_half_width", &DisksCase::box_half_width)
      .def("make_model", &DisksCase::MakeModel)
      .def("make_constraints",
           [](const DisksCase& c) { return std::make_shared<ParticleConstraints>(c.MakeModel()); })
      .def("make_drift", [](const DisksCase& c) { return std::shared_ptr<Drift>(c.MakeDrift()); })
      .def("initial_state", &DisksCase::InitialState);
}

// The study problem of a case, as `moreau study` builds it (the disks' reference comes later).
StudyProblem MakeStudyProblem(const py::object& case_object, const std::optional<Vector>& x0) {
  StudyProblem p;
  if (py::isinstance<SlidingCase>(case_object)) {
    const SlidingCase c = case_object.cast<SlidingCase>();
    c.Validate();
    p.constraints = std::make_shared<CaseConstraintModel<SlidingCase>>(c);
    p.drift = c.MakeDrift();
    p.solution = [c](double t) { return c.ExactSolution(t); };
    p.x0 = x0.value_or(c.InitialState());
    p.T = c.T;
    return p;
  }
  if (!py::isinstance<DisksCase>(case_object)) {
    throw InputError("case must be a SlidingCase or a DisksCase");
  }
  const DisksCase c = case_object.cast<DisksCase>();
  c.Validate();
  p.constraints = std::make_shared<ParticleSystemModel>(
      std::make_shared<const particles::ParticleModel>(c.MakeModel()));
  p.drift = c.MakeDrift();
  p.x0 = x0.value_or(c.InitialState());
  p.T = c.T;
  return p;
}

// The study's rows as columns (one list or array per StudyRow field).
py::dict StudyColumns(const std::vector<StudyRow>& rows) {
  py::list label, method, termination, message;
  std::vector<double> h, error, max_violation, seconds;
  std::vector<std::int64_t> evaluations, sweeps;
  for (const StudyRow& r : rows) {
    label.append(r.label);
    method.append(std::string(MethodName(r.method)));
    termination.append(std::string(ToString(r.termination)));
    message.append(r.message);
    h.push_back(r.h);
    error.push_back(r.error);
    max_violation.push_back(r.max_violation);
    seconds.push_back(r.total_seconds);
    evaluations.push_back(r.constraint_evaluations);
    sweeps.push_back(r.sweeps);
  }
  py::dict d;
  d["method"] = label;
  d["method_name"] = method;
  d["h"] = py::array(py::cast(h));
  d["error"] = py::array(py::cast(error));
  d["constraint_evaluations"] = py::array(py::cast(evaluations));
  d["sweeps"] = py::array(py::cast(sweeps));
  d["max_violation"] = py::array(py::cast(max_violation));
  d["total_seconds"] = py::array(py::cast(seconds));
  d["termination"] = termination;
  d["message"] = message;
  return d;
}

py::dict Study(const py::object& case_object, const std::vector<std::string>& method_names,
               std::vector<double> hs, const StepperOptions& base,
               const std::optional<StepperOptions>& reference, const std::optional<Vector>& x0) {
  std::vector<MethodSpec> methods;
  for (const std::string& name : method_names) methods.push_back(ParseMethodSpec(name));
  if (methods.empty()) throw InputError("methods: at least one method is needed");
  if (hs.empty()) throw InputError("h: at least one step size is needed");
  std::sort(hs.begin(), hs.end(), std::greater<>());
  StudyProblem problem = MakeStudyProblem(case_object, x0);
  for (double h : hs) (void)StepCount(problem.T, h);
  std::vector<StudyRow> rows;
  try {
    const py::gil_scoped_release release;
    if (!problem.solution) {
      if (!reference) throw InputError("reference: the disks case needs reference options");
      auto trajectory =
          std::make_shared<SampledTrajectory>(ComputeReference(problem, *reference, hs.back()));
      problem.solution = [trajectory](double t) { return trajectory->At(t); };
    }
    InterruptCheck check(std::chrono::milliseconds(0));
    rows = RunStudy(problem, methods, hs, base, [&](int, int) { check.Tick(false, [] {}); });
  } catch (const PythonErrorPending&) {
    throw py::error_already_set();
  }
  return StudyColumns(rows);
}

void BindStudy(py::module_& m) {
  m.def(
      "study",
      [](const py::object& case_object, const std::vector<std::string>& methods,
         const std::vector<double>& h, std::optional<StepperOptions> options,
         std::optional<StepperOptions> reference, std::optional<Vector> x0, const py::kwargs& kw) {
        StepperOptions base = WithKwargs(options, kw);
        base.Validate();
        return Study(case_object, methods, h, base, reference, x0);
      },
      py::arg("case"), py::arg("methods"), py::arg("hs"), py::arg("options") = py::none(),
      py::arg("reference") = py::none(), py::arg("x0") = py::none(),
      "The convergence study of `moreau study`: every method (\"pbd\", \"pngs\", \"pgs\", "
      "\"penalty:GAMMA\") at every h (sorted large to small), error against the exact solution "
      "(sliding) or a reference run with `reference` options (disks, sampled at the smallest h). "
      "Returns a dict of columns in row order. Keyword arguments are StepperOptions fields.");
  m.def("observed_order", &ObservedOrder, py::arg("h"), py::arg("error"),
        "Least-squares slope of log(error) against log(h).");
}

}  // namespace

void RegisterPbd(py::module_& m) {
  BindSets(m);
  BindDrifts(m);
  BindStepper(m);
  BindCases(m);
  BindStudy(m);
}

}  // namespace moreau::python
