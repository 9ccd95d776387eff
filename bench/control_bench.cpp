// Time per Newton iteration of the Symplectic Pontryagin solver on the arm model (thesis 9.2),
// N = 512 … 16384: the structure-exploiting Riccati solve against Eigen SparseLU (factorise +
// solve of the same Jacobian), and the residual + Jacobian evaluation for scale.
//
//   build/release/control_bench --benchmark_counters_tabular=true
#include <benchmark/benchmark.h>

#include <map>
#include <memory>

#include "moreau/control/continuation.h"
#include "moreau/control/examples.h"
#include "moreau/control/linear_solver.h"
#include "moreau/control/newton.h"

namespace {

using namespace moreau::control;

// The Jacobian at the fixed-point initial guess of the arm problem with N steps (built once).
struct ArmSystem {
  std::unique_ptr<PontryaginDiscretization> disc;
  PontryaginWorkspace ws;
  Eigen::VectorXd y, residual;
};

ArmSystem& GetArmSystem(int steps) {
  static std::map<int, std::unique_ptr<ArmSystem>> cache;
  auto& slot = cache[steps];
  if (!slot) {
    slot = std::make_unique<ArmSystem>();
    static const TrackingProblem problem = MakeArmProblem(ArmExample{}, 1.0);
    slot->disc = std::make_unique<PontryaginDiscretization>(problem, steps);
    FixedPointSweep(*slot->disc, ReferenceGuess(*slot->disc), FixedPointOptions{}, slot->y);
    EvaluateResidualAndJacobian(*slot->disc, slot->y, slot->ws, slot->residual);
  }
  return *slot;
}

template <typename Solver>
void BM_LinearSolve(benchmark::State& state) {
  ArmSystem& sys = GetArmSystem(static_cast<int>(state.range(0)));
  Solver solver;
  Eigen::VectorXd step;
  for (auto _ : state) {
    if (!solver.Factorize(*sys.disc, sys.ws.jacobian)) state.SkipWithError("singular");
    solver.Solve(sys.residual, step);
    benchmark::DoNotOptimize(step.data());
  }
  state.counters["N"] = static_cast<double>(state.range(0));
  state.counters["unknowns"] = static_cast<double>(sys.disc->unknowns());
  state.counters["us_per_step"] = benchmark::Counter(
      static_cast<double>(state.range(0)),
      benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

void BM_ResidualAndJacobian(benchmark::State& state) {
  ArmSystem& sys = GetArmSystem(static_cast<int>(state.range(0)));
  for (auto _ : state) {
    benchmark::DoNotOptimize(EvaluateResidualAndJacobian(*sys.disc, sys.y, sys.ws, sys.residual));
  }
  state.counters["N"] = static_cast<double>(state.range(0));
}

BENCHMARK(BM_LinearSolve<RiccatiSolver>)
    ->Name("Riccati")
    ->RangeMultiplier(2)
    ->Range(512, 16384)
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_LinearSolve<SparseLuSolver>)
    ->Name("SparseLU")
    ->RangeMultiplier(2)
    ->Range(512, 16384)
    ->Unit(benchmark::kMillisecond)
    ->Iterations(3);
BENCHMARK(BM_ResidualAndJacobian)
    ->Name("ResidualAndJacobian")
    ->RangeMultiplier(2)
    ->Range(512, 16384)
    ->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
