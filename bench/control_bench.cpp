// Time per Newton iteration of the Symplectic Pontryagin solver on the arm model (thesis 9.2),
// N = 512 … 16384: the structure-exploiting Riccati solve against Eigen SparseLU (factorise +
// solve of the same Jacobian), and the residual + Jacobian evaluation for scale. ArmSolve: the
// whole solve from the documented start of examples/control/arm_2d.toml at N = 1024 and 4096,
// 1 and 2 threads, coarse-to-fine (coarse = -1: the default coarse grid; coarse > 0: that
// continuation.coarse_steps) against the plain path (every stage on the requested grid,
// coarse = 0), with the max difference of the controls from the plain path's.
//
//   build/release/control_bench --benchmark_counters_tabular=true
//   build/release/control_bench --benchmark_filter=ArmSolve --benchmark_counters_tabular=true
#include <benchmark/benchmark.h>
#include <sys/resource.h>
#include <unistd.h>

#include <cstdlib>
#include <map>
#include <memory>

#include "arm_documented_start.h"
#include "bench_main.h"
#include "moreau/common/openmp_wait.h"
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

// Process CPU time (all threads), seconds.
double ProcessCpuSeconds() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
         1e-6 * static_cast<double>(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

// The documented start of examples/control/arm_2d.toml, on `threads` threads; coarse < 0 keeps
// the default coarse grid, coarse >= 0 sets continuation.coarse_steps (0: the plain path, every
// stage on the requested grid).
ContinuationOptions DocumentedStart(int coarse, int threads) {
  ContinuationOptions o = moreau::bench::ArmDocumentedStart();
  o.newton.threads = threads;
  if (coarse >= 0) o.coarse_steps = coarse;
  return o;
}

const ProblemFamily& ArmFamily() {
  static const ProblemFamily family = [](double p) { return MakeArmProblem(ArmExample{}, p); };
  return family;
}

// Controls of the plain path at N (solved once, with 2 threads: the comparison reference).
std::map<int, Eigen::MatrixXd>& PlainControlCache() {
  static std::map<int, Eigen::MatrixXd> cache;
  return cache;
}

const Eigen::MatrixXd& PlainControls(int steps) {
  auto& slot = PlainControlCache()[steps];
  if (slot.size() == 0) {
    Eigen::VectorXd y;
    SolveWithContinuation(ArmFamily(), steps, DocumentedStart(0, 2), y);
    slot = EffectiveControls(PontryaginDiscretization(ArmFamily()(1.0), steps), y);
  }
  return slot;
}

void BM_ArmSolve(benchmark::State& state) {
  const int steps = static_cast<int>(state.range(0));
  const int threads = static_cast<int>(state.range(1));
  const int coarse = static_cast<int>(state.range(2));
  const ContinuationOptions options = DocumentedStart(coarse, threads);
  Eigen::VectorXd y;
  ContinuationSummary summary;
  double cpu = 0.0;
  for (auto _ : state) {
    const double cpu0 = ProcessCpuSeconds();
    summary = SolveWithContinuation(ArmFamily(), steps, options, y);
    cpu += ProcessCpuSeconds() - cpu0;
  }
  if (!summary.ok()) state.SkipWithError(summary.message.c_str());
  const PontryaginDiscretization disc(ArmFamily()(1.0), steps);
  const Eigen::MatrixXd controls = EffectiveControls(disc, y);
  if (coarse == 0 && threads == 2) PlainControlCache()[steps] = controls;
  PontryaginWorkspace ws;
  Eigen::VectorXd residual;
  state.counters["residual"] = EvaluateResidual(disc, y, ws, residual);
  state.counters["max_control_diff"] = (controls - PlainControls(steps)).lpNorm<Eigen::Infinity>();
  state.counters["newton_iterations"] = summary.newton_iterations;
  state.counters["fine_iterations"] = summary.grids.back().newton_iterations;
  state.counters["grids"] = static_cast<double>(summary.grids.size());
  state.counters["coarse_grid"] = summary.grids.front().steps;
  state.counters["cpu_s"] = cpu / static_cast<double>(state.iterations());
}

// Plain 2-thread cases first: they fill the comparison cache.
BENCHMARK(BM_ArmSolve)
    ->Name("ArmSolve")
    ->ArgNames({"N", "threads", "coarse"})
    ->Args({1024, 2, 0})
    ->Args({1024, 1, 0})
    ->Args({1024, 1, -1})
    ->Args({1024, 2, -1})
    ->Args({1024, 1, 512})
    ->Args({1024, 1, 256})
    ->Args({4096, 2, 0})
    ->Args({4096, 1, 0})
    ->Args({4096, 1, -1})
    ->Args({4096, 2, -1})
    ->Args({4096, 1, 512})
    ->Args({4096, 1, 256})
    ->Iterations(1)
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);

}  // namespace

// OpenMP waiting as moreau's command line chooses it (moreau/common/openmp_wait.h).
int main(int argc, char** argv) {
  moreau::RestartWithBoundedOpenMpSpin(argv);
  return moreau::bench::RunBenchmarks(argc, argv);
}
