#include "control/control_scenario.h"

#include <fmt/format.h>

#include "moreau/common/error.h"
#include "moreau/common/memory.h"
#include "moreau/control/pontryagin.h"

namespace moreau::cli {
namespace {

using CS = ControlScenario;

// Runs `f`, prefixing a library InputError ("key: reason") with the scenario file.
template <typename F>
auto WithFile(const Scenario& s, F&& f) {
  try {
    return f();
  } catch (const InputError& e) {
    throw InputError(fmt::format("{}: {}", s.path(), e.what()));
  }
}

FieldTable<control::OscillatorExample> OscillatorFields() {
  using E = control::OscillatorExample;
  FieldTable<E> t;
  t.Number("mass", &E::mass, Range::Positive(), "mass m")
      .Number("stiffness", &E::stiffness, Range::Any(), "spring stiffness κ")
      .Number("damping", &E::damping, Range::Any(), "spring damping ξ")
      .Number("rest_min", &E::rest_min, Range::Any(), "smallest rest length L−")
      .Number("rest_max", &E::rest_max, Range::Any(), "largest rest length L+")
      .Number("start", &E::start, Range::Any(), "x(0), at rest")
      .Number("target", &E::target, Range::Any(), "final reference position")
      .Number("move_time", &E::move_time, Range::Positive(), "the reference moves in [0, T_m]");
  return t;
}

FieldTable<control::ArmExample> ArmFields() {
  using E = control::ArmExample;
  FieldTable<E> t;
  t.Number("mass", &E::mass, Range::Positive(), "mass of the four free nodes")
      .Number("stiffness", &E::stiffness, Range::NonNegative(), "κ of every spring")
      .Number("damping", &E::damping, Range::NonNegative(), "ξ of every spring")
      .Number("spring_limit", &E::spring_limit, Range::Any(), "L± = (1 ± limit) × length")
      .Number("upper_bone", &E::upper_bone, Range::Positive(), "L1 = |AB|")
      .Number("lower_bone", &E::lower_bone, Range::Positive(), "L2 = |BC|")
      .Number("elbow_half_width", &E::elbow_half_width, Range::Positive(), "l1")
      .Number("hand_half_width", &E::hand_half_width, Range::Positive(), "l2")
      .Numbers("anchor", &E::anchor, "shoulder A [x, y]")
      .Number("angle_ab_deg", &E::angle_ab_deg, Range::Any(), "θ1 max (degrees)")
      .Number("angle_bc_deg", &E::angle_bc_deg, Range::Any(), "θ2 max (degrees)")
      .Number("angle_34_deg", &E::angle_34_deg, Range::Any(), "φ1 max (degrees)")
      .Number("angle_12_deg", &E::angle_12_deg, Range::Any(), "φ2 max (degrees)")
      .Number("periods", &E::periods, Range::Any(), "periods of the motion k");
  return t;
}

// The keys the thesis examples share: horizon, γ and the running-cost weights.
template <class E>
FieldTable<E> ExampleProblemFields() {
  FieldTable<E> t;
  t.Number("problem.horizon", &E::horizon, Range::Positive(), "T")
      .Number("regularization.gamma", &E::gamma, Range::Any(), "γ")
      .Number("cost.position", &E::position_weight, Range::NonNegative(), "μ_x")
      .Number("cost.velocity", &E::velocity_weight, Range::NonNegative(), "μ_v");
  return t;
}

FieldTable<control::CostWeights> CostFields(bool terminal) {
  using W = control::CostWeights;
  FieldTable<W> t;
  t.Number("position", &W::position, Range::NonNegative(), "μ_x on |x − X|²")
      .Number("velocity", &W::velocity, Range::NonNegative(), "μ_v on |v − V|²");
  if (terminal) {
    t.Number("terminal_position", &W::terminal_position, Range::NonNegative(), "η_x")
        .Number("terminal_velocity", &W::terminal_velocity, Range::NonNegative(), "η_v");
  }
  return t;
}

FieldTable<control::ValueErrorConstants> TheoremFields() {
  using C = control::ValueErrorConstants;
  FieldTable<C> t;
  t.Number("c1", &C::c1, Range::NonNegative(), "C1")
      .Required()
      .Number("c2", &C::c2, Range::NonNegative(), "C2")
      .Required()
      .Number("c3", &C::c3, Range::NonNegative(), "C3 (0 without terminal cost)")
      .Number("delta", &C::delta, Range::NonNegative(), "δ")
      .Required();
  return t;
}

void ReadTheorem(Scenario& s, CS& c, const std::string& key) {
  if (!s.Has(key)) {
    (void)s.GetNode(key);
    return;
  }
  FieldTable<control::ValueErrorConstants> t;
  t.Mount(
      key, [](auto& x) -> auto& { return x; }, TheoremFields());
  control::ValueErrorConstants constants;
  t.Read(s, constants);
  c.theorem = constants;
}

// model-specific fields: the example or the network, horizon, γ and cost.
void AddModelFields(FieldTable<CS>& t, const std::string& model) {
  if (model == "oscillator") {
    t.Mount("oscillator", &CS::oscillator, OscillatorFields())
        .Mount("", &CS::oscillator, ExampleProblemFields<control::OscillatorExample>());
  } else if (model == "arm") {
    t.Mount("arm", &CS::arm, ArmFields())
        .OptionalNumber("arm.bounds_time", &CS::arm_bounds_time, Range::Any(),
                        "time of the bounds' reference configuration (default T/2)")
        .Mount("", &CS::arm, ExampleProblemFields<control::ArmExample>());
  } else {
    auto matrix = [](Eigen::MatrixXd NetworkSettings::*m) {
      return [m](Scenario& sc, CS& s, const std::string& k) {
        ReadReferenceMatrix(sc, k, &(s.network.*m));
      };
    };
    t.Integer(
         "network.dimension", [](auto& s) -> auto& { return s.network.dimension; },
         Range::Closed(1, 3), "d")
        .Custom(
            "network.nodes", "array of tables", ReadNetworkNodes,
            [](const CS& s) { return nlohmann::json(s.network.nodes.size()); },
            "{mass, position, velocity, fixed}")
        .Required()
        .Custom(
            "network.springs", "array of tables", ReadNetworkSprings,
            [](const CS& s) { return nlohmann::json(s.network.springs.size()); },
            "{nodes, stiffness, damping, rest_min, rest_max}")
        .Required()
        .Number(
            "problem.horizon", [](auto& s) -> auto& { return s.network.horizon; },
            Range::Positive(), "T")
        .Required()
        .Number(
            "regularization.gamma", [](auto& s) -> auto& { return s.network.gamma; }, Range::Any(),
            "γ")
        .Mount(
            "cost", [](auto& s) -> auto& { return s.network.cost; }, CostFields(true))
        .Custom("reference.positions", "frames × (d · free nodes)",
                matrix(&NetworkSettings::positions), {}, "sampled reference positions")
        .Required()
        .Custom("reference.velocities", "frames × (d · free nodes)",
                matrix(&NetworkSettings::velocities), {}, "sampled reference velocities")
        .Custom("reference.weights", "frames × free nodes", matrix(&NetworkSettings::weights), {},
                "weights; 0 marks a missing sample");
  }
}

FieldTable<CS> MakeControlFields(const std::string& model) {
  FieldTable<CS> t;
  t.Text("model", &CS::model, "oscillator, arm or network").Required();
  AddModelFields(t, model);
  t.Integer("discretization.steps", &CS::steps,
            Range::Closed(1, 1e8).Because("so that the time step T/N is positive"),
            "number of time steps N")
      .Mount("continuation", &CS::continuation, control::ContinuationOptions::Fields(),
             {{"fixed_point", "fixed_point"}, {"newton", "newton"}})
      .CapThreads("newton.threads")
      .Flag("study.warm_start", &CS::warm_start, "Newton from the coarser solution first")
      .Integer("study.compare_samples", &CS::compare_samples, Range::NonNegative(),
               "instants for diff_finest (0: the coarsest grid's nodes)")
      .Custom(
          "study.theorem", "table {c1, c2, c3, delta}", ReadTheorem,
          [](const CS& s) { return s.theorem ? s.theorem->ToJson() : nlohmann::json(); },
          "constants of Theorem 5.1 for the bounds in convergence.csv");
  return t;
}

// The memory of a solve on `steps` steps (control::CheckSolveMemory), named by its key.
void CheckControlMemory(const control::SpringNetwork& network, int steps) {
  try {
    control::CheckSolveMemory(network, steps);
  } catch (const InputError& e) {
    throw InputError(fmt::format("discretization.steps: {}", e.what()));  // WithFile adds the file
  }
}

}  // namespace

const FieldTable<CS>& ControlFields(const std::string& model) {
  static const FieldTable<CS> oscillator = MakeControlFields("oscillator");
  static const FieldTable<CS> arm = MakeControlFields("arm");
  static const FieldTable<CS> network = MakeControlFields("network");
  return model == "oscillator" ? oscillator : model == "arm" ? arm : network;
}

ControlScenario ReadControlScenario(Scenario& s) {
  ControlScenario c;
  c.model = s.RequireString("model");
  if (c.model != "oscillator" && c.model != "arm" && c.model != "network") {
    s.Fail("model",
           fmt::format("unknown model '{}' (expected oscillator, arm or network)", c.model));
  }
  ControlFields(c.model).Read(s, c);
  if (c.model == "arm") {
    c.arm.bounds_time = c.arm_bounds_time.value_or(0.5 * c.arm.horizon);
    c.arm_bounds_time = c.arm.bounds_time;
  }
  WithFile(s, [&] {
    // Build the target problem now so that every model error surfaces before any output.
    const control::TrackingProblem target = MakeProblemFamily(c)(1.0);
    CheckControlMemory(target.network(), c.steps);
    return control::PontryaginDiscretization(target, c.steps).steps();
  });
  return c;
}

nlohmann::json EchoControlScenario(const ControlScenario& scenario) {
  return ControlFields(scenario.model).Echo(scenario);
}

control::ProblemFamily MakeProblemFamily(const ControlScenario& c) {
  if (c.model == "oscillator") {
    return [ex = c.oscillator](double p) { return control::MakeOscillatorProblem(ex, p); };
  }
  if (c.model == "arm") {
    return [ex = c.arm](double p) { return control::MakeArmProblem(ex, p); };
  }
  const NetworkSettings& n = c.network;
  control::SpringNetwork network(n.dimension, n.nodes, n.springs);
  control::ReferenceFunction reference = control::SampledReference(
      network, n.horizon, n.positions, n.velocities, n.weights, "reference");
  return control::LinearPathFamily(
      control::TrackingProblem(network, n.horizon, std::move(reference), n.cost, n.gamma));
}

}  // namespace moreau::cli
