// PBD on the paper's disks run: 40 disks of radius 0.2, f(x) = −x, h = 1e−4, T = 1 (10^4
// steps), one sweep of pair projections per step (pairs i < j in lexicographic order).
//
//   BM_PlainLoop            the baseline: a plain all-pairs double loop over a flat
//                           std::vector<double>, written here as a competent user would.
//   BM_PlainLoopHoisted     the same loop with disk i kept in locals over its row (reference
//                           only; not the baseline of the comparison).
//   BM_LibraryPBD           moreau::pbd::Simulate with ParticleConstraints (Verlet list, the
//                           default) and HarmonicDrift(1), without / with violation monitoring.
//   BM_LibraryPBDAllPairs   the same with PairSearch::kAllPairs (the library's kernel on all
//                           780 pairs, for comparison with the baseline).
//
// Each iteration is one full run of 10^4 steps from the same initial state (construction of the
// constraints and the neighbour list included). Before any benchmark runs, main() checks that the
// baseline and every library variant end in the same state to within 1e−9 and aborts otherwise.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "moreau/pbd/cases.h"
#include "moreau/pbd/drift.h"
#include "moreau/pbd/particle_constraints.h"
#include "moreau/pbd/stepper.h"

namespace {

constexpr int kCount = 40;
constexpr double kRadius = 0.2;
constexpr double kStep = 1e-4;
constexpr double kFinalTime = 1.0;
constexpr int kSteps = 10000;

moreau::pbd::DisksCase Case() {
  moreau::pbd::DisksCase c;
  c.count = kCount;
  c.radius = kRadius;
  c.gamma = 1.0;
  c.T = kFinalTime;
  c.seed = 1;
  return c;
}

std::vector<double> InitialState() {
  const moreau::pbd::Vector x0 = Case().InitialState();
  return std::vector<double>(x0.data(), x0.data() + x0.size());
}

// The baseline: explicit Euler step of x' = −x, then one sweep over all pairs i < j, moving each
// disk of an overlapping pair by half the overlap along the line of centres.
void PlainLoopRun(std::vector<double>& x, int steps, double h, double radius) {
  const int n = static_cast<int>(x.size()) / 2;
  const double contact = 2.0 * radius;
  const double contact2 = contact * contact;
  for (int step = 0; step < steps; ++step) {
    for (double& v : x) v += h * (-v);
    for (int i = 0; i < n; ++i) {
      for (int j = i + 1; j < n; ++j) {
        const double dx = x[2 * i] - x[2 * j];
        const double dy = x[2 * i + 1] - x[2 * j + 1];
        const double d2 = dx * dx + dy * dy;
        if (d2 < contact2) {
          const double d = std::sqrt(d2);
          const double s = 0.5 * (contact - d) / d;
          x[2 * i] += s * dx;
          x[2 * i + 1] += s * dy;
          x[2 * j] -= s * dx;
          x[2 * j + 1] -= s * dy;
        }
      }
    }
  }
}

// The same loop with disk i's position kept in locals over its row of pairs (the one obvious
// hand optimisation; same operations in the same order, so the same bits). For reference only:
// the baseline of the comparison is PlainLoopRun.
void PlainLoopHoistedRun(std::vector<double>& x, int steps, double h, double radius) {
  const int n = static_cast<int>(x.size()) / 2;
  const double contact = 2.0 * radius;
  const double contact2 = contact * contact;
  for (int step = 0; step < steps; ++step) {
    for (double& v : x) v += h * (-v);
    for (int i = 0; i < n; ++i) {
      double xi = x[2 * i];
      double yi = x[2 * i + 1];
      for (int j = i + 1; j < n; ++j) {
        const double dx = xi - x[2 * j];
        const double dy = yi - x[2 * j + 1];
        const double d2 = dx * dx + dy * dy;
        if (d2 < contact2) {
          const double d = std::sqrt(d2);
          const double s = 0.5 * (contact - d) / d;
          xi += s * dx;
          yi += s * dy;
          x[2 * j] -= s * dx;
          x[2 * j + 1] -= s * dy;
        }
      }
      x[2 * i] = xi;
      x[2 * i + 1] = yi;
    }
  }
}

struct LibraryResult {
  moreau::pbd::Vector final_state;
  moreau::pbd::SimulationSummary summary;
  moreau::pbd::NeighbourListStats stats;
};

LibraryResult LibraryRun(const moreau::pbd::Vector& x0, bool monitor,
                         moreau::pbd::PairSearch search) {
  moreau::pbd::ParticleConstraintsOptions copts;
  copts.search = search;
  moreau::pbd::ParticleConstraints constraints(Case().MakeModel(), copts);
  const moreau::pbd::HarmonicDrift drift(1.0);
  moreau::pbd::StepperOptions options;
  options.method = moreau::pbd::Method::kPBD;
  options.h = kStep;
  options.monitor_violation = monitor;
  LibraryResult r;
  r.summary =
      moreau::pbd::Simulate(drift, constraints, options, x0, kFinalTime, {}, &r.final_state);
  r.stats = constraints.neighbour_stats();
  return r;
}

// Times one whole run of a plain loop (`run`) from the initial state per iteration.
template <void (*run)(std::vector<double>&, int, double, double)>
void TimePlainLoop(benchmark::State& state) {
  const std::vector<double> x0 = InitialState();
  std::vector<double> x;
  for (auto _ : state) {
    x = x0;
    run(x, kSteps, kStep, kRadius);
    benchmark::DoNotOptimize(x.data());
    benchmark::ClobberMemory();
  }
  state.counters["pairs"] = kCount * (kCount - 1) / 2;
}

void BM_PlainLoop(benchmark::State& state) { TimePlainLoop<PlainLoopRun>(state); }
BENCHMARK(BM_PlainLoop)->Unit(benchmark::kMillisecond);

void BM_PlainLoopHoisted(benchmark::State& state) { TimePlainLoop<PlainLoopHoistedRun>(state); }
BENCHMARK(BM_PlainLoopHoisted)->Unit(benchmark::kMillisecond);

// The library's PBD on the 40 disks with the given pair search; state.range(0) turns the
// violation monitor on.
template <moreau::pbd::PairSearch kSearch>
void TimeLibraryRun(benchmark::State& state) {
  const bool monitor = state.range(0) != 0;
  const moreau::pbd::Vector x0 = Case().InitialState();
  LibraryResult r;
  for (auto _ : state) {
    r = LibraryRun(x0, monitor, kSearch);
    benchmark::DoNotOptimize(r.final_state.data());
    benchmark::ClobberMemory();
  }
  state.counters["list_builds"] = static_cast<double>(r.stats.neighbour_list_builds);
  state.counters["pairs_last_build"] = static_cast<double>(r.stats.candidate_pairs);
}

void BM_LibraryPBD(benchmark::State& state) {
  TimeLibraryRun<moreau::pbd::PairSearch::kVerletList>(state);
}
// Both library runs, without and with the violation monitor, in milliseconds.
void MonitorOffAndOn(benchmark::internal::Benchmark* b) {
  b->ArgName("monitor_violation")->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);
}
BENCHMARK(BM_LibraryPBD)->Apply(MonitorOffAndOn);

