#include "pbd_scenario.h"

#include <cmath>
#include <numbers>
#include <fmt/format.h>

#include "moreau/common/error.h"

namespace moreau::cli {
namespace {

// Runs `check` and re-throws its InputError as "FILE: KEY: REASON".
template <class Fn>
void WithKey(const Scenario& s, std::string_view key, Fn&& check) {
  try {
    check();
  } catch (const InputError& e) {
    s.Fail(key, e.what());
  }
}

pbd::StepperOptions ReadSolver(Scenario& s, const std::string& table, pbd::StepperOptions o) {
  const std::string p = table + ".";
  if (s.Has(p + "method")) {
    WithKey(s, p + "method", [&] { o.method = pbd::ParseMethod(s.GetString(p + "method", "")); });
  }
  o.h = s.GetDouble(p + "h", o.h);
  if (!(o.h > 0.0)) s.Fail(p + "h", fmt::format("must be > 0 (got {})", o.h));
  o.abstol = s.GetDouble(p + "abstol", o.abstol);
  if (!(o.abstol >= 0.0)) s.Fail(p + "abstol", fmt::format("must be ≥ 0 (got {})", o.abstol));
  o.reltol = s.GetDouble(p + "reltol", o.reltol);
  if (!(o.reltol >= 0.0)) s.Fail(p + "reltol", fmt::format("must be ≥ 0 (got {})", o.reltol));
  if (o.abstol == 0.0 && o.reltol == 0.0) s.Fail(p + "reltol", "abstol and reltol are both 0");
  const std::int64_t sweeps = s.GetInt(p + "max_sweeps", o.max_sweeps);
  if (sweeps < 1 || sweeps > 1'000'000'000) {
    s.Fail(p + "max_sweeps", fmt::format("must be in [1, 1e9] (got {})", sweeps));
  }
  o.max_sweeps = static_cast<int>(sweeps);
  o.penalty = s.GetDouble(p + "penalty", o.penalty);
  if (!(o.penalty > 0.0)) s.Fail(p + "penalty", fmt::format("must be > 0 (got {})", o.penalty));
  return o;
}

}  // namespace

PbdScenario ReadPbdScenario(Scenario& s) {
  PbdScenario out;
  out.kind = s.RequireString("problem.kind");
  if (out.kind == "sliding") {
    pbd::SlidingCase c;
    const std::int64_t d = s.GetInt("problem.dimension", c.dimension);
    if (d < 3 || d > 1000) s.Fail("problem.dimension", fmt::format("must be in [3, 1000] (got {})", d));
    c.dimension = static_cast<int>(d);
    c.C = s.RequirePositive("problem.C", s.GetDouble("problem.C", c.C));
    c.alpha = s.GetDouble("problem.alpha", c.alpha);
    if (!(c.alpha > 0.0 && c.alpha < std::numbers::pi)) {
      s.Fail("problem.alpha", fmt::format("must be in (0, π) (got {})", c.alpha));
    }
    c.T = s.RequirePositive("problem.T", s.GetDouble("problem.T", c.T));
    out.sliding = c;
  } else if (out.kind == "disks") {
    pbd::DisksCase c;
    const std::int64_t n = s.GetInt("problem.count", c.count);
    if (n < 1 || n > 100'000'000) s.Fail("problem.count", fmt::format("must be in [1, 1e8] (got {})", n));
    c.count = static_cast<int>(n);
    c.radius = s.RequirePositive("problem.radius", s.GetDouble("problem.radius", c.radius));
    c.gamma = s.GetDouble("problem.gamma", c.gamma);
    c.T = s.RequirePositive("problem.T", s.GetDouble("problem.T", c.T));
    const std::int64_t seed = s.GetInt("problem.seed", static_cast<std::int64_t>(c.seed));
    if (seed < 0) s.Fail("problem.seed", "must be ≥ 0");
    c.seed = static_cast<std::uint64_t>(seed);
    c.wall = s.GetOptionalDouble("problem.wall");
    c.box = s.GetDouble("problem.box", c.box);
    if (!(c.box >= 0.0)) s.Fail("problem.box", fmt::format("must be ≥ 0 (got {})", c.box));
    if (c.box > 0.0 && c.box < c.radius) s.Fail("problem.box", "is smaller than the radius");
    if (const toml::node* node = s.GetNode("problem.positions")) {
      const toml::array* rows = node->as_array();
      if (rows == nullptr || static_cast<int>(rows->size()) != c.count) {
        s.Fail("problem.positions", fmt::format("expected an array of {} [x, y] pairs", c.count));
      }
      pbd::Vector x(2 * c.count);
      for (int i = 0; i < c.count; ++i) {
        const toml::array* xy = (*rows)[static_cast<std::size_t>(i)].as_array();
        if (xy == nullptr || xy->size() != 2 || !(*xy)[0].value<double>() || !(*xy)[1].value<double>()) {
          s.Fail("problem.positions", fmt::format("entry {} is not an [x, y] pair of numbers", i));
        }
        x[2 * i] = *(*xy)[0].value<double>();
        x[2 * i + 1] = *(*xy)[1].value<double>();
      }
      if (!x.allFinite()) s.Fail("problem.positions", "entries must be finite");
      out.positions = x;
    }
    out.disks = c;
    // The initial state must be feasible.
    const pbd::Vector x0 = out.InitialState();
    const particles::ParticleModel model = c.MakeModel();
    const double tol = 1e-12 * std::max(1.0, c.radius);
    for (int i = 0; i < c.count; ++i) {
      for (int j = i + 1; j < c.count; ++j) {
        const double overlap = 2.0 * c.radius - (x0.segment<2>(2 * i) - x0.segment<2>(2 * j)).norm();
        if (overlap > tol) {
          s.Fail("problem.positions", fmt::format("infeasible initial state: disks {} and {} overlap by {:.3g}", i, j, overlap));
        }
      }
      if (c.wall && x0[2 * i + 1] < *c.wall + c.radius - tol) {
        s.Fail("problem.wall", fmt::format("infeasible initial state: disk {} crosses the wall", i));
      }
    }
  } else {
    s.Fail("problem.kind", fmt::format("unknown kind '{}' (expected sliding, disks or particles)", out.kind));
  }

  out.solver = ReadSolver(s, "solver", pbd::StepperOptions{});
  WithKey(s, "solver.h", [&] { (void)StepCount(out.T(), out.solver.h); });

  pbd::StepperOptions ref;
  ref.method = pbd::Method::kPNGS;
  ref.h = 1e-5;
  ref.reltol = 1e-10;
  ref.abstol = 1e-12;
  ref.max_sweeps = 100000;
  out.reference = ReadSolver(s, "reference", ref);
  out.reference_for_run = s.GetBool("reference.compute", false);
  out.output_stride = s.GetInt("output.stride", 0);
  if (out.output_stride < 0) s.Fail("output.stride", "must be ≥ 0");
  return out;
}

pbd::Vector PbdScenario::InitialState() const {
  if (sliding) return sliding->InitialState();
  if (positions) return *positions;
  return disks->InitialState();
}

pbd::StudyProblem PbdScenario::MakeProblem() const {
  pbd::StudyProblem p;
  p.x0 = InitialState();
  p.T = T();
  if (sliding) {
    const pbd::SlidingCase c = *sliding;
    p.constraints = std::make_shared<pbd::CaseConstraintModel<pbd::SlidingCase>>(c);
    p.drift = c.MakeDrift();
    p.solution = [c](double t) { return c.ExactSolution(t); };
  } else {
    p.constraints = std::make_shared<pbd::ParticleSystemModel>(
        std::make_shared<const particles::ParticleModel>(disks->MakeModel()));
    p.drift = disks->MakeDrift();
  }
  return p;
}

nlohmann::json PbdScenario::ToJson() const {
  nlohmann::json j;
  j["problem"]["kind"] = kind;
  if (sliding) {
    j["problem"]["dimension"] = sliding->dimension;
    j["problem"]["C"] = sliding->C;
    j["problem"]["alpha"] = sliding->alpha;
    j["problem"]["T"] = sliding->T;
  } else {
    j["problem"]["count"] = disks->count;
    j["problem"]["radius"] = disks->radius;
    j["problem"]["gamma"] = disks->gamma;
    j["problem"]["T"] = disks->T;
    j["problem"]["seed"] = disks->seed;
    j["problem"]["box"] = disks->box_half_width();
    if (disks->wall) j["problem"]["wall"] = *disks->wall;
    j["reference"] = {{"method", pbd::MethodName(reference.method)},
                      {"h", reference.h},
                      {"abstol", reference.abstol},
                      {"reltol", reference.reltol},
                      {"max_sweeps", reference.max_sweeps}};
  }
  j["solver"] = {{"method", pbd::MethodName(solver.method)}, {"h", solver.h},
                 {"abstol", solver.abstol},                  {"reltol", solver.reltol},
                 {"max_sweeps", solver.max_sweeps},          {"penalty", solver.penalty}};
  return j;
}

}  // namespace moreau::cli
