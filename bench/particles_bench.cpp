// Particle engine throughput: time per particle-step for the paper's disks at scale.
//
// Workload: N disks of radius 0.5 on a jittered square lattice at packing fraction 0.5 in the
// square [−L/2, L/2]², drift −γx (the paper's disks case, γ = 1) with h chosen so that the
// outermost disks move 0.005 per step (h = 0.01/L): the same displacement per step, hence the same
// neighbour-list rebuild interval, for every N. Steps are timed after setup; the overlap monitor
// is off (it is an optional pass).
//
//   BM_Engine/N/threads            the engine (coloured sweep, Verlet lists, reordering)
//   BM_Disks1e6/threads            examples/disks_1e6.toml's workload (random start, trap, monitor
//                                  on): steps/s, phase times, the time of one list build at 10^6
//   BM_PlainCellListSweep/N        the baseline: a plain sequential sweep over a cell list rebuilt
//                                  by counting sort every step (no Verlet list, no reordering)
//
// Counters: s_per_particle_step (printed with an SI prefix) and steps_per_s (real time).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <numbers>
#include <vector>

#include <time.h>
#include <unistd.h>

#include "bench_main.h"
#include "moreau/common/hash.h"
#include "moreau/common/openmp_wait.h"
#include "moreau/common/random.h"
#include "moreau/particles/engine.h"
#include "moreau/pbd/cases.h"

