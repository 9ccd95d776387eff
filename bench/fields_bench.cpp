// Diffusing fields (docs/benchmarks.md, "Diffusing fields"): one Step of a substrate on 100³
// voxels against a memory pass over the same values (c ← a c + b: one read and one write of every
// voxel), on the same threads, timed in turns within one run; and 1, 2 and 4 substrates in turns,
// to show the cost is linear in their number; the step on one thread against the same pass on two
// threads (BM_StepFloor); the x lines' two copies in turns (BM_XLineCopies).
// And the field's part of a population's step against the agents' part at 10^5 agents in 3D
// (BM_FieldAgainstAgents, below).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <ctime>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>

#include "bench_main.h"
#include "moreau/common/openmp_wait.h"
#include "moreau/common/random.h"
#include "moreau/fields/field_set.h"
#include "moreau/particles/population.h"

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

// side³ voxels of edge 1, zero-flux faces, `count` substrates (D = 1, λ = 0.1), values varying.
FieldSet MakeFields(int count, int threads, int side = kSide) {
  Grid grid;
  grid.dimension = 3;
  grid.spacing = 1.0;
  const auto edge = static_cast<double>(side);
  grid.upper = {edge, edge, edge};
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

// One Step of one substrate and a memory pass over as many values, in turns, nothing else between
// them (another grid's traffic would evict this one's from a shared cache between rounds). With
// sources:1 the substrate's sources are written (uptake in every 10th voxel), so a step also reads
// the four source arrays. Counters: ms of each (wall and CPU), the ratio step ÷ memory pass, ns
// per voxel, and the ratio of the fastest step to the fastest memory pass over the rounds
// (min_ratio: what each costs when nothing else runs on the cores; the means take in whatever
// else the machine does). On 100³ voxels (the 10^6 of the goal; 8 MB, which a large L3 holds) and
// on 200³ (64 MB: the pass runs from main memory).
void BM_StepAgainstMemoryPass(benchmark::State& state) {
  const int threads = static_cast<int>(state.range(0));
  const int side = static_cast<int>(state.range(1));
  FieldSet fields = MakeFields(1, threads, side);
  if (state.range(2) != 0) {
    std::span<double> uptake = fields.uptake(0);
    for (std::size_t v = 0; v < uptake.size(); v += 10) uptake[v] = 0.5;
  }
  std::vector<double> memory(fields.values(0).begin(), fields.values(0).end());
  fields.Step(kDt);  // the factorisation and first touch outside the timing
  MemoryPass(memory, threads);
  double wall[2] = {0.0, 0.0};
  double cpu[2] = {0.0, 0.0};
  double fastest[2] = {1e300, 1e300};
  std::int64_t rounds = 0;
  for (auto _ : state) {
    const double w0 = wall[0], w1 = wall[1];
    Timed([&] { fields.Step(kDt); }, &wall[0], &cpu[0]);
    Timed([&] { MemoryPass(memory, threads); }, &wall[1], &cpu[1]);
    fastest[0] = std::min(fastest[0], wall[0] - w0);
    fastest[1] = std::min(fastest[1], wall[1] - w1);
    benchmark::DoNotOptimize(memory.data());
    ++rounds;
  }
  const auto r = static_cast<double>(rounds);
  const double voxels = static_cast<double>(fields.grid().voxel_count());
  state.counters["step_ms"] = 1e3 * wall[0] / r;
  state.counters["memory_ms"] = 1e3 * wall[1] / r;
  state.counters["ratio"] = wall[0] / wall[1];
  state.counters["cpu_ratio"] = cpu[0] / cpu[1];
  state.counters["min_ratio"] = fastest[0] / fastest[1];
  state.counters["ns_per_voxel"] = 1e9 * wall[0] / r / voxels;
}
BENCHMARK(BM_StepAgainstMemoryPass)
    ->ArgNames({"threads", "side", "sources"})
    ->Args({1, kSide, 0})
    ->Args({2, kSide, 0})
    ->Args({1, 2 * kSide, 0})
    ->Args({2, 2 * kSide, 0})
    ->Args({1, kSide, 1})
    ->Args({2, kSide, 1})
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);

