// Wall-clock time of the ocp fill through FillGaps (gap_fill.h, method ocp: the candidate fills,
// the network, the prior and, in the *OptimalControl variants, the windows' optimal control; all
// threads) on synthetic recordings of rigid bodies with 4 markers each (smooth rotation and
// translation, mm):
//   Qualisys-sized: 56 markers, 340 frames at 200 Hz, 10 gaps of 0.2–0.5 s;
//   long: 40 markers, 5000 frames at 100 Hz, 50 gaps of 0.2–0.5 s.
//
//   OMP_NUM_THREADS=2 build/release/ocp_fill_bench --benchmark_counters_tabular=true
#include <benchmark/benchmark.h>
#include <fmt/format.h>

#include <Eigen/Geometry>
#include <cmath>
#include <numbers>

#include "moreau/common/random.h"
#include "moreau/mocap/gap_fill.h"

namespace {

using namespace moreau::mocap;

Recording Bodies(int bodies, std::int64_t frames, double rate) {
  const Eigen::Vector3d offsets[] = {
      {100.0, 0.0, 0.0}, {0.0, 80.0, 0.0}, {0.0, 0.0, 90.0}, {-70.0, -50.0, 20.0}};
  std::vector<std::string> labels;
  for (int b = 0; b < bodies; ++b) {
    for (int k = 0; k < 4; ++k) labels.push_back(fmt::format("B{}M{}", b, k));
  }
  Recording rec(labels, frames, rate, "mm");
  for (std::int64_t f = 0; f < frames; ++f) {
    const double t = static_cast<double>(f) / rate;
    for (int b = 0; b < bodies; ++b) {
      const double phase = 0.7 * b;
      const Eigen::Matrix3d r =
          Eigen::AngleAxisd(0.8 * std::sin(2.0 * std::numbers::pi * 0.6 * t + phase),
                            Eigen::Vector3d(0.3, 1.0, 0.1 * b).normalized())
              .toRotationMatrix();
      const Eigen::Vector3d c(400.0 * b + 300.0 * std::sin(0.5 * t), 100.0 * std::cos(t + phase),
                              1000.0);
      for (int k = 0; k < 4; ++k) rec.SetPoint(f, 4 * b + k, c + r * offsets[k]);
    }
  }
  return rec;
}

// `count` gaps of 0.2–0.5 s at random markers and times (seeded), at least 0.1 s from the ends.
std::vector<Gap> MakeGaps(Recording& rec, int count, std::uint64_t seed) {
  moreau::SplitMix64 rng(seed);
  std::vector<Gap> gaps;
  const auto margin = static_cast<std::int64_t>(0.1 * rec.rate()) + 1;
  while (static_cast<int>(gaps.size()) < count) {
    const int marker = static_cast<int>(rng.Next() % static_cast<std::uint64_t>(rec.markers()));
    const auto length = static_cast<std::int64_t>((0.2 + 0.3 * rng.Uniform01()) * rec.rate());
    const auto span = static_cast<std::uint64_t>(rec.frames() - length - 2 * margin);
    const std::int64_t first = margin + static_cast<std::int64_t>(rng.Next() % span);
    bool free = true;
    for (std::int64_t f = first - margin; f <= first + length + margin; ++f) {
      for (int m = 4 * (marker / 4); m < 4 * (marker / 4) + 4; ++m)
        free = free && rec.observed(f, m);
    }
    if (!free) continue;  // keep each body with at least three visible markers
    for (std::int64_t f = first; f < first + length; ++f) rec.ClearPoint(f, marker);
    gaps.push_back(Gap{marker, first, first + length - 1});
  }
  return gaps;
}

void Run(benchmark::State& state, int bodies, std::int64_t frames, double rate, int count,
         bool optimal_control) {
  Recording rec = Bodies(bodies, frames, rate);
  const std::vector<Gap> gaps = MakeGaps(rec, count, 7);
  GapFillOptions options;
  options.method = GapFillMethod::kOcp;
  options.ocp.optimal_control = optimal_control;
  Recording out;
  FillSummary summary;
  for (auto _ : state) {
    summary = FillGaps(rec, gaps, options, &out);
    benchmark::DoNotOptimize(out.positions().data());
  }
  int solved = 0;
  for (const GapReport& g : summary.gaps) solved += g.message.starts_with("optimal control");
  state.counters["gaps"] = count;
  state.counters["filled"] = static_cast<double>(summary.gaps_filled);
  state.counters["solved"] = solved;  // filled by the optimal control (not its prior)
}

void BM_OcpFillQualisysSized(benchmark::State& state) { Run(state, 14, 340, 200.0, 10, false); }
void BM_OcpFillLong(benchmark::State& state) { Run(state, 10, 5000, 100.0, 50, false); }
void BM_OcpFillQualisysSizedOptimalControl(benchmark::State& state) {
  Run(state, 14, 340, 200.0, 10, true);
}
void BM_OcpFillLongOptimalControl(benchmark::State& state) {
  Run(state, 10, 5000, 100.0, 50, true);
}

// Time against recording length (state.range(0) frames at 100 Hz, 40 markers) and gap count
// (state.range(1) gaps of 0.2–0.5 s), optimal control on: it should grow with the gaps only.
void BM_OcpFillScaling(benchmark::State& state) {
  Run(state, 10, state.range(0), 100.0, static_cast<int>(state.range(1)), true);
}

BENCHMARK(BM_OcpFillScaling)
    ->ArgNames({"frames", "gaps"})
    ->Args({1000, 10})
    ->Args({2000, 10})
    ->Args({4000, 10})
    ->Args({2000, 5})
    ->Args({2000, 20})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(1);
BENCHMARK(BM_OcpFillQualisysSized)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_OcpFillLong)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);
BENCHMARK(BM_OcpFillQualisysSizedOptimalControl)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_OcpFillLongOptimalControl)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(1);

}  // namespace

BENCHMARK_MAIN();
