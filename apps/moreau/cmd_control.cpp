// `moreau control SCENARIO.toml [--set key=value ...] [--out DIR] [--study-steps 32,64,...]`:
// optimal control of a mass–spring–damper network by the Symplectic Pontryagin method + Newton
// (issue 3; docs/control.md). Writes summary.json, trajectory.csv and controls.csv, or, with
// --study-steps, the grid-refinement table convergence.csv and its figures.
#include <fmt/format.h>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>

#include "commands.h"
#include "moreau/common/error.h"
#include "moreau/control/continuation.h"
#include "moreau/control/examples.h"
#include "moreau/control/newton.h"
#include "output.h"
#include "progress.h"
#include "scenario.h"

namespace moreau::cli {
namespace {

using namespace moreau::control;

struct ControlArgs {
  std::string scenario;
  std::vector<std::string> overrides;
  std::string out;
  std::vector<int> study_steps;
};

// Constants of Theorem 5.1 for the study figure (optional).
struct TheoremConstants {
  double c1 = 0.0, c2 = 0.0, c3 = 0.0, delta = 0.0;
};

struct ControlScenario {
  std::string model;
  ProblemFamily family;
  int steps = 0;
  ContinuationOptions continuation;
  bool warm_start = false;
  int compare_samples = 0;
  std::optional<TheoremConstants> theorem;
  nlohmann::json settings;
};

nlohmann::json JsonNumber(double v) {
  return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
}

// Runs `f`, prefixing a library InputError ("key: reason") with the scenario file.
template <typename F>
auto WithFile(const Scenario& s, F&& f) {
  try {
    return f();
  } catch (const InputError& e) {
    throw InputError(fmt::format("{}: {}", s.path(), e.what()));
  }
}

// A number, an array of numbers, or an array of arrays of numbers inside a structured value.
double NodeNumber(const Scenario& s, const toml::node& node, const std::string& key) {
  if (auto v = node.value<double>()) {
    if (!std::isfinite(*v)) s.Fail(key, "must be a finite number");
    return *v;
  }
  s.Fail(key, "expected a number");
}

std::vector<double> NodeNumbers(const Scenario& s, const toml::node& node, const std::string& key) {
  const toml::array* arr = node.as_array();
  if (arr == nullptr) s.Fail(key, "expected an array of numbers");
  std::vector<double> out;
  std::size_t i = 0;
  for (const toml::node& item : *arr) {
    out.push_back(NodeNumber(s, item, fmt::format("{}[{}]", key, i++)));
  }
  return out;
}

Eigen::MatrixXd NodeMatrix(const Scenario& s, const toml::node& node, const std::string& key) {
  const toml::array* arr = node.as_array();
  if (arr == nullptr) s.Fail(key, "expected an array of frames (arrays of numbers)");
  std::vector<std::vector<double>> rows;
  for (const toml::node& item : *arr) {
    rows.push_back(NodeNumbers(s, item, fmt::format("{}[{}]", key, rows.size())));
  }
  const std::size_t cols = rows.empty() ? 0 : rows.front().size();
  Eigen::MatrixXd m(static_cast<Eigen::Index>(rows.size()), static_cast<Eigen::Index>(cols));
  for (std::size_t i = 0; i < rows.size(); ++i) {
    if (rows[i].size() != cols) {
      s.Fail(fmt::format("{}[{}]", key, i),
             fmt::format("reference of the wrong length: frame has {} values, frame 0 has {}",
                         rows[i].size(), cols));
    }
    for (std::size_t j = 0; j < cols; ++j) {
      m(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = rows[i][j];
    }
  }
  return m;
}

// Fails on any field of a table entry outside `allowed`.
void CheckFields(const Scenario& s, const toml::table& table, const std::string& key,
                 const std::set<std::string>& allowed) {
  for (const auto& [k, v] : table) {
    (void)v;
    if (allowed.count(std::string(k.str())) == 0) {
      s.Fail(fmt::format("{}.{}", key, k.str()), "unknown key");
    }
  }
}

const toml::table& EntryTable(const Scenario& s, const toml::node& node, const std::string& key) {
  if (node.is_table()) return static_cast<const toml::table&>(node);
  s.Fail(key, "expected a table");
}

SpringNetwork ReadNetwork(Scenario& s) {
  const int d = static_cast<int>(s.GetInt("network.dimension", 2));
  const toml::node* nodes_node = s.GetNode("network.nodes");
  const toml::node* springs_node = s.GetNode("network.springs");
  if (nodes_node == nullptr || nodes_node->as_array() == nullptr) {
    s.Fail("network.nodes", "required: an array of tables {mass, position, velocity, fixed}");
  }
  if (springs_node == nullptr || springs_node->as_array() == nullptr) {
    s.Fail("network.springs",
           "required: an array of tables {nodes, stiffness, damping, rest_min, rest_max}");
  }
  std::vector<NetworkNode> nodes;
  const toml::array& na = *nodes_node->as_array();
  std::size_t j = 0;
  for (const toml::node& item : na) {
    const std::string key = fmt::format("network.nodes[{}]", j++);
    const toml::table& t = EntryTable(s, item, key);
    CheckFields(s, t, key, {"mass", "position", "velocity", "fixed"});
    NetworkNode node;
    if (const toml::node* f = t.get("fixed")) {
      auto b = f->value<bool>();
      if (!b) s.Fail(key + ".fixed", "expected true or false");
      node.fixed = *b;
    }
    if (const toml::node* m = t.get("mass"))
      node.mass = NodeNumber(s, *m, key + ".mass");
    else if (!node.fixed)
      s.Fail(key + ".mass", "required for a free node");
    const toml::node* p = t.get("position");
    if (p == nullptr) s.Fail(key + ".position", "required key is missing");
    const std::vector<double> pos = NodeNumbers(s, *p, key + ".position");
    if (static_cast<int>(pos.size()) != d) {
      s.Fail(key + ".position",
             fmt::format("expected {} numbers (network.dimension), got {}", d, pos.size()));
    }
    for (int i = 0; i < d; ++i) node.position[i] = pos[static_cast<std::size_t>(i)];
    if (const toml::node* v = t.get("velocity")) {
      const std::vector<double> vel = NodeNumbers(s, *v, key + ".velocity");
      if (static_cast<int>(vel.size()) != d) {
        s.Fail(key + ".velocity", fmt::format("expected {} numbers, got {}", d, vel.size()));
      }
      for (int i = 0; i < d; ++i) node.velocity[i] = vel[static_cast<std::size_t>(i)];
    }
    nodes.push_back(node);
  }
  std::vector<NetworkSpring> springs;
  const toml::array& sa = *springs_node->as_array();
  std::size_t k = 0;
  for (const toml::node& item : sa) {
    const std::string key = fmt::format("network.springs[{}]", k++);
    const toml::table& t = EntryTable(s, item, key);
    CheckFields(s, t, key, {"nodes", "stiffness", "damping", "rest_min", "rest_max"});
    NetworkSpring sp;
    const toml::node* ends = t.get("nodes");
    if (ends == nullptr) s.Fail(key + ".nodes", "required key is missing");
    const std::vector<double> e = NodeNumbers(s, *ends, key + ".nodes");
    if (e.size() != 2 || e[0] != std::floor(e[0]) || e[1] != std::floor(e[1])) {
      s.Fail(key + ".nodes", "expected two node indices [a, b]");
    }
    sp.a = static_cast<int>(e[0]);
    sp.b = static_cast<int>(e[1]);
    auto number = [&](const char* field, double& out) {
      const toml::node* n = t.get(field);
      if (n == nullptr) s.Fail(fmt::format("{}.{}", key, field), "required key is missing");
      out = NodeNumber(s, *n, fmt::format("{}.{}", key, field));
    };
    number("stiffness", sp.stiffness);
    number("damping", sp.damping);
    number("rest_min", sp.rest_min);
    number("rest_max", sp.rest_max);
    springs.push_back(sp);
  }
  return WithFile(s, [&] { return SpringNetwork(d, std::move(nodes), std::move(springs)); });
}

CostWeights ReadCost(Scenario& s, CostWeights w) {
  w.position = s.GetDouble("cost.position", w.position);
  w.velocity = s.GetDouble("cost.velocity", w.velocity);
  w.terminal_position = s.GetDouble("cost.terminal_position", w.terminal_position);
  w.terminal_velocity = s.GetDouble("cost.terminal_velocity", w.terminal_velocity);
  return w;
}

ControlScenario ReadControlScenario(Scenario& s) {
  ControlScenario c;
  c.model = s.RequireString("model");
  nlohmann::json settings;
  settings["model"] = c.model;
  if (c.model == "oscillator") {
    OscillatorExample ex;
    ex.mass = s.GetDouble("oscillator.mass", ex.mass);
    ex.stiffness = s.GetDouble("oscillator.stiffness", ex.stiffness);
    ex.damping = s.GetDouble("oscillator.damping", ex.damping);
    ex.rest_min = s.GetDouble("oscillator.rest_min", ex.rest_min);
    ex.rest_max = s.GetDouble("oscillator.rest_max", ex.rest_max);
    ex.start = s.GetDouble("oscillator.start", ex.start);
    ex.target = s.GetDouble("oscillator.target", ex.target);
    ex.move_time = s.GetDouble("oscillator.move_time", ex.move_time);
    ex.horizon = s.GetDouble("problem.horizon", ex.horizon);
    ex.gamma = s.GetDouble("regularization.gamma", ex.gamma);
    const CostWeights w = ReadCost(s, CostWeights{ex.position_weight, ex.velocity_weight, 0, 0});
    if (w.terminal_position != 0.0 || w.terminal_velocity != 0.0) {
      s.Fail("cost.terminal_position", "the oscillator example has no terminal cost (g = 0)");
    }
    ex.position_weight = w.position;
    ex.velocity_weight = w.velocity;
    c.family = [ex](double p) { return MakeOscillatorProblem(ex, p); };
    settings["oscillator"] = {{"mass", ex.mass},         {"stiffness", ex.stiffness},
                              {"damping", ex.damping},   {"rest_min", ex.rest_min},
                              {"rest_max", ex.rest_max}, {"start", ex.start},
                              {"target", ex.target},     {"move_time", ex.move_time}};
  } else if (c.model == "arm") {
    ArmExample ex;
    ex.mass = s.GetDouble("arm.mass", ex.mass);
    ex.stiffness = s.GetDouble("arm.stiffness", ex.stiffness);
    ex.damping = s.GetDouble("arm.damping", ex.damping);
    ex.spring_limit = s.GetDouble("arm.spring_limit", ex.spring_limit);
    ex.upper_bone = s.GetDouble("arm.upper_bone", ex.upper_bone);
    ex.lower_bone = s.GetDouble("arm.lower_bone", ex.lower_bone);
    ex.elbow_half_width = s.GetDouble("arm.elbow_half_width", ex.elbow_half_width);
    ex.hand_half_width = s.GetDouble("arm.hand_half_width", ex.hand_half_width);
    const std::vector<double> anchor = s.GetDoubleArray("arm.anchor", {ex.anchor[0], ex.anchor[1]});
    if (anchor.size() != 2) s.Fail("arm.anchor", "expected two numbers [x, y]");
    ex.anchor = {anchor[0], anchor[1]};
    ex.angle_ab_deg = s.GetDouble("arm.angle_ab_deg", ex.angle_ab_deg);
    ex.angle_bc_deg = s.GetDouble("arm.angle_bc_deg", ex.angle_bc_deg);
    ex.angle_34_deg = s.GetDouble("arm.angle_34_deg", ex.angle_34_deg);
    ex.angle_12_deg = s.GetDouble("arm.angle_12_deg", ex.angle_12_deg);
    ex.periods = s.GetDouble("arm.periods", ex.periods);
    ex.horizon = s.GetDouble("problem.horizon", ex.horizon);
    ex.bounds_time = s.GetDouble("arm.bounds_time", 0.5 * ex.horizon);
    ex.gamma = s.GetDouble("regularization.gamma", ex.gamma);
    const CostWeights w = ReadCost(s, CostWeights{ex.position_weight, ex.velocity_weight, 0, 0});
    if (w.terminal_position != 0.0 || w.terminal_velocity != 0.0) {
      s.Fail("cost.terminal_position", "the arm example has no terminal cost (g = 0)");
    }
    ex.position_weight = w.position;
    ex.velocity_weight = w.velocity;
    c.family = [ex](double p) { return MakeArmProblem(ex, p); };
    settings["arm"] = {{"mass", ex.mass},
                       {"stiffness", ex.stiffness},
                       {"damping", ex.damping},
                       {"spring_limit", ex.spring_limit},
                       {"upper_bone", ex.upper_bone},
                       {"lower_bone", ex.lower_bone},
                       {"elbow_half_width", ex.elbow_half_width},
                       {"hand_half_width", ex.hand_half_width},
                       {"anchor", anchor},
                       {"angle_ab_deg", ex.angle_ab_deg},
                       {"angle_bc_deg", ex.angle_bc_deg},
                       {"angle_34_deg", ex.angle_34_deg},
                       {"angle_12_deg", ex.angle_12_deg},
                       {"periods", ex.periods},
                       {"bounds_time", ex.bounds_time}};
  } else if (c.model == "network") {
    SpringNetwork network = ReadNetwork(s);
    const double horizon = s.RequirePositive("problem.horizon", s.RequireDouble("problem.horizon"));
    const double gamma = s.GetDouble("regularization.gamma", 1e-4);
    const CostWeights w = ReadCost(s, CostWeights{});
    const toml::node* pos = s.GetNode("reference.positions");
    if (pos == nullptr) s.Fail("reference.positions", "required key is missing");
    Eigen::MatrixXd positions = NodeMatrix(s, *pos, "reference.positions");
    Eigen::MatrixXd velocities, weights;
    if (const toml::node* v = s.GetNode("reference.velocities")) {
      velocities = NodeMatrix(s, *v, "reference.velocities");
    }
    if (const toml::node* v = s.GetNode("reference.weights")) {
      weights = NodeMatrix(s, *v, "reference.weights");
    }
    TrackingProblem problem = WithFile(s, [&] {
      ReferenceFunction ref =
          SampledReference(network, horizon, std::move(positions), std::move(velocities),
                           std::move(weights), "reference");
      return TrackingProblem(network, horizon, std::move(ref), w, gamma);
    });
    c.family = LinearPathFamily(problem);
    settings["network"] = {{"dimension", network.dimension()},
                           {"nodes", network.num_nodes()},
                           {"springs", network.num_springs()}};
  } else {
    s.Fail("model",
           fmt::format("unknown model '{}' (expected oscillator, arm or network)", c.model));
  }
  const std::int64_t steps = s.GetInt("discretization.steps", 512);
  if (steps < 1 || steps > 100000000) {
    s.Fail("discretization.steps",
           fmt::format("must be >= 1 so that the time step T/N is positive (got {})", steps));
  }
  c.steps = static_cast<int>(steps);

  ContinuationOptions& co = c.continuation;
  co.path_start = s.GetDouble("continuation.path_start", co.path_start);
  co.path_increase = s.GetDouble("continuation.path_increase", co.path_increase);
  co.stiffness_start = s.GetDouble("continuation.stiffness_start", co.stiffness_start);
  co.stiffness_increase = s.GetDouble("continuation.stiffness_increase", co.stiffness_increase);
  co.gamma_start = s.GetDouble("continuation.gamma_start", co.gamma_start);
  co.gamma_decrease = s.GetDouble("continuation.gamma_decrease", co.gamma_decrease);
  co.min_increase = s.GetDouble("continuation.min_increase", co.min_increase);
  co.max_solves = static_cast<int>(s.GetInt("continuation.max_solves", co.max_solves));
  co.fixed_point.sweeps = static_cast<int>(s.GetInt("fixed_point.sweeps", co.fixed_point.sweeps));
  co.fixed_point.damping = s.GetDouble("fixed_point.damping", co.fixed_point.damping);
  co.fixed_point.tolerance = s.GetDouble("fixed_point.tolerance", co.fixed_point.tolerance);
  co.newton.max_iterations =
      static_cast<int>(s.GetInt("newton.max_iterations", co.newton.max_iterations));
  co.newton.residual_tolerance =
      s.GetDouble("newton.residual_tolerance", co.newton.residual_tolerance);
  co.newton.armijo = s.GetDouble("newton.armijo", co.newton.armijo);
  co.newton.min_step = s.GetDouble("newton.min_step", co.newton.min_step);
  co.newton.divergence_threshold =
      s.GetDouble("newton.divergence_threshold", co.newton.divergence_threshold);
  const std::string solver = s.GetString("newton.linear_solver", "riccati");
  WithFile(s, [&] {
    co.newton.linear_solver = ParseLinearSolverType(solver, "newton.linear_solver");
    co.Validate();
    return 0;
  });
  c.warm_start = s.GetBool("study.warm_start", false);
  c.compare_samples = static_cast<int>(s.GetInt("study.compare_samples", 0));
  if (c.compare_samples < 0) s.Fail("study.compare_samples", "must be >= 0");
  if (s.Has("study.theorem")) {
    TheoremConstants tc;
    tc.c1 = s.RequireDouble("study.theorem.c1");
    tc.c2 = s.RequireDouble("study.theorem.c2");
    tc.c3 = s.GetDouble("study.theorem.c3", 0.0);
    tc.delta = s.RequireDouble("study.theorem.delta");
    c.theorem = tc;
  }
  // Build the target problem now so that every model error surfaces before any output.
  const TrackingProblem target = WithFile(s, [&] { return c.family(1.0); });
  (void)WithFile(s, [&] { return PontryaginDiscretization(target, c.steps).steps(); });

  settings["horizon"] = target.horizon();
  settings["gamma"] = target.gamma();
  settings["delta"] = target.RegularizationDelta();
  settings["cost"] = {{"position", target.weights().position},
                      {"velocity", target.weights().velocity},
                      {"terminal_position", target.weights().terminal_position},
                      {"terminal_velocity", target.weights().terminal_velocity}};
  settings["steps"] = c.steps;
  settings["continuation"] = {
      {"path_start", co.path_start},           {"path_increase", co.path_increase},
      {"stiffness_start", co.stiffness_start}, {"stiffness_increase", co.stiffness_increase},
      {"gamma_start", co.gamma_start},         {"gamma_decrease", co.gamma_decrease},
      {"min_increase", co.min_increase},       {"max_solves", co.max_solves}};
  settings["fixed_point"] = {{"sweeps", co.fixed_point.sweeps},
                             {"damping", co.fixed_point.damping},
                             {"tolerance", co.fixed_point.tolerance}};
  settings["newton"] = {{"max_iterations", co.newton.max_iterations},
                        {"residual_tolerance", co.newton.residual_tolerance},
                        {"linear_solver", ToString(co.newton.linear_solver)},
                        {"armijo", co.newton.armijo},
                        {"min_step", co.newton.min_step},
                        {"divergence_threshold", co.newton.divergence_threshold}};
  c.settings = std::move(settings);
  return c;
}

nlohmann::json PathJson(const std::vector<ContinuationRecord>& path) {
  nlohmann::json arr = nlohmann::json::array();
  for (const auto& r : path) {
    arr.push_back({{"stage", r.stage},
                   {"path_fraction", r.path_fraction},
                   {"stiffness_scale", r.stiffness_scale},
                   {"gamma", r.gamma},
                   {"accepted", r.accepted},
                   {"newton_iterations", r.newton_iterations},
                   {"residual_norm", JsonNumber(r.residual)},
                   {"termination", r.termination}});
  }
  return arr;
}

std::string TrajectoryCsv(const PontryaginDiscretization& disc, const Eigen::MatrixXd& z) {
  const SpringNetwork& net = disc.problem().network();
  const int d = net.dimension();
  fmt::memory_buffer b;
  fmt::format_to(std::back_inserter(b), "t");
  for (int j = 0; j < net.num_nodes(); ++j) {
    for (int i = 0; i < d; ++i) fmt::format_to(std::back_inserter(b), ",node{}_x{}", j, i);
  }
  for (int j = 0; j < net.num_nodes(); ++j) {
    if (net.free_index(j) < 0) continue;
    for (int i = 0; i < d; ++i) fmt::format_to(std::back_inserter(b), ",node{}_v{}", j, i);
  }
  for (int j = 0; j < net.num_nodes(); ++j) {
    if (net.free_index(j) < 0) continue;
    for (int i = 0; i < d; ++i) fmt::format_to(std::back_inserter(b), ",ref{}_x{}", j, i);
    fmt::format_to(std::back_inserter(b), ",ref{}_w", j);
  }
  fmt::format_to(std::back_inserter(b), "\n");
  for (int n = 0; n <= disc.steps(); ++n) {
    const Instant& in = disc.instant(n);
    fmt::format_to(std::back_inserter(b), "{:.17g}", in.t);
    for (int j = 0; j < net.num_nodes(); ++j) {
      const int k = net.free_index(j);
      for (int i = 0; i < d; ++i) {
        const double x = k < 0 ? in.fixed_position[d * j + i] : z(2 * d * k + i, n);
        fmt::format_to(std::back_inserter(b), ",{:.17g}", x);
      }
    }
    for (int k = 0; k < net.num_free(); ++k) {
      for (int i = 0; i < d; ++i) {
        fmt::format_to(std::back_inserter(b), ",{:.17g}", z(2 * d * k + d + i, n));
      }
    }
    for (int k = 0; k < net.num_free(); ++k) {
      for (int i = 0; i < d; ++i) {
        fmt::format_to(std::back_inserter(b), ",{:.17g}", in.ref_position[d * k + i]);
      }
      fmt::format_to(std::back_inserter(b), ",{:.17g}", in.ref_weight[k]);
    }
    fmt::format_to(std::back_inserter(b), "\n");
  }
  return fmt::to_string(b);
}

std::string ControlsCsv(const PontryaginDiscretization& disc, const Eigen::MatrixXd& controls) {
  const SpringNetwork& net = disc.problem().network();
  fmt::memory_buffer b;
  fmt::format_to(std::back_inserter(b), "t");
  for (int s = 0; s < net.num_springs(); ++s) {
    fmt::format_to(std::back_inserter(b), ",spring{}_{}_{}", s, net.spring(s).a, net.spring(s).b);
  }
  fmt::format_to(std::back_inserter(b), "\n");
  for (int n = 0; n < disc.steps(); ++n) {
    fmt::format_to(std::back_inserter(b), "{:.17g}", disc.instant(n).t);
    for (int s = 0; s < net.num_springs(); ++s) {
      fmt::format_to(std::back_inserter(b), ",{:.17g}", controls(s, n));
    }
    fmt::format_to(std::back_inserter(b), "\n");
  }
  return fmt::to_string(b);
}

std::string BoundsCsvRow(const std::optional<TheoremConstants>& tc, double horizon, double dt) {
  if (!tc) return ",,";
  // Theorem 5.1: lower <= u − ū <= upper.
  const double e = std::exp(tc->c2 * horizon);
  const double lower = -0.5 * tc->c1 * tc->c2 * horizon * ((e - 1.0) * dt + dt * dt) -
                       0.5 * tc->c1 * tc->c3 * (e - 1.0) * dt - horizon * tc->delta;
  const double upper =
      0.5 * tc->c1 * tc->c2 * (tc->c3 + 1.0) * e * horizon * dt + horizon * tc->delta;
  return fmt::format(",{:.17g},{:.17g}", lower, upper);
}

int RunSingle(const ControlArgs& args, const ControlScenario& c) {
  const auto start = std::chrono::steady_clock::now();
  const TrackingProblem target = c.family(1.0);
  const PontryaginDiscretization disc(target, c.steps);
  OutputDir out(
      args.out.empty()
          ? (std::filesystem::path("out") / std::filesystem::path(args.scenario).stem()).string()
          : args.out);
  Eigen::VectorXd y;
  const ContinuationSummary cs = SolveWithContinuation(c.family, c.steps, c.continuation, y);
  // y belongs to the last accepted problem; evaluate it on the target (its residual says whether
  // it solves the target).
  PontryaginWorkspace ws;
  Eigen::VectorXd residual;
  const double residual_norm = EvaluateResidual(disc, y, ws, residual);
  const double value = DiscreteValue(disc, y, ws);
  Eigen::MatrixXd z, rho;
  disc.Unpack(y, z, rho);
  const Eigen::MatrixXd controls = EffectiveControls(disc, y);
  const double rms = TrackingRms(disc, z);
  const double wall =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  nlohmann::json j;
  j["converged"] = cs.converged;
  j["termination"] = cs.converged ? "converged" : ToString(cs.last_newton.termination);
  j["message"] = cs.converged ? "" : cs.message;
  j["value"] = JsonNumber(value);
  j["newton_iterations"] = cs.newton_iterations;
  j["newton_solves"] = cs.newton_solves;
  j["final_newton_iterations"] = cs.last_newton.iterations;
  j["residual_norm"] = JsonNumber(residual_norm);
  j["residual_history"] = cs.last_newton.residual_norms;
  j["wall_seconds"] = wall;
  j["time_residual_jacobian"] = cs.last_newton.time_residual_jacobian;
  j["time_factorize"] = cs.last_newton.time_factorize;
  j["time_solve"] = cs.last_newton.time_solve;
  j["time_line_search"] = cs.last_newton.time_line_search;
  j["steps"] = c.steps;
  j["dt"] = disc.dt();
  j["tracking_rms"] = rms;
  j["delta"] = target.RegularizationDelta();
  j["reached"] = {{"path_fraction", cs.path_fraction},
                  {"stiffness_scale", cs.stiffness_scale},
                  {"gamma", cs.gamma}};
  j["continuation_path"] = PathJson(cs.path);
  j["settings"] = c.settings;
  j["scenario_file"] = args.scenario;
  out.WriteText("summary.json", j.dump(2) + "\n");
  out.WriteText("trajectory.csv", TrajectoryCsv(disc, z));
  out.WriteText("controls.csv", ControlsCsv(disc, controls));
  RunPlotScript("plot_control.py", {"run", out.Stage("trajectory.png").string(),
                                    out.StagedPath("trajectory.csv").string(),
                                    out.StagedPath("controls.csv").string()});
  out.Commit();
  std::printf("%s\n", cs.BriefReport().c_str());
  std::printf("value %.12g, residual %.3e, tracking RMS %.3e, %d steps, %.2f s\n", value,
              residual_norm, rms, c.steps, wall);
  std::printf("wrote %s/summary.json, trajectory.csv, controls.csv, trajectory.png\n",
              out.dir().c_str());
  if (!cs.converged) {
    std::fprintf(stderr, "moreau: control did not converge: %s\n", cs.message.c_str());
    return 3;
  }
  return 0;
}

int RunStudyCommand(const ControlArgs& args, const ControlScenario& c) {
  const auto start = std::chrono::steady_clock::now();
  StudyOptions so;
  so.steps = args.study_steps;
  so.continuation = c.continuation;
  so.warm_start = c.warm_start;
  so.compare_samples = c.compare_samples;
  try {
    so.Validate();
  } catch (const InputError& e) {
    throw InputError(fmt::format("--study-steps: {}", e.what()));
  }
  OutputDir out(args.out.empty()
                    ? (std::filesystem::path("out") /
                       (std::filesystem::path(args.scenario).stem().string() + "_study"))
                          .string()
                    : args.out);
  std::vector<StudyLevel> levels;
  ProgressBar progress("control study", static_cast<std::int64_t>(so.steps.size()));
  std::int64_t done = 0;
  so.on_level = [&](const StudyLevel&) { progress.Update(++done); };
  levels = RunStudy(c.family, so);
  progress.Finish();
  const TrackingProblem target = c.family(1.0);
  const double horizon = target.horizon();
  const double u_finest = levels.back().value;
  fmt::memory_buffer b;
  fmt::format_to(std::back_inserter(b),
                 "steps,dt,converged,value,value_minus_finest,residual_norm,newton_iterations,"
                 "newton_total,wall_seconds,diff_previous,diff_finest,tracking_rms,bound_lower,"
                 "bound_upper\n");
  nlohmann::json jl = nlohmann::json::array();
  bool all = true;
  for (const StudyLevel& l : levels) {
    const double dt = horizon / l.steps;
    all = all && l.converged;
    fmt::format_to(
        std::back_inserter(b), "{},{:.17g},{},{:.17g},{:.17g},{:.6e},{},{},{:.6f},{},{},{:.6e}{}\n",
        l.steps, dt, l.converged ? 1 : 0, l.value, u_finest - l.value, l.residual,
        l.newton_iterations, l.newton_total, l.wall_seconds,
        std::isfinite(l.diff_previous) ? fmt::format("{:.6e}", l.diff_previous) : "",
        fmt::format("{:.6e}", l.diff_finest), l.tracking_rms, BoundsCsvRow(c.theorem, horizon, dt));
    jl.push_back({{"steps", l.steps},
                  {"converged", l.converged},
                  {"message", l.message},
                  {"value", JsonNumber(l.value)},
                  {"residual_norm", JsonNumber(l.residual)},
                  {"newton_iterations", l.newton_iterations},
                  {"newton_total", l.newton_total},
                  {"wall_seconds", l.wall_seconds},
                  {"diff_previous", JsonNumber(l.diff_previous)},
                  {"diff_finest", JsonNumber(l.diff_finest)},
                  {"tracking_rms", l.tracking_rms}});
  }
  const double wall =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  nlohmann::json j;
  j["converged"] = all;
  j["value"] = JsonNumber(u_finest);
  j["newton_iterations"] = levels.back().newton_iterations;
  j["residual_norm"] = JsonNumber(levels.back().residual);
  j["wall_seconds"] = wall;
  j["steps"] = so.steps;
  j["levels"] = jl;
  if (c.theorem) {
    j["theorem"] = {{"c1", c.theorem->c1},
                    {"c2", c.theorem->c2},
                    {"c3", c.theorem->c3},
                    {"delta", c.theorem->delta}};
  }
  j["settings"] = c.settings;
  j["scenario_file"] = args.scenario;
  out.WriteText("summary.json", j.dump(2) + "\n");
  out.WriteText("convergence.csv", fmt::to_string(b));
  // The finest trajectory and controls, as for a single run.
  {
    const PontryaginDiscretization disc(target, levels.back().steps);
    out.WriteText("trajectory.csv", TrajectoryCsv(disc, levels.back().z));
    out.WriteText("controls.csv", ControlsCsv(disc, levels.back().controls));
  }
  RunPlotScript("plot_control.py", {"study", out.Stage("value_vs_steps.png").string(),
                                    out.Stage("difference_vs_steps.png").string(),
                                    out.StagedPath("convergence.csv").string()});
  out.Commit();
  std::printf("%-8s %-10s %-22s %-12s %-12s %-12s %-10s\n", "N", "converged", "value", "residual",
              "diff_prev", "diff_finest", "rms");
  for (const StudyLevel& l : levels) {
    std::printf("%-8d %-10s %-22.15g %-12.3e %-12.3e %-12.3e %-10.3e\n", l.steps,
                l.converged ? "yes" : "no", l.value, l.residual, l.diff_previous, l.diff_finest,
                l.tracking_rms);
  }
  std::printf(
      "wrote %s/summary.json, convergence.csv, value_vs_steps.png, "
      "difference_vs_steps.png\n",
      out.dir().c_str());
  if (!all) {
    std::fprintf(stderr, "moreau: some levels of the study did not converge\n");
    return 3;
  }
  return 0;
}

int Control(const ControlArgs& args) {
  Scenario scenario = Scenario::Load(args.scenario, args.overrides);
  const ControlScenario c = ReadControlScenario(scenario);
  scenario.CheckAllKeysUsed();
  if (!args.study_steps.empty()) return RunStudyCommand(args, c);
  return RunSingle(args, c);
}

}  // namespace

void AddControlCommand(CLI::App& app) {
  auto args = std::make_shared<ControlArgs>();
  CLI::App* cmd = app.add_subcommand(
      "control", "Optimal control of a spring network (Symplectic Pontryagin + Newton)");
  cmd->add_option("scenario", args->scenario, "Scenario file (TOML)")->required();
  cmd->add_option("--set", args->overrides, "Override a scenario value: key=value (repeatable)");
  cmd->add_option("--out", args->out, "Output folder (default out/<scenario name>)");
  cmd->add_option("--study-steps", args->study_steps,
                  "Grid-refinement study over these numbers of steps N (comma separated)")
      ->delimiter(',');
  cmd->callback([args] {
    const int code = Control(*args);
    if (code != 0) throw CLI::RuntimeError(code);
  });
}

}  // namespace moreau::cli