// The step's floor on two threads: Steps of a side³ grid on one thread against the memory pass
// over 100³ values on two threads, in turns, as many steps as make about 10^6 voxels.
// `floor_ratio` = (the step's ns per voxel ÷ 2) ÷ the pass's: the ratio of BM_StepAgainstMemoryPass
// on two threads if the step scaled perfectly. side 100 is that step; side 48 (864 KiB, within a
// 1 MiB L2) shows what a step costs per voxel when its grid stays in a core's cache.
void BM_StepFloor(benchmark::State& state) {
  const int side = static_cast<int>(state.range(0));
  constexpr int kPassThreads = 2;
  FieldSet fields = MakeFields(1, 1, side);
  std::vector<double> memory(static_cast<std::size_t>(kSide) * kSide * kSide, 1.0);
  const double voxels = static_cast<double>(fields.grid().voxel_count());
  const int steps = std::max(1, static_cast<int>(1e6 / voxels));
  fields.Step(kDt);
  MemoryPass(memory, kPassThreads);
  double wall[2] = {0.0, 0.0};
  double cpu[2] = {0.0, 0.0};
  std::int64_t rounds = 0;
  for (auto _ : state) {
    Timed(
        [&] {
          for (int k = 0; k < steps; ++k) fields.Step(kDt);
        },
        &wall[0], &cpu[0]);
    Timed([&] { MemoryPass(memory, kPassThreads); }, &wall[1], &cpu[1]);
    benchmark::DoNotOptimize(memory.data());
    ++rounds;
  }
  const auto r = static_cast<double>(rounds);
  const double step_ns = 1e9 * wall[0] / r / (steps * voxels);
  const double pass_ns = 1e9 * wall[1] / r / static_cast<double>(memory.size());
  state.counters["step_ns_per_voxel"] = step_ns;
  state.counters["pass_ns_per_voxel"] = pass_ns;
  state.counters["floor_ratio"] = step_ns / kPassThreads / pass_ns;
}
BENCHMARK(BM_StepFloor)
    ->ArgName("side")
    ->Arg(48)
    ->Arg(kSide)
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);

// The x lines' solve alone, its portable and AVX2 copies in turns (the same bits) on the 10^4 x
// lines of the 100³ grid (the factorisation of BM_StepAgainstMemoryPass's substrate), groups of
// 16 lines shared between the threads. Counters: ms per sweep of each copy, and portable ÷ AVX2.
void BM_XLineCopies(benchmark::State& state) {
  using moreau::random_internal::InstructionSet;
  if (!moreau::random_internal::Supports(InstructionSet::kAvx2)) {
    state.SkipWithError("no AVX2 copy on this processor or build");
    return;
  }
  const int threads = static_cast<int>(state.range(0));
  const moreau::fields::FaceBoundary zero_flux;
  const moreau::fields::internal::LineSolve f =
      moreau::fields::internal::MakeLineSolve(kSide, kDt, kDt * 0.1 / 3, zero_flux, zero_flux);
  FieldSet fields = MakeFields(1, threads);
  std::span<double> c = fields.values(0);
  const std::int64_t groups = kSide * kSide / 16;
  const auto sweep = [&](InstructionSet set) {
#pragma omp parallel for num_threads(threads) schedule(static)
    for (std::int64_t g = 0; g < groups; ++g) {
      moreau::fields::internal::SolveXLinesOn(set, f, c.data() + g * 16 * kSide, kSide, 16);
    }
  };
  sweep(InstructionSet::kAvx2);
  double wall[2] = {0.0, 0.0};
  double cpu[2] = {0.0, 0.0};
  std::int64_t rounds = 0;
  for (auto _ : state) {
    Timed([&] { sweep(InstructionSet::kPortable); }, &wall[0], &cpu[0]);
    Timed([&] { sweep(InstructionSet::kAvx2); }, &wall[1], &cpu[1]);
    ++rounds;
  }
  const auto r = static_cast<double>(rounds);
  state.counters["portable_ms"] = 1e3 * wall[0] / r;
  state.counters["avx2_ms"] = 1e3 * wall[1] / r;
  state.counters["ratio"] = wall[0] / wall[1];
  state.counters["cpu_ratio"] = cpu[0] / cpu[1];
}
BENCHMARK(BM_XLineCopies)
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

