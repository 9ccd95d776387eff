#include "run/pbd_scenario.h"

#include <cmath>
#include <numbers>

#include <fmt/format.h>

#include "moreau/common/error.h"
#include "moreau/common/memory.h"
#include "moreau/common/steps.h"

namespace moreau::cli {
namespace {

FieldTable<pbd::SlidingCase> SlidingFields() {
  using C = pbd::SlidingCase;
  FieldTable<C> t;
  t.Integer("dimension", &C::dimension, Range::Closed(3, 1000), "dimension d")
      .Number("C", &C::C, Range::Positive(), "distance of the ball centres from the plane")
      .Number("alpha", &C::alpha, Range::Open(0.0, std::numbers::pi), "initial angle from e_2")
      .Number("T", &C::T, Range::Positive(), "final time");
  return t;
}

FieldTable<pbd::DisksCase> DisksFields() {
  using C = pbd::DisksCase;
  FieldTable<C> t;
  t.Integer("count", &C::count,
            Range::Closed(1, kMaxAllPairsDisks)
                .Because("(the disks case places and checks all N²/2 pairs; "
                         "problem.kind = \"particles\" has cell lists for more)"),
            "number of disks N")
      .Number("radius", &C::radius, Range::Positive(), "disk radius R")
      .Number("gamma", &C::gamma, Range::Any(), "attraction to the origin γ")
      .Number("T", &C::T, Range::Positive(), "final time")
      .Integer("seed", &C::seed, Range::NonNegative(), "seed of the random start")
      .OptionalNumber("wall", &C::wall, Range::Any(), "the line y = wall (none if absent)")
      .Number("box", &C::box, Range::NonNegative(), "half-width of the start box (0: automatic)")
      .Check("box", [](const C& c) {
        if (c.box > 0.0 && c.box < c.radius) throw InputError("is smaller than the radius");
      });
  return t;
}

void ReadDiskPositions(Scenario& s, PbdScenario& out, const std::string& key) {
  const toml::node* node = s.GetNode(key);
  if (node == nullptr) return;
  const int n = out.disks.count;
  const toml::array* rows = node->as_array();
  if (rows == nullptr || static_cast<int>(rows->size()) != n) {
    s.Fail(key, fmt::format("expected an array of {} [x, y] pairs", n));
  }
  pbd::Vector x(2 * n);
  for (int i = 0; i < n; ++i) {
    const toml::array* xy = (*rows)[static_cast<std::size_t>(i)].as_array();
    if (xy == nullptr || xy->size() != 2 || !(*xy)[0].value<double>() ||
        !(*xy)[1].value<double>()) {
      s.Fail(key, fmt::format("entry {} is not an [x, y] pair of numbers", i));
    }
    x[2 * i] = *(*xy)[0].value<double>();
    x[2 * i + 1] = *(*xy)[1].value<double>();
  }
  if (!x.allFinite()) s.Fail(key, "entries must be finite");
  out.positions = x;
}

// The initial state must be feasible: no overlapping pair, no disk across the wall.
void CheckNoOverlap(const PbdScenario& s) {
  const pbd::DisksCase& c = s.disks;
  const pbd::Vector x0 = s.InitialState();
  const double tol = 1e-12 * std::max(1.0, c.radius);
  for (int i = 0; i < c.count; ++i) {
    for (int j = i + 1; j < c.count; ++j) {
      const double overlap = 2.0 * c.radius - (x0.segment<2>(2 * i) - x0.segment<2>(2 * j)).norm();
      if (overlap > tol) {
        throw InputError(fmt::format("infeasible initial state: disks {} and {} overlap by {:.3g}",
                                     i, j, overlap));
      }
    }
  }
}

void CheckAboveWall(const PbdScenario& s) {
  const pbd::DisksCase& c = s.disks;
  if (!c.wall) return;
  const pbd::Vector x0 = s.InitialState();
  const double tol = 1e-12 * std::max(1.0, c.radius);
  for (int i = 0; i < c.count; ++i) {
    if (x0[2 * i + 1] < *c.wall + c.radius - tol) {
      throw InputError(fmt::format("infeasible initial state: disk {} crosses the wall", i));
    }
  }
}

// The run keeps its frames in memory and writes them as CSV text (about 25 bytes a number).
void CheckTrajectorySize(const PbdScenario& s) {
  const std::int64_t frames = CheckFrameCount(StepCount(s.T(), s.solver.h), s.stride());
  const double numbers = static_cast<double>(s.InitialStateSize()) + 1.0;
  CheckMemory(fmt::format("{} frames of the trajectory", frames),
              static_cast<double>(frames) * numbers * (8.0 + 25.0));
}

FieldTable<PbdScenario> MakePbdFields(const std::string& kind) {
  using PD = PbdScenario;
  FieldTable<PD> t;
  t.Text("problem.kind", &PD::kind, "sliding, disks (or particles: see docs/particles.md)")
      .Required();
  if (kind == "sliding") {
    t.Mount("problem", &PD::sliding, SlidingFields());
  } else {
    t.Mount("problem", &PD::disks, DisksFields())
        .Custom("problem.positions", "array of [x, y]", ReadDiskPositions, {},
                "initial positions (default: random sequential addition from the seed)")
        .Check("problem.positions", CheckNoOverlap)
        .Check("problem.wall", CheckAboveWall);
  }
  t.Mount("solver", &PD::solver, pbd::StepperOptions::Fields())
      .Check("solver.h", [](const PD& s) { (void)StepCount(s.T(), s.solver.h); })
      .Mount("reference", &PD::reference, pbd::StepperOptions::Fields())
      .Flag("reference.compute", &PD::reference_for_run, "disks: error against a reference in run")
      .Check("reference.h",
             [](const PD& s) {
               if (!s.reference_for_run) return;
               (void)StepCount(s.T(), s.reference.h);  // "T / h must be …" with this T
               try {
                 (void)StepCount(s.solver.h, s.reference.h);
               } catch (const InputError&) {
                 throw InputError(fmt::format(
                     "must divide solver.h = {} into a whole number of steps (got {})",
                     s.solver.h, s.reference.h));
               }
             })
      .Integer("output.stride", &PD::output_stride, Range::NonNegative(),
               "write every stride-th step (0: about 1000 frames)")
      .Check("output.stride", CheckTrajectorySize);
  return t;
}

}  // namespace

pbd::StepperOptions ReferenceSolverDefaults() {
  pbd::StepperOptions ref;
  ref.method = pbd::Method::kPNGS;
  ref.h = 1e-5;
  ref.reltol = 1e-10;
  ref.abstol = 1e-12;
  ref.max_sweeps = 100000;
  return ref;
}

const FieldTable<PbdScenario>& PbdFields(const std::string& kind) {
  static const FieldTable<PbdScenario> sliding = MakePbdFields("sliding");
  static const FieldTable<PbdScenario> disks = MakePbdFields("disks");
  return kind == "sliding" ? sliding : disks;
}

PbdScenario ReadPbdScenario(Scenario& s) {
  PbdScenario out;
  out.kind = s.RequireString("problem.kind");
  if (out.kind != "sliding" && out.kind != "disks") {
    s.Fail("problem.kind",
           fmt::format("unknown kind '{}' (expected sliding, disks or particles)", out.kind));
  }
  PbdFields(out.kind).Read(s, out);
  return out;
}

nlohmann::json EchoPbdScenario(const PbdScenario& scenario) {
  return PbdFields(scenario.kind).Echo(scenario);
}

std::int64_t PbdScenario::stride() const {
  return output_stride > 0 ? output_stride
                           : std::max<std::int64_t>(1, StepCount(T(), solver.h) / 1000);
}

pbd::Vector PbdScenario::InitialState() const {
  if (!is_disks()) return sliding.InitialState();
  if (positions) return *positions;
  return disks.InitialState();
}

std::unique_ptr<pbd::ParticleConstraints> PbdScenario::MakeParticleConstraints() const {
  return std::make_unique<pbd::ParticleConstraints>(disks.MakeModel());
}

pbd::StudyProblem PbdScenario::MakeProblem() const {
  pbd::StudyProblem p;
  p.x0 = InitialState();
  p.T = T();
  if (!is_disks()) {
    const pbd::SlidingCase c = sliding;
    p.constraints = std::make_shared<pbd::CaseConstraintModel<pbd::SlidingCase>>(c);
    p.drift = c.MakeDrift();
    p.solution = [c](double t) { return c.ExactSolution(t); };
  } else {
    p.constraints = std::make_shared<pbd::ParticleSystemModel>(
        std::make_shared<const particles::ParticleModel>(disks.MakeModel()));
    p.drift = disks.MakeDrift();
  }
  return p;
}

}  // namespace moreau::cli
