// Diffusing fields (docs/benchmarks.md, "Diffusing fields"): one Step of a substrate on 100³
// voxels against a memory pass over the same values (c ← a c + b: one read and one write of every
// voxel), on the same threads, timed in turns within one run; and 1, 2 and 4 substrates in turns,
// to show the cost is linear in their number.
#include <benchmark/benchmark.h>

#include <chrono>
#include <ctime>
#include <vector>

#include <fmt/format.h>

#include "bench_main.h"
#include "moreau/common/openmp_wait.h"
#include "moreau/fields/field_set.h"

namespace {

using moreau::fields::FieldSet;
using moreau::fields::Grid;
using moreau::fields::Substrate;

constexpr int kSide = 100;
constexpr double kDt = 0.1;

double CpuSeconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

double WallSeconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

// kSide³ voxels of edge 1, zero-flux faces, `count` substrates (D = 1, λ = 0.1), values varying.
FieldSet MakeFields(int count, int threads) {
  Grid grid;
  grid.dimension = 3;
  grid.spacing = 1.0;
  grid.upper = {kSide, kSide, kSide};
  std::vector<Substrate> substrates(static_cast<std::size_t>(count));
  for (int s = 0; s < count; ++s) {
    substrates[static_cast<std::size_t>(s)].name = fmt::format("s{}", s);
    substrates[static_cast<std::size_t>(s)].decay = 0.1;
  }
  FieldSet fields(grid, substrates, threads);
  for (int s = 0; s < count; ++s) {
    std::span<double> c = fields.values(s);
    for (std::size_t v = 0; v < c.size(); ++v) c[v] = 1.0 + static_cast<double>(v % 97) / 97.0;
  }
  return fields;
}

void MemoryPass(std::vector<double>& c, int threads) {
  const auto n = static_cast<std::int64_t>(c.size());
  double* p = c.data();
#pragma omp parallel for num_threads(threads) schedule(static)
  for (std::int64_t i = 0; i < n; ++i) p[i] = 0.999 * p[i] + 1e-3;
}

// Wall and CPU seconds of f(), added to *wall and *cpu.
template <typename F>
void Timed(F&& f, double* wall, double* cpu) {
  const double w = WallSeconds();
  const double c = CpuSeconds();
  f();
  *cpu += CpuSeconds() - c;
  *wall += WallSeconds() - w;
}

// One Step of one substrate, a memory pass, and a Step of a substrate whose sources are written
// (uptake in every 10th voxel), in turns. Counters: ms of each (wall and CPU), the ratio
// step ÷ memory pass, ns per voxel.
void BM_StepAgainstMemoryPass(benchmark::State& state) {
  const int threads = static_cast<int>(state.range(0));
  FieldSet plain = MakeFields(1, threads);
  FieldSet sourced = MakeFields(1, threads);
  std::span<double> uptake = sourced.uptake(0);
  for (std::size_t v = 0; v < uptake.size(); v += 10) uptake[v] = 0.5;
  std::vector<double> memory(plain.values(0).begin(), plain.values(0).end());
  plain.Step(kDt);  // the factorisation and first touch outside the timing
  sourced.Step(kDt);
  MemoryPass(memory, threads);
  double wall[3] = {0.0, 0.0, 0.0};
  double cpu[3] = {0.0, 0.0, 0.0};
  std::int64_t rounds = 0;
  for (auto _ : state) {
    Timed([&] { plain.Step(kDt); }, &wall[0], &cpu[0]);
    Timed([&] { MemoryPass(memory, threads); }, &wall[1], &cpu[1]);
    Timed([&] { sourced.Step(kDt); }, &wall[2], &cpu[2]);
    benchmark::DoNotOptimize(memory.data());
    ++rounds;
  }
  const auto r = static_cast<double>(rounds);
  const double voxels = static_cast<double>(plain.grid().voxel_count());
  state.counters["step_ms"] = 1e3 * wall[0] / r;
  state.counters["memory_ms"] = 1e3 * wall[1] / r;
  state.counters["ratio"] = wall[0] / wall[1];
  state.counters["cpu_ratio"] = cpu[0] / cpu[1];
  state.counters["ns_per_voxel"] = 1e9 * wall[0] / r / voxels;
  state.counters["sources_step_ms"] = 1e3 * wall[2] / r;
  state.counters["sources_ratio"] = wall[2] / wall[1];
}
BENCHMARK(BM_StepAgainstMemoryPass)
    ->ArgName("threads")
    ->Arg(1)
    ->Arg(2)
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);

// 1, 2 and 4 substrates stepped in turns. Counters: ms per step of each, and per substrate.
void BM_Substrates(benchmark::State& state) {
  const int threads = static_cast<int>(state.range(0));
  const int counts[3] = {1, 2, 4};
  std::vector<FieldSet> sets;
  for (int count : counts) {
    sets.push_back(MakeFields(count, threads));
    sets.back().Step(kDt);
  }
  double wall[3] = {0.0, 0.0, 0.0};
  double cpu[3] = {0.0, 0.0, 0.0};
  std::int64_t rounds = 0;
  for (auto _ : state) {
    for (std::size_t k = 0; k < sets.size(); ++k) {
      Timed([&] { sets[k].Step(kDt); }, &wall[k], &cpu[k]);
    }
    ++rounds;
  }
  const auto r = static_cast<double>(rounds);
  for (std::size_t k = 0; k < sets.size(); ++k) {
    state.counters[fmt::format("ms_{}", counts[k])] = 1e3 * wall[k] / r;
    state.counters[fmt::format("ms_per_substrate_{}", counts[k])] = 1e3 * wall[k] / r / counts[k];
    state.counters[fmt::format("cpu_ms_per_substrate_{}", counts[k])] =
        1e3 * cpu[k] / r / counts[k];
  }
}
BENCHMARK(BM_Substrates)
    ->ArgName("threads")
    ->Arg(1)
    ->Arg(2)
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);

}  // namespace

// OpenMP waiting as moreau's command line chooses it (moreau/common/openmp_wait.h).
int main(int argc, char** argv) {
  moreau::RestartWithBoundedOpenMpSpin(argv);
  return moreau::bench::RunBenchmarks(argc, argv);
}