// The field's part of a population step against the agents' part (the goal: with 10^5 agents the
// field step costs no more than the agents' step). 10^5 cells of radius 0.5 in 3D on the first
// 10^5 sites of a 47³ cubic lattice of spacing 48/47 filling the box [0, 48]³ (packing fraction
// 0.49, none touching at the start), a little noise (D = 10⁻⁴, h = 0.02), no growth or division,
// rules every kColonyInterval steps. One substrate (oxygen: D = 100, λ = 0.1, fixed value 1 on
// every face) on voxels of edge `spacing` (1 or 2: one or two cell diameters, the range of
// BioFVM/PhysiCell models), taken up by every cell at rate 10. Each round, on the same threads:
//   agents   kColonyInterval steps of a Population without fields (one rule step among them);
//   field    what a coupled population does once per rule step: clear the sources, deposit the
//            uptake at the agents, one FieldSet::Step, sample c and ∇c at the agents;
//   coupled  kColonyInterval steps of the same Population coupled to the field (a check: its CPU
//            time above the uncoupled one's is the field part as the population pays it, which
//            samples twice per rule step: after the field step and at the new roster).
// Counters: ms per agents' step (the mean Population::Step, its rule step included; the engine's
// and the rules' wall-clock seconds from the population's summary), ms of the field part per
// rule step and of its three pieces, ratio = field part ÷ one agents' step (wall; cpu_ratio CPU).
constexpr int kColonyInterval = 10;
constexpr int kColonyCells = 100000;
constexpr int kLatticeSide = 47;
constexpr double kBoxSide = 48.0;
constexpr double kUptake = 10.0;

moreau::particles::Population MakeColony(int threads) {
  using namespace moreau::particles;
  ParticleModel geometry;
  geometry.dimension = 3;
  Forces forces;
  forces.diffusion = 1e-4;
  EngineOptions options;
  options.h = 0.02;
  options.seed = 5;
  options.threads = threads;
  AgentType cell;
  cell.radius = 0.5;
  PopulationRules rules;
  rules.types = {cell};
  rules.interval = kColonyInterval;
  std::vector<double> x;
  const double a = kBoxSide / kLatticeSide;
  for (int i = 0; i < kColonyCells; ++i) {
    const int lattice[3] = {i % kLatticeSide, (i / kLatticeSide) % kLatticeSide,
                            i / (kLatticeSide * kLatticeSide)};
    for (int c : lattice) x.push_back(a * (c + 0.5));
  }
  const std::vector<int> types(kColonyCells, 0);
  return Population(geometry, forces, options, rules, types, x);
}

FieldSet MakeOxygen(double spacing, int threads) {
  Grid grid;
  grid.dimension = 3;
  grid.spacing = spacing;
  grid.upper = {kBoxSide, kBoxSide, kBoxSide};
  Substrate oxygen;
  oxygen.diffusion = 100.0;
  oxygen.decay = 0.1;
  oxygen.initial = 1.0;
  for (auto& face : oxygen.boundary) face = {moreau::fields::BoundaryKind::kFixed, 1.0};
  return FieldSet(grid, {oxygen}, threads);
}

// Wall and CPU seconds of the parts, summed over the rounds.
struct PartTimes {
  double wall[6] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
  double cpu[6] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
};
enum Part { kAgents, kDeposit, kFieldStep, kSample, kCoupled, kField };

// The field part on `fields` at the colony's agents (positions gathered before the timing: the
// rules gather them anyway).
void FieldPart(moreau::particles::Population& colony, FieldSet& fields,
               std::span<const double> volume, std::span<const double> uptake,
               std::vector<double>& value, std::vector<double>& gradient, PartTimes* t) {
  const std::span<const double> x = colony.CurrentPositions();
  const auto voxel = moreau::fields::Interpolation::kVoxel;
  const double dt = kColonyInterval * colony.engine().options().h;
  const double w = WallSeconds();
  const double c = CpuSeconds();
  Timed(
      [&] {
        fields.ClearSources();
        fields.Deposit(0, x, volume, {}, {}, uptake, {}, voxel);
      },
      &t->wall[kDeposit], &t->cpu[kDeposit]);
  Timed([&] { fields.Step(dt); }, &t->wall[kFieldStep], &t->cpu[kFieldStep]);
  Timed([&] { fields.Sample(0, x, voxel, value, gradient); }, &t->wall[kSample], &t->cpu[kSample]);
  t->cpu[kField] += CpuSeconds() - c;
  t->wall[kField] += WallSeconds() - w;
}

