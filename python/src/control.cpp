// moreau.control: spring networks, tracking problems, the thesis' examples and the solve with
// continuation.
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include "bindings.h"
#include "moreau/common/error.h"
#include "moreau/control/continuation.h"
#include "moreau/control/examples.h"
#include "moreau/control/pontryagin.h"
#include "moreau/control/refinement_study.h"
#include "moreau/control/spring_network.h"
#include "moreau/control/tracking_problem.h"

namespace moreau::python {
namespace {

using namespace moreau::control;

void BindNetwork(py::module_& m) {
  py::class_<NetworkNode>(m, "NetworkNode", "A free (mass) or fixed (anchor) node.")
      .def(py::init(&FromKwargs<NetworkNode>))
      .def_readwrite("fixed", &NetworkNode::fixed)
      .def_readwrite("mass", &NetworkNode::mass)
      .def_readwrite("position", &NetworkNode::position)
      .def_readwrite("velocity", &NetworkNode::velocity);
  py::class_<NetworkSpring>(m, "NetworkSpring", "A spring–damper between nodes a and b.")
      .def(py::init(&FromKwargs<NetworkSpring>))
      .def_readwrite("a", &NetworkSpring::a)
      .def_readwrite("b", &NetworkSpring::b)
      .def_readwrite("stiffness", &NetworkSpring::stiffness)
      .def_readwrite("damping", &NetworkSpring::damping)
      .def_readwrite("rest_min", &NetworkSpring::rest_min)
      .def_readwrite("rest_max", &NetworkSpring::rest_max);
  py::class_<SpringNetwork>(m, "SpringNetwork", "The mass–spring–damper network (validated).")
      .def(py::init<int, std::vector<NetworkNode>, std::vector<NetworkSpring>>(),
           py::arg("dimension"), py::arg("nodes"), py::arg("springs"))
      .def_property_readonly("dimension", &SpringNetwork::dimension)
      .def_property_readonly("num_nodes", &SpringNetwork::num_nodes)
      .def_property_readonly("num_springs", &SpringNetwork::num_springs)
      .def_property_readonly("num_free", &SpringNetwork::num_free)
      .def_property_readonly("state_size", &SpringNetwork::state_size)
      .def_property_readonly("nodes", &SpringNetwork::nodes)
      .def_property_readonly("springs", &SpringNetwork::springs)
      .def("initial_state", &SpringNetwork::InitialState);
  py::class_<CostWeights>(m, "CostWeights", "Keys of [cost]: position, velocity, terminal_*.")
      .def(py::init(&FromKwargs<CostWeights>))
      .def_readwrite("position", &CostWeights::position)
      .def_readwrite("velocity", &CostWeights::velocity)
      .def_readwrite("terminal_position", &CostWeights::terminal_position)
      .def_readwrite("terminal_velocity", &CostWeights::terminal_velocity);
  py::class_<TrackingProblem>(m, "TrackingProblem", "Steer a network to follow a reference.")
      .def(py::init([](const SpringNetwork& network, double horizon, Eigen::MatrixXd positions,
                       std::optional<Eigen::MatrixXd> velocities,
                       std::optional<Eigen::MatrixXd> weights, std::optional<CostWeights> cost,
                       double gamma) {
             ReferenceFunction reference = SampledReference(
                 network, horizon, std::move(positions), velocities.value_or(Eigen::MatrixXd()),
                 weights.value_or(Eigen::MatrixXd()), "reference");
             return TrackingProblem(network, horizon, std::move(reference),
                                    cost.value_or(CostWeights{}), gamma);
           }),
           py::arg("network"), py::arg("horizon"), py::arg("positions"),
           py::arg("velocities") = py::none(), py::arg("weights") = py::none(),
           py::arg("cost") = py::none(), py::arg("gamma") = 1e-4,
           "A reference sampled at F ≥ 2 equally spaced frames: positions F × (d M), velocities "
           "F × (d M) (default 0), weights F × M (default 1; 0 marks missing data).")
      .def_property_readonly("network", &TrackingProblem::network)
      .def_property_readonly("horizon", &TrackingProblem::horizon)
      .def_property_readonly("weights", &TrackingProblem::weights)
      .def_property_readonly("gamma", &TrackingProblem::gamma)
      .def("regularization_delta", &TrackingProblem::RegularizationDelta);
}

void BindExamples(py::module_& m) {
  py::class_<OscillatorExample>(m, "OscillatorExample", "Thesis example 9.1 (d = 1).")
      .def(py::init(&FromKwargs<OscillatorExample>))
      .def_readwrite("mass", &OscillatorExample::mass)
      .def_readwrite("stiffness", &OscillatorExample::stiffness)
      .def_readwrite("damping", &OscillatorExample::damping)
      .def_readwrite("rest_min", &OscillatorExample::rest_min)
      .def_readwrite("rest_max", &OscillatorExample::rest_max)
      .def_readwrite("gamma", &OscillatorExample::gamma)
      .def_readwrite("horizon", &OscillatorExample::horizon)
      .def_readwrite("start", &OscillatorExample::start)
      .def_readwrite("target", &OscillatorExample::target)
      .def_readwrite("move_time", &OscillatorExample::move_time)
      .def_readwrite("position_weight", &OscillatorExample::position_weight)
      .def_readwrite("velocity_weight", &OscillatorExample::velocity_weight)
      .def("problem", &MakeOscillatorProblem, py::arg("path_fraction") = 1.0);
  py::class_<ArmExample>(m, "ArmExample", "Thesis example 9.2, the arm (d = 2).")
      .def(py::init(&FromKwargs<ArmExample>))
      .def_readwrite("mass", &ArmExample::mass)
      .def_readwrite("stiffness", &ArmExample::stiffness)
      .def_readwrite("damping", &ArmExample::damping)
      .def_readwrite("spring_limit", &ArmExample::spring_limit)
      .def_readwrite("horizon", &ArmExample::horizon)
      .def_readwrite("gamma", &ArmExample::gamma)
      .def_readwrite("position_weight", &ArmExample::position_weight)
      .def_readwrite("velocity_weight", &ArmExample::velocity_weight)
      .def_readwrite("periods", &ArmExample::periods)
      .def("problem", &MakeArmProblem, py::arg("path_fraction") = 1.0);
}

void BindOptions(py::module_& m) {
  BindOptionsClass<FixedPointOptions>(m, "FixedPointOptions", "Keys of [fixed_point].");
  BindOptionsClass<NewtonOptions>(m, "NewtonOptions", "Keys of [newton].");
  BindOptionsClass<ContinuationOptions>(m, "ContinuationOptions", "Keys of [continuation].")
      .def_readwrite("fixed_point", &ContinuationOptions::fixed_point)
      .def_readwrite("newton", &ContinuationOptions::newton);
  BindSummary<ContinuationSummary>(m, "ContinuationSummary", "How the solve ended.")
      .def("brief_report", &ContinuationSummary::BriefReport);
}

// The problem family of what Python passed: an example (its own path scaling) or a problem.
ProblemFamily FamilyOf(const py::object& problem) {
  if (py::isinstance<OscillatorExample>(problem)) {
    const auto e = problem.cast<OscillatorExample>();
    return [e](double p) { return MakeOscillatorProblem(e, p); };
  }
  if (py::isinstance<ArmExample>(problem)) {
    const auto e = problem.cast<ArmExample>();
    return [e](double p) { return MakeArmProblem(e, p); };
  }
  return LinearPathFamily(problem.cast<const TrackingProblem&>());
}

py::dict Solve(const py::object& problem, int steps, const ContinuationOptions& options) {
  if (steps < 1) throw InputError("steps must be ≥ 1 (got " + std::to_string(steps) + ")");
  options.Validate();
  const ProblemFamily family = FamilyOf(problem);
  py::dict result;
  Eigen::VectorXd y;
  Eigen::MatrixXd z, rho, controls;
  ContinuationSummary summary;
  double residual_norm = 0.0, value = 0.0, tracking_rms = 0.0, dt = 0.0;
  {
    const py::gil_scoped_release release;
    const TrackingProblem target = family(1.0);
    try {
      CheckSolveMemory(target.network(), steps);  // before anything of N steps is allocated
    } catch (const InputError& e) {
      throw InputError("steps", e.what());
    }
    const PontryaginDiscretization disc(target, steps);
    summary = SolveWithContinuation(family, steps, options, y);
    PontryaginWorkspace ws;
    Eigen::VectorXd residual;
    residual_norm = EvaluateResidual(disc, y, ws, residual);
    value = DiscreteValue(disc, y, ws);
    disc.Unpack(y, z, rho);
    controls = EffectiveControls(disc, y);
    tracking_rms = TrackingRms(disc, z);
    dt = disc.dt();
  }
  result["summary"] = py::cast(summary);
  result["states"] = py::cast(Eigen::MatrixXd(z.transpose()));
  result["duals"] = py::cast(Eigen::MatrixXd(rho.transpose()));
  result["controls"] = py::cast(Eigen::MatrixXd(controls.transpose()));
  result["dt"] = dt;
  result["residual_norm"] = residual_norm;
  result["value"] = value;
  result["tracking_rms"] = tracking_rms;
  if (!summary.ok()) {
    py::dict attributes;
    attributes["summary"] = result["summary"];
    attributes["state"] = result;
    RaiseNumericalError(summary.message, attributes);
  }
  return result;
}

}  // namespace

void RegisterControl(py::module_& m) {
  BindNetwork(m);
  BindExamples(m);
  BindOptions(m);
  m.def(
      "solve",
      [](const py::object& problem, int steps, std::optional<ContinuationOptions> options,
         const py::kwargs& kw) {
        ContinuationOptions o = WithKwargs(options, kw);
        return Solve(problem, steps, o);
      },
      py::arg("problem"), py::arg("steps"), py::arg("options") = py::none(),
      "Solves a TrackingProblem (or an OscillatorExample / ArmExample, whose reference is "
      "scaled by the path fraction) on `steps` steps with continuation, the GIL released. "
      "Returns {summary, states (N+1 × n_z), duals, controls (rows per step), dt, "
      "residual_norm, value, tracking_rms}; NumericalError (with .state = that dict) when the "
      "target is not solved. Keyword arguments are ContinuationOptions fields.");
}

}  // namespace moreau::python
