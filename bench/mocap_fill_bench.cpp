// Time to fill one 0.5 s gap (100 frames) of one marker in a 55-marker, 340-frame, 200 Hz
// walking-like recording (tests/mocap/synthetic.h), for each established method; the counter
// mean_error_mm is the fill's mean Euclidean error against the truth.
//
//   build/release/mocap_fill_bench --benchmark_counters_tabular=true
#include <benchmark/benchmark.h>

#include "../tests/mocap/synthetic.h"
#include "moreau/mocap/evaluate.h"
#include "moreau/mocap/fill.h"

namespace {

using namespace moreau::mocap;

constexpr int kMarker = 17;  // on the left forearm
const Gap kGap{kMarker, 120, 219};

const Recording& Truth() {
  static const Recording truth = testing::MakeWalkingRecording(340, 200.0, 2024);
  return truth;
}

const Recording& Gapped() {
  static const Recording gapped = [] {
    Recording r = Truth();
    for (std::int64_t f = kGap.first; f <= kGap.last; ++f) r.ClearPoint(f, kGap.marker);
    return r;
  }();
  return gapped;
}

void BM_FillGap(benchmark::State& state) {
  FillOptions options;
  options.method = static_cast<FillMethod>(state.range(0));
  state.SetLabel(std::string(ToString(options.method)));
  GapFill fill;
  for (auto _ : state) {
    fill = FillGap(Gapped(), kGap, options);
    benchmark::DoNotOptimize(fill.points.data());
  }
  if (fill.status != GapStatus::kFilled) {
    state.SkipWithError(fill.message.c_str());
    return;
  }
  double error = 0.0;
  for (std::int64_t f = kGap.first; f <= kGap.last; ++f) {
    error += (fill.points.col(f - kGap.first) - Truth().point(f, kMarker)).norm();
  }
  state.counters["mean_error_mm"] = error / static_cast<double>(kGap.length());
  state.counters["gap_frames"] = static_cast<double>(kGap.length());
}
BENCHMARK(BM_FillGap)
    ->DenseRange(0, static_cast<int>(FillMethod::kPca))
    ->Unit(benchmark::kMillisecond);

// The whole protocol: every method, gaps of 0.1/0.2/0.5/1.0 s, 10 trials each, on 1 thread.
void BM_EvaluateFillMethods(benchmark::State& state) {
  EvaluationOptions options;
  options.trials = 10;
  options.threads = static_cast<int>(state.range(0));
  EvaluationSummary summary;
  for (auto _ : state) {
    summary = EvaluateFillMethods(Truth(), options);
    benchmark::DoNotOptimize(summary.rows.data());
  }
  state.counters["fills"] = static_cast<double>(summary.rows.size());
  state.counters["threads"] = static_cast<double>(options.threads);
}
BENCHMARK(BM_EvaluateFillMethods)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