namespace {

using moreau::particles::Engine;
using moreau::particles::EngineOptions;
using moreau::particles::Forces;
using moreau::particles::HarmonicTrap;
using moreau::particles::ParticleModel;

constexpr double kRadius = 0.5;
constexpr double kPacking = 0.5;

struct Workload {
  int n = 0;
  double L = 0.0;
  double h = 0.0;
  std::vector<double> x0;
};

Workload MakeWorkload(int side) {
  Workload w;
  w.n = side * side;
  const double area_per_disk = std::numbers::pi * kRadius * kRadius / kPacking;
  const double a = std::sqrt(area_per_disk);  // lattice spacing 1.2533 > 2r
  w.L = a * side;
  w.h = 0.01 / w.L;
  w.x0.resize(2 * static_cast<std::size_t>(w.n));
  moreau::SplitMix64 rng(12345);
  auto uniform = [&rng] { return rng.Uniform01(); };
  const double jitter = 0.08;  // keeps lattice neighbours ≥ a − 2√2·0.08 > 2r apart
  for (int i = 0; i < side; ++i) {
    for (int j = 0; j < side; ++j) {
      const std::size_t p = 2 * static_cast<std::size_t>(i * side + j);
      w.x0[p] = -0.5 * w.L + a * (i + 0.5) + jitter * (2.0 * uniform() - 1.0);
      w.x0[p + 1] = -0.5 * w.L + a * (j + 0.5) + jitter * (2.0 * uniform() - 1.0);
    }
  }
  return w;
}

int SideFor(std::int64_t n) {
  return static_cast<int>(std::lround(std::sqrt(static_cast<double>(n))));
}

void Report(benchmark::State& state, int n) {
  // Seconds per particle-step (printed with an SI prefix: "25n" is 25 ns).
  state.counters["s_per_particle_step"] =
      benchmark::Counter(static_cast<double>(n), benchmark::Counter::kIsIterationInvariantRate |
                                                     benchmark::Counter::kInvert);
  state.counters["steps_per_s"] =
      benchmark::Counter(1.0, benchmark::Counter::kIsIterationInvariantRate);
}

// The engine of the benchmark workload: disks of radius kRadius in the trap −x, overlap monitor
// off, the lattice start feasible by construction (not re-checked).
// diffusion: D (0: no noise); monitor: the overlap monitor.
Engine MakeWorkloadEngine(const Workload& w, int threads, double diffusion = 0.0,
                          bool monitor = false) {
  ParticleModel model;
  model.radius.assign(static_cast<std::size_t>(w.n), kRadius);
  Forces forces;
  forces.trap = HarmonicTrap{1.0, {0.0, 0.0, 0.0}};
  forces.diffusion = diffusion;
  EngineOptions options;
  options.h = w.h;
  options.threads = threads;
  options.monitor_overlap = monitor;
  options.check_initial_state = false;
  return Engine(model, forces, options, w.x0);
}

// The noise of the noise benchmarks: √(2 D h) = 0.005 per component and step, the drift's
// largest step (h = 0.01/L), so D = 0.005² / (2h) grows with L.
double NoiseDiffusion(const Workload& w) { return 0.005 * 0.005 / (2.0 * w.h); }

double CpuSeconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

void BM_Engine(benchmark::State& state) {
  const Workload w = MakeWorkload(SideFor(state.range(0)));
  Engine engine = MakeWorkloadEngine(w, static_cast<int>(state.range(1)));
  for (int i = 0; i < 3; ++i) engine.Step();  // warm up (first-touch, caches)
  for (auto _ : state) {
    if (!engine.Step()) state.SkipWithError("non-finite state");
  }
  const auto s = engine.summary().stats;
  state.counters["rebuild_every"] =
      static_cast<double>(s.steps) /
      static_cast<double>(std::max<std::int64_t>(1, s.neighbour_list_builds));
  state.counters["pairs_per_particle"] =
      static_cast<double>(s.candidate_pairs) / static_cast<double>(w.n);
  state.counters["retries"] = static_cast<double>(s.verlet_retries);
  Report(state, w.n);
}

// The baseline: predicted positions, a cell list of edge 2r rebuilt by counting sort, one
// sequential sweep of the pairs (i, j) found in the 3×3 cells around i with j after i in cell
// order. Arrays in particle order; no Verlet list, no reordering.
void BM_PlainCellListSweep(benchmark::State& state) {
  const Workload w = MakeWorkload(SideFor(state.range(0)));
  const int n = w.n;
  std::vector<double> x = w.x0;
  const double c = 2.0 * kRadius;
  const double c2 = c * c;
  std::vector<int> cell_of(static_cast<std::size_t>(n)), start, order(static_cast<std::size_t>(n));
  auto step = [&] {
    for (double& v : x) v += w.h * (-1.0 * v);
    double lo = x[0], hi = x[0];
    for (double v : x) {
      lo = std::min(lo, v);
      hi = std::max(hi, v);
    }
    const int nc = std::max(1, static_cast<int>((hi - lo) / c));
    const double inv = nc / (hi - lo) * (1.0 - 1e-12);
    start.assign(static_cast<std::size_t>(nc) * nc + 1, 0);
    for (int i = 0; i < n; ++i) {
      const int cx =
          std::min(nc - 1, static_cast<int>((x[2 * static_cast<std::size_t>(i)] - lo) * inv));
      const int cy =
          std::min(nc - 1, static_cast<int>((x[2 * static_cast<std::size_t>(i) + 1] - lo) * inv));
      cell_of[static_cast<std::size_t>(i)] = cy * nc + cx;
      ++start[static_cast<std::size_t>(cy * nc + cx) + 1];
    }
    for (std::size_t k = 1; k < start.size(); ++k) start[k] += start[k - 1];
    std::vector<int> fill(start.begin(), start.end() - 1);
    for (int i = 0; i < n; ++i)
      order[static_cast<std::size_t>(
          fill[static_cast<std::size_t>(cell_of[static_cast<std::size_t>(i)])]++)] = i;
    for (int cy = 0; cy < nc; ++cy) {
      for (int cx = 0; cx < nc; ++cx) {
        const int cell = cy * nc + cx;
        for (int p = start[static_cast<std::size_t>(cell)];
             p < start[static_cast<std::size_t>(cell) + 1]; ++p) {
          const int i = order[static_cast<std::size_t>(p)];
          for (int dy = -1; dy <= 1; ++dy) {
            for (int dx = -1; dx <= 1; ++dx) {
              const int ny = cy + dy, nx = cx + dx;
              if (ny < 0 || nx < 0 || ny >= nc || nx >= nc) continue;
              const int other = ny * nc + nx;
              if (other < cell) continue;
              for (int q = other == cell ? p + 1 : start[static_cast<std::size_t>(other)];
                   q < start[static_cast<std::size_t>(other) + 1]; ++q) {
                const int j = order[static_cast<std::size_t>(q)];
                double* xi = &x[2 * static_cast<std::size_t>(i)];
                double* xj = &x[2 * static_cast<std::size_t>(j)];
                const double u0 = xi[0] - xj[0], u1 = xi[1] - xj[1];
                const double r2 = u0 * u0 + u1 * u1;
                if (r2 >= c2) continue;
                const double r = std::sqrt(r2);
                const double s = 0.5 * (c - r) / r;
                xi[0] += s * u0;
                xi[1] += s * u1;
                xj[0] -= s * u0;
                xj[1] -= s * u1;
              }
            }
          }
        }
      }
    }
  };
  for (int i = 0; i < 3; ++i) step();
  for (auto _ : state) {
    step();
    benchmark::DoNotOptimize(x.data());
  }
  Report(state, n);
}

// 1 and 2 threads interleaved: two engines on the same state (results do not depend on the thread
// count) advance in alternating bursts of 5 steps, each burst timed, so both see the same machine
// (the second core of the shared machines comes and goes). Counters: the two times per step, their
// ratio, and the same ratio for the trivially parallel control loop measured in the same bursts.
// Also ms per step of each phase (force = prediction, lists, sweep) on 1 and 2 threads.
// warm = 1: a parallel region wakes the second thread before each 2-thread burst is timed. While
// the 1-thread burst and the control loop run (milliseconds), the 2-thread engine's idle thread
// outlasts its spin (about 0.2 ms, docs/benchmarks.md "OpenMP waiting") and sleeps, so with
// warm = 0 each burst also pays one wake-up of a halted virtual CPU (about 0.14 ms here), which a
// run that steps without pause pays once. The two variants bracket what a user sees.
void BM_ThreadSpeedupInterleaved(benchmark::State& state) {
  const Workload w = MakeWorkload(SideFor(state.range(0)));
  const bool warm = state.range(1) != 0;
  Engine one = MakeWorkloadEngine(w, 1);
  Engine two = MakeWorkloadEngine(w, 2);
  for (int i = 0; i < 3; ++i) {
    one.Step();
    two.Step();
  }
  using Clock = std::chrono::steady_clock;
  double t1 = 0.0, t2 = 0.0, c1 = 0.0, c2 = 0.0;
  std::int64_t steps = 0;
  auto control = [](int threads) {
    const auto a = Clock::now();
    double sum = 0.0;
#pragma omp parallel for num_threads(threads) reduction(+ : sum) schedule(static)
    for (int i = 0; i < 2000000; ++i) sum += std::sqrt(static_cast<double>(i));
    benchmark::DoNotOptimize(sum);
    return std::chrono::duration<double>(Clock::now() - a).count();
  };
  for (auto _ : state) {
    auto a = Clock::now();
    for (int i = 0; i < 5; ++i) one.Step();
    if (warm) {
      // Wake the second thread before the clock starts (see the comment above).
#pragma omp parallel num_threads(2)
      benchmark::ClobberMemory();
    }
    auto b = Clock::now();
    for (int i = 0; i < 5; ++i) two.Step();
    auto c = Clock::now();
    t1 += std::chrono::duration<double>(b - a).count();
    t2 += std::chrono::duration<double>(c - b).count();
    c1 += control(1);
    c2 += control(2);
    steps += 5;
  }
  if (one.Positions() != two.Positions()) state.SkipWithError("1 and 2 threads differ");
  state.counters["ms_per_step_1"] = 1e3 * t1 / static_cast<double>(steps);
  state.counters["ms_per_step_2"] = 1e3 * t2 / static_cast<double>(steps);
  state.counters["speedup"] = t1 / t2;
  // Per-phase speedups (whole run, warm-up included).
  const auto s1 = one.summary().stats;
  const auto s2 = two.summary().stats;
  state.counters["speedup_force"] = s1.force_seconds / s2.force_seconds;
  state.counters["speedup_lists"] = s1.neighbour_seconds / s2.neighbour_seconds;
  state.counters["speedup_sweep"] = s1.sweep_seconds / s2.sweep_seconds;
  state.counters["lists_share_2"] = s2.neighbour_seconds / s2.total_seconds;
  const double per = 1e3 / static_cast<double>(s1.steps);
  state.counters["ms_force_1"] = per * s1.force_seconds;
  state.counters["ms_force_2"] = per * s2.force_seconds;
  state.counters["ms_sweep_1"] = per * s1.sweep_seconds;
  state.counters["ms_sweep_2"] = per * s2.sweep_seconds;
  state.counters["ms_lists_1"] = per * s1.neighbour_seconds;
  state.counters["ms_lists_2"] = per * s2.neighbour_seconds;
  state.counters["control_speedup"] = c1 / c2;
}

// examples/disks_1e6.toml without the CLI: 10^6 disks of radius 0.5 from the random start
// (random sequential addition, seed 1) at packing fraction 1/4 in [−886.227, 886.227]², the trap
// γ = 0.001, h = 0.02, skin factor as the engine's default, overlap monitor on (the example's
// defaults). Besides steps/s it reports the phase timers per step and the time of one
// neighbour-list build (wrap, cell sort, storage reorder and list fill) at 10^6.
void BM_Disks1e6(benchmark::State& state) {
  static const std::vector<double> x0 = [] {
    ParticleModel m;
    m.radius.assign(1000000, kRadius);
    return moreau::particles::RandomSequentialAddition(m, {-886.227, -886.227, 0.0},
                                                       {886.227, 886.227, 0.0}, 1);
  }();
  ParticleModel model;
  model.radius.assign(1000000, kRadius);
  model.domain_lo = {-886.227, -886.227, 0.0};
  model.domain_hi = {886.227, 886.227, 0.0};
  Forces forces;
  forces.trap = HarmonicTrap{0.001, {0.0, 0.0, 0.0}};
  EngineOptions options;
  options.h = 0.02;
  options.threads = static_cast<int>(state.range(0));
  options.check_initial_state = false;  // feasible by construction
  Engine engine(model, forces, options, x0);
  for (auto _ : state) {
    if (!engine.Step()) state.SkipWithError("non-finite state");
  }
  const auto s = engine.summary().stats;
  const auto steps = static_cast<double>(s.steps);
  state.counters["builds"] = static_cast<double>(s.neighbour_list_builds);
  state.counters["ms_per_list_build"] =
      1e3 * s.neighbour_seconds /
      static_cast<double>(std::max<std::int64_t>(1, s.neighbour_list_builds));
  state.counters["ms_lists_per_step"] = 1e3 * s.neighbour_seconds / steps;
  state.counters["ms_sweep_per_step"] = 1e3 * s.sweep_seconds / steps;
  state.counters["ms_predict_per_step"] = 1e3 * s.force_seconds / steps;
  state.counters["ms_monitor_per_step"] = 1e3 * s.monitor_seconds / steps;
  state.counters["pairs_per_particle"] = static_cast<double>(s.candidate_pairs) / 1e6;
  Report(state, 1000000);
}

// Engines on the same workload advancing in alternating bursts of 5 steps, each burst timed in
// wall-clock and process CPU time, so all see the same machine. Returns per engine the seconds
// per step (wall, CPU).
struct BurstTimes {
  std::vector<double> wall, cpu;
  std::int64_t steps = 0;
};

template <typename Benchmark>
BurstTimes InterleavedBursts(benchmark::State& state, std::vector<Engine>& engines,
                             const Benchmark& extra) {
  using Clock = std::chrono::steady_clock;
  BurstTimes t;
  t.wall.assign(engines.size(), 0.0);
  t.cpu.assign(engines.size(), 0.0);
  for (Engine& e : engines) {
    for (int i = 0; i < 3; ++i) e.Step();  // warm up (first-touch, caches)
  }
  for (auto _ : state) {
    for (std::size_t k = 0; k < engines.size(); ++k) {
      const auto a = Clock::now();
      const double c = CpuSeconds();
      for (int i = 0; i < 5; ++i) {
        if (!engines[k].Step()) state.SkipWithError("non-finite state");
        extra(k, engines[k]);
      }
      t.cpu[k] += CpuSeconds() - c;
      t.wall[k] += std::chrono::duration<double>(Clock::now() - a).count();
    }
    t.steps += 5;
  }
  return t;
}

// Brownian noise against none: the noiseless and the noisy engine (√(2Dh) = 0.005)
// interleaved. Counters: ms per step (wall and CPU) of each, their ratios, and the noisy engine's
// share of prediction (drift + noise), list builds and sweeps.
void BM_NoiseInterleaved(benchmark::State& state) {
  const Workload w = MakeWorkload(SideFor(state.range(0)));
  const int threads = static_cast<int>(state.range(1));
  std::vector<Engine> engines;
  engines.push_back(MakeWorkloadEngine(w, threads));
  engines.push_back(MakeWorkloadEngine(w, threads, NoiseDiffusion(w)));
  const BurstTimes t = InterleavedBursts(state, engines, [](std::size_t, const Engine&) {});
  const auto steps = static_cast<double>(t.steps);
  state.counters["ms_per_step_plain"] = 1e3 * t.wall[0] / steps;
  state.counters["ms_per_step_noise"] = 1e3 * t.wall[1] / steps;
  state.counters["ratio"] = t.wall[1] / t.wall[0];
  state.counters["cpu_ms_per_step_plain"] = 1e3 * t.cpu[0] / steps;
  state.counters["cpu_ms_per_step_noise"] = 1e3 * t.cpu[1] / steps;
  state.counters["cpu_ratio"] = t.cpu[1] / t.cpu[0];
  const auto p = engines[0].summary().stats;
  const auto q = engines[1].summary().stats;
  state.counters["noise_prediction_ms"] = 1e3 * q.force_seconds / static_cast<double>(q.steps);
  state.counters["plain_prediction_ms"] = 1e3 * p.force_seconds / static_cast<double>(p.steps);
  state.counters["noise_lists_ms"] = 1e3 * q.neighbour_seconds / static_cast<double>(q.steps);
  state.counters["plain_lists_ms"] = 1e3 * p.neighbour_seconds / static_cast<double>(p.steps);
  state.counters["noise_sweep_ms"] = 1e3 * q.sweep_seconds / static_cast<double>(q.steps);
  state.counters["plain_sweep_ms"] = 1e3 * p.sweep_seconds / static_cast<double>(p.steps);
  state.counters["noise_builds"] = static_cast<double>(q.neighbour_list_builds);
  state.counters["plain_builds"] = static_cast<double>(p.neighbour_list_builds);
}

// The overlap monitor's cost, noiseless and noisy: an engine without the monitor, one
// with it, and one without it followed by the pass over every pair after each step (what a monitor
// without the sweep's near-contact rows would do), interleaved. Counters: ms per step of each, the
// monitor's share of the monitored step, the full pass's cost per step, and the check that the
// monitor's value equals the full pass's at every step (mismatches, must be 0).
void BM_MonitorInterleaved(benchmark::State& state) {
  const Workload w = MakeWorkload(SideFor(state.range(0)));
  const int threads = static_cast<int>(state.range(1));
  const double diffusion = state.range(2) != 0 ? NoiseDiffusion(w) : 0.0;
  std::vector<Engine> engines;
  engines.push_back(MakeWorkloadEngine(w, threads, diffusion));
  engines.push_back(MakeWorkloadEngine(w, threads, diffusion, true));
  engines.push_back(MakeWorkloadEngine(w, threads, diffusion));
  using Clock = std::chrono::steady_clock;
  double full_pass = 0.0;
  std::int64_t mismatches = 0;
  std::vector<double> monitored;  // engine 1's value per step (engine 2 has the same states)
  std::size_t compared = 0;
  const BurstTimes t = InterleavedBursts(state, engines, [&](std::size_t k, const Engine& e) {
    if (k == 1) monitored.push_back(e.summary().stats.last_overlap);
    if (k == 2) {
      const auto a = Clock::now();
      const double worst = e.MaxPairOverlap();
      full_pass += std::chrono::duration<double>(Clock::now() - a).count();
      if (compared >= monitored.size() || worst != monitored[compared]) ++mismatches;
      ++compared;
    }
  });
  const auto steps = static_cast<double>(t.steps);
  const auto s = engines[1].summary().stats;
  state.counters["ms_per_step_off"] = 1e3 * t.wall[0] / steps;
  state.counters["ms_per_step_on"] = 1e3 * t.wall[1] / steps;
  state.counters["ms_per_step_full_pass"] = 1e3 * t.wall[2] / steps;
  state.counters["monitor_share"] = s.monitor_seconds / s.total_seconds;
  state.counters["monitor_ms"] = 1e3 * s.monitor_seconds / static_cast<double>(s.steps);
  state.counters["full_pass_ms"] = 1e3 * full_pass / steps;
  state.counters["mismatches"] = static_cast<double>(mismatches);
}

// Machine check: a trivially parallel loop (no memory traffic, no barriers but one), timed with
// 1 and 2 threads in the same run. On the shared 2-core machines other jobs often hold a core;
// this control shows how much parallel speedup the machine offered at the time.
void BM_ParallelControl(benchmark::State& state) {
  const int threads = static_cast<int>(state.range(0));
  for (auto _ : state) {
    double sum = 0.0;
#pragma omp parallel for num_threads(threads) reduction(+ : sum) schedule(static)
    for (int i = 0; i < 20000000; ++i) sum += std::sqrt(static_cast<double>(i));
    benchmark::DoNotOptimize(sum);
  }
}

// The same number of steps (after 3 warm-up steps) for every N, so every N is timed on the same
// stretch of the dynamics (h = 0.01/L makes the motion per step N-independent).
constexpr int kSteps = 100;

BENCHMARK(BM_ThreadSpeedupInterleaved)
    ->ArgsProduct({{100000, 1000000}, {0, 1}})
    ->ArgNames({"N", "warm"})
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond)
    ->Iterations(20);

