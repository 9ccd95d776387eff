// The neighbour-list build's phases at 10^6 disks, each timed on its own: the cell sort
// (CellList::FitAndSort), the storage reorder (ParticleStore::Reorder) and the list fill with its
// concatenation (NeighbourList::Build), on examples/disks_1e6.toml's start (random sequential
// addition, seed 1, packing fraction 1/4, radius 0.5, the engine's default skin 0.5). Between
// builds the positions contract by 10^−3 about the centre and every particle moves by up to 0.06
// (deterministic). About half the slots then change cell between builds,
// against about 8 % between the example's builds: the sort and the reorder do more scattered work
// here than in the example (kept so, for comparison with the figures in docs/benchmarks.md).
//
// Counters: per phase the mean and the fastest ms over the iterations, wall-clock and process CPU
// time (the fastest is the one to compare on a noisy machine; on one thread the CPU time leaves out
// the time the virtual machine's host took the core), and the pairs of the list.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include <time.h>

#include "bench_main.h"
#include "moreau/common/openmp_wait.h"
#include "moreau/common/random.h"
#include "moreau/particles/engine.h"
#include "particles/cell_list.h"
#include "particles/neighbour_list.h"
#include "particles/particle_store.h"

namespace {

using moreau::particles::ParticleModel;
namespace internal = moreau::particles::internal;

constexpr int kN = 1000000;
constexpr double kHalf = 886.227;

double CpuSeconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

void BM_ListBuildPhases(benchmark::State& state) {
  const int threads = static_cast<int>(state.range(0));
  ParticleModel model;
  model.radius.assign(kN, 0.5);
  model.domain_lo = {-kHalf, -kHalf, 0.0};
  model.domain_hi = {kHalf, kHalf, 0.0};
  static const std::vector<double> x0 =
      moreau::particles::RandomSequentialAddition(model, model.domain_lo, model.domain_hi, 1);
  const internal::PeriodicBox box = internal::PeriodicBox::Of(model);
  const double skin = 0.5, reach = 1.0 + skin;
  internal::ParticleStore store(model, x0);
  internal::CellList cells;
  internal::NeighbourList list;
  list.Configure(box, kN, skin, std::numeric_limits<double>::infinity(), 0.0);
  list.AssumeUniformRadius(0.5);
  moreau::SplitMix64 rng(7);
  using Clock = std::chrono::steady_clock;
  double total[3] = {0, 0, 0}, fastest[3] = {1e9, 1e9, 1e9};
  double cpu_total[3] = {0, 0, 0}, cpu_fastest[3] = {1e9, 1e9, 1e9};
  std::int64_t builds = 0;
  auto build = [&](bool timed) {
    const auto t0 = Clock::now();
    const double c0 = CpuSeconds();
    cells.FitAndSort(store.predicted.data(), store.id.data(), kN, box, reach, 0, threads);
    const auto t1 = Clock::now();
    const double c1 = CpuSeconds();
    // As the engine: the reorder also writes the list's build positions.
    store.Reorder(cells.permutation(), threads, false, &store.predicted,
                  list.BuildPositionsTarget());
    const auto t2 = Clock::now();
    const double c2 = CpuSeconds();
    list.Build(store.predicted.data(), store.radius.data(), cells, nullptr,
               internal::ListRows::kAsVisited, builds, threads);
    const auto t3 = Clock::now();
    const double c3 = CpuSeconds();
    ++builds;
    if (!timed) return;
    const double phase[3] = {std::chrono::duration<double>(t1 - t0).count(),
                             std::chrono::duration<double>(t2 - t1).count(),
                             std::chrono::duration<double>(t3 - t2).count()};
    const double cpu[3] = {c1 - c0, c2 - c1, c3 - c2};
    for (int i = 0; i < 3; ++i) {
      total[i] += phase[i];
      fastest[i] = std::min(fastest[i], phase[i]);
      cpu_total[i] += cpu[i];
      cpu_fastest[i] = std::min(cpu_fastest[i], cpu[i]);
    }
    state.SetIterationTime(phase[0] + phase[1] + phase[2]);
  };
  store.predicted = store.current;
  build(false);  // the first build sorts from id order; the timed ones from the last build's
  for (auto _ : state) {
    for (double& v : store.predicted) v = 0.999 * v + 0.06 * (2.0 * rng.Uniform01() - 1.0);
    build(true);
  }
  const auto iterations = static_cast<double>(state.iterations());
  const char* names[3] = {"sort", "reorder", "fill"};
  for (int i = 0; i < 3; ++i) {
    state.counters[std::string(names[i]) + "_ms"] = 1e3 * total[i] / iterations;
    state.counters[std::string(names[i]) + "_fastest_ms"] = 1e3 * fastest[i];
    state.counters[std::string(names[i]) + "_cpu_ms"] = 1e3 * cpu_total[i] / iterations;
    state.counters[std::string(names[i]) + "_cpu_fastest_ms"] = 1e3 * cpu_fastest[i];
  }
  state.counters["pairs"] = static_cast<double>(list.pairs());
}

BENCHMARK(BM_ListBuildPhases)
    ->Arg(1)
    ->Arg(2)
    ->ArgName("threads")
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond)
    ->Iterations(30);

}  // namespace

int main(int argc, char** argv) {
  moreau::RestartWithBoundedOpenMpSpin(argv);
  return moreau::bench::RunBenchmarks(argc, argv);
}