void BM_LibraryPBDAllPairs(benchmark::State& state) {
  TimeLibraryRun<moreau::pbd::PairSearch::kAllPairs>(state);
}
BENCHMARK(BM_LibraryPBDAllPairs)->Apply(MonitorOffAndOn);

// Aborts unless the baseline and every library variant agree to within 1e−9 (max abs difference).
void CheckSameFinalState() {
  std::vector<double> base = InitialState();
  PlainLoopRun(base, kSteps, kStep, kRadius);
  std::vector<double> hoisted = InitialState();
  PlainLoopHoistedRun(hoisted, kSteps, kStep, kRadius);
  double hoisted_diff = 0.0;
  for (std::size_t i = 0; i < base.size(); ++i) {
    hoisted_diff = std::max(hoisted_diff, std::abs(base[i] - hoisted[i]));
  }
  if (!(hoisted_diff <= 1e-9)) {
    std::fprintf(stderr,
                 "pbd_bench: final states differ: max |baseline - hoisted loop| = %.3e > 1e-9\n",
                 hoisted_diff);
    std::abort();
  }
  const moreau::pbd::Vector x0 = Case().InitialState();
  struct Variant {
    const char* name;
    bool monitor;
    moreau::pbd::PairSearch search;
  };
  const Variant variants[] = {
      {"verlet, no monitor", false, moreau::pbd::PairSearch::kVerletList},
      {"verlet, monitor", true, moreau::pbd::PairSearch::kVerletList},
      {"all pairs, no monitor", false, moreau::pbd::PairSearch::kAllPairs},
      {"all pairs, monitor", true, moreau::pbd::PairSearch::kAllPairs},
  };
  for (const Variant& v : variants) {
    const LibraryResult r = LibraryRun(x0, v.monitor, v.search);
    if (!r.summary.ok() || r.summary.counters.steps != kSteps ||
        r.final_state.size() != static_cast<Eigen::Index>(base.size())) {
      std::fprintf(stderr, "pbd_bench: library run (%s) did not complete %d steps: %s\n", v.name,
                   kSteps, r.summary.BriefReport().c_str());
      std::abort();
    }
    double diff = 0.0;
    for (std::size_t i = 0; i < base.size(); ++i) {
      diff = std::max(diff, std::abs(base[i] - r.final_state[static_cast<Eigen::Index>(i)]));
    }
    if (!(diff <= 1e-9)) {
      std::fprintf(stderr,
                   "pbd_bench: final states differ: max |baseline - library (%s)| = %.3e > 1e-9\n",
                   v.name, diff);
      std::abort();
    }
    std::fprintf(stderr, "pbd_bench: check %-22s max |baseline - library| = %.3e\n", v.name, diff);
  }
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  CheckSameFinalState();
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
