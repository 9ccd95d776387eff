// A changing population at scale: a 2D colony grown from one cell to 10^5 cells, against the
// fixed-population engine step at the same N.
//
// Workload: cells of birth radius 0.5 that grow at dr/dt = 0.002 and divide at rate λ = 0.01 (or
// at r = 0.7071), random division axis, small noise (D = 1e−4), h = 0.02, rules every 20 steps
// (docs/abm.md); no contact inhibition and one PBD sweep per step, so the count grows
// exponentially (doubling every ~3500 steps; slow enough that one sweep per step keeps the
// colony from piling up). Timed:
//   growth      all steps of the growth (engine steps + rule steps + repopulation) while
//               N ∈ [N_max/2, N_max] (the last doubling), per particle-step (Σ N over those steps);
//   fixed       the plain Engine on the final state (same radii, forces, options) for 500 steps,
//               per particle-step;
//   ratio       growth / fixed (1: a changing population costs no more than a fixed one).
// Times are process CPU seconds (meaningful for threads = 1 on a shared machine).
// One iteration (the growth is the measurement). MOREAU_BENCH_ABM_CELLS overrides N_max,
// MOREAU_BENCH_ABM_INTERVAL the rule interval (20; 5 and 1 are the worst cadences). Counters of
// the last doubling (growth_*) and of the fixed run (fixed_*): list builds, redone steps and the
// engine's wall-clock phase seconds (neighbour lists, sweeps, forces) and the rules' seconds.
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <ctime>
#include <vector>

#include "moreau/particles/population.h"

namespace {

using namespace moreau::particles;
// Process CPU seconds: on a shared machine (2 cores, other jobs) the wall clock of a
// single-threaded run counts the time other processes hold the core; the CPU time does not.
double CpuSeconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

void BM_GrowingColony(benchmark::State& state) {
  const char* env = std::getenv("MOREAU_BENCH_ABM_CELLS");
  const int n_max = env != nullptr ? std::atoi(env) : 100000;
  for (auto _ : state) {
    ParticleModel geometry;
    geometry.dimension = 2;
    Forces forces;
    forces.diffusion = 1e-4;
    EngineOptions options;
    options.h = 0.02;
    options.seed = 3;
    options.monitor_overlap = false;
    options.threads = static_cast<int>(state.range(0));
    AgentType cell;
    cell.radius = 0.5;
    cell.growth_rate = 0.002;
    cell.division_radius = 0.7071;
    cell.division_rate = 0.01;
    PopulationRules rules;
    rules.types = {cell};
    const char* every = std::getenv("MOREAU_BENCH_ABM_INTERVAL");
    rules.interval = every != nullptr ? std::atoi(every) : 20;
    rules.seed = 3;
    const std::vector<int> types{0};
    const std::vector<double> x0{0.0, 0.0};
    Population colony(geometry, forces, options, rules, types, x0);
    double growth_seconds = 0.0, growth_particle_steps = 0.0;
    EngineStats at_half;
    double rules_at_half = 0.0;
    bool half = false;
    while (colony.count() < n_max) {
      const int n = colony.count();
      const double t0 = CpuSeconds();
      if (!half && 2 * n >= n_max) {
        half = true;
        at_half = colony.engine().summary().stats;
        rules_at_half = colony.summary().rules_seconds;
      }
      if (!colony.Step()) break;
      if (2 * n >= n_max) {
        growth_seconds += CpuSeconds() - t0;
        growth_particle_steps += n;
      }
    }
    ParticleModel model = geometry;
    for (const Agent& a : colony.agents()) model.radius.push_back(a.radius);
    model.stable_ids.clear();
    options.check_initial_state = false;
    Engine fixed(model, forces, options, colony.Positions());
    const int steps = 500;
    const double t0 = CpuSeconds();
    for (int i = 0; i < steps; ++i) fixed.Step();
    const double fixed_per = (CpuSeconds() - t0) / (static_cast<double>(steps) * fixed.count());
    const double growth_per = growth_seconds / growth_particle_steps;
    const EngineStats end = colony.engine().summary().stats;
    const EngineStats fs = fixed.summary().stats;
    state.counters["growth_builds"] =
        static_cast<double>(end.neighbour_list_builds - at_half.neighbour_list_builds);
    state.counters["growth_retries"] =
        static_cast<double>(end.verlet_retries - at_half.verlet_retries);
    state.counters["growth_steps"] = static_cast<double>(end.steps - at_half.steps);
    state.counters["growth_neighbour_s"] = end.neighbour_seconds - at_half.neighbour_seconds;
    state.counters["growth_sweep_s"] = end.sweep_seconds - at_half.sweep_seconds;
    state.counters["growth_force_s"] = end.force_seconds - at_half.force_seconds;
    state.counters["growth_rules_s"] = colony.summary().rules_seconds - rules_at_half;
    state.counters["fixed_builds"] = static_cast<double>(fs.neighbour_list_builds);
    state.counters["fixed_neighbour_s"] = fs.neighbour_seconds;
    state.counters["fixed_sweep_s"] = fs.sweep_seconds;
    state.counters["fixed_force_s"] = fs.force_seconds;
    state.counters["cells"] = colony.count();
    state.counters["steps"] = static_cast<double>(colony.engine().step());
    state.counters["growth_s_per_particle_step"] = growth_per;
    state.counters["fixed_s_per_particle_step"] = fixed_per;
    state.counters["ratio"] = growth_per / fixed_per;
  }
}

BENCHMARK(BM_GrowingColony)->Arg(1)->Iterations(1)->Unit(benchmark::kSecond);

}  // namespace

BENCHMARK_MAIN();