BENCHMARK(BM_NoiseInterleaved)
    ->ArgsProduct({{100000, 1000000}, {1, 2}})
    ->ArgNames({"N", "threads"})
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond)
    ->Iterations(20);
BENCHMARK(BM_MonitorInterleaved)
    ->ArgsProduct({{100000, 1000000}, {2}, {0, 1}})
    ->ArgNames({"N", "threads", "noise"})
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond)
    ->Iterations(20);

// The control runs first and last (when = 0, 1): the machine's offer can change during a run.
BENCHMARK(BM_ParallelControl)
    ->Args({1, 0})
    ->Args({2, 0})
    ->ArgNames({"threads", "when"})
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Engine)
    ->ArgsProduct({{10000, 100000, 1000000}, {1, 2}})
    ->ArgNames({"N", "threads"})
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond)
    ->Iterations(kSteps);
// The example's 500 steps (T = 10), one run per thread count: the first build happens in setup
// and is not timed; the list builds of the steps are.
BENCHMARK(BM_Disks1e6)
    ->Arg(1)
    ->Arg(2)
    ->ArgName("threads")
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond)
    ->Iterations(500);
BENCHMARK(BM_PlainCellListSweep)
    ->Arg(10000)
    ->Arg(100000)
    ->Arg(1000000)
    ->ArgName("N")
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond)
    ->Iterations(kSteps);
BENCHMARK(BM_ParallelControl)
    ->Args({1, 1})
    ->Args({2, 1})
    ->ArgNames({"threads", "when"})
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);

}  // namespace

// OpenMP waiting as moreau's command line chooses it (moreau/common/openmp_wait.h).
int main(int argc, char** argv) {
  moreau::RestartWithBoundedOpenMpSpin(argv);
  // --hash_steps=S: no timing; runs the 10^6-disk workload (2 threads) for S steps and prints the
  // hash of the final positions (a regression check on bits: two builds must print the same hash).
  if (argc == 2 && std::strncmp(argv[1], "--hash_steps=", 13) == 0) {
    const std::int64_t steps = std::atoll(argv[1] + 13);
    const Workload w = MakeWorkload(SideFor(1000000));
    Engine engine = MakeWorkloadEngine(w, 2);
    for (std::int64_t i = 0; i < steps; ++i) engine.Step();
    std::printf("N %d steps %lld positions_hash %s\n", w.n, static_cast<long long>(steps),
                moreau::HashDoublesHex(engine.Positions()).c_str());
    return 0;
  }
  return moreau::bench::RunBenchmarks(argc, argv);
}