void StepColony(moreau::particles::Population& colony) {
  for (int i = 0; i < kColonyInterval; ++i) {
    if (!colony.Step()) throw std::runtime_error(colony.summary().message);
  }
}

void BM_FieldAgainstAgents(benchmark::State& state) {
  using namespace moreau::particles;
  const double spacing = static_cast<double>(state.range(0));
  const int threads = 2;
  Population agents = MakeColony(threads);
  Population coupled = MakeColony(threads);
  FieldCouplingOptions coupling;
  SubstrateResponse response;
  response.type = "cell";
  response.substrate = "oxygen";
  response.uptake_rate = kUptake;
  coupling.responses = {response};
  coupled.CoupleFields(MakeOxygen(spacing, threads), coupling);
  FieldSet fields = MakeOxygen(spacing, threads);
  const std::vector<double> volume(kColonyCells, AgentVolume(3, 0.5));
  const std::vector<double> uptake(kColonyCells, kUptake);
  std::vector<double> value(kColonyCells), gradient(3 * kColonyCells);
  PartTimes t;
  StepColony(agents);  // first touch and the first rule step outside the timing
  StepColony(coupled);
  FieldPart(agents, fields, volume, uptake, value, gradient, &t);
  t = PartTimes{};
  const PopulationSummary a0 = agents.summary();
  std::int64_t rounds = 0;
  for (auto _ : state) {
    Timed([&] { StepColony(agents); }, &t.wall[kAgents], &t.cpu[kAgents]);
    FieldPart(agents, fields, volume, uptake, value, gradient, &t);
    Timed([&] { StepColony(coupled); }, &t.wall[kCoupled], &t.cpu[kCoupled]);
    benchmark::DoNotOptimize(value.data());
    ++rounds;
  }
  const PopulationSummary a1 = agents.summary();
  const double r = static_cast<double>(rounds);
  const double steps = r * kColonyInterval;
  const double agents_step = t.wall[kAgents] / steps, agents_cpu = t.cpu[kAgents] / steps;
  const double engine_step =
      (a1.engine.stats.total_seconds - a0.engine.stats.total_seconds) / steps;
  state.counters["agents_step_ms"] = 1e3 * agents_step;
  state.counters["agents_cpu_ms"] = 1e3 * agents_cpu;
  state.counters["engine_step_ms"] = 1e3 * engine_step;
  state.counters["rule_step_ms"] = 1e3 * (a1.rules_seconds - a0.rules_seconds) / r;
  state.counters["field_ms"] = 1e3 * t.wall[kField] / r;
  state.counters["field_cpu_ms"] = 1e3 * t.cpu[kField] / r;
  state.counters["deposit_cpu_ms"] = 1e3 * t.cpu[kDeposit] / r;
  state.counters["step_cpu_ms"] = 1e3 * t.cpu[kFieldStep] / r;
  state.counters["sample_cpu_ms"] = 1e3 * t.cpu[kSample] / r;
  state.counters["ratio"] = t.wall[kField] / r / agents_step;
  state.counters["cpu_ratio"] = t.cpu[kField] / r / agents_cpu;
  // The coupled population's CPU time above the uncoupled one's, per rule step.
  state.counters["coupled_extra_cpu_ms"] = 1e3 * (t.cpu[kCoupled] - t.cpu[kAgents]) / r;
  const double voxels = static_cast<double>(fields.grid().voxel_count());
  state.counters["voxels"] = voxels;
  state.counters["step_cpu_ns_per_voxel"] = 1e9 * t.cpu[kFieldStep] / r / voxels;
}
BENCHMARK(BM_FieldAgainstAgents)
    ->ArgName("spacing")
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
