// The cost of one OpenMP parallel region (docs/benchmarks.md, "OpenMP waiting"): a `parallel for`
// summing 20 000 doubles on 1 or 2 threads. The difference between the two rows is what waking the
// second thread and joining it costs, under whatever OMP_WAIT_POLICY / GOMP_SPINCOUNT the caller
// set (this binary sets none: compare `OMP_WAIT_POLICY=passive` with `GOMP_SPINCOUNT=10000`).
#include <benchmark/benchmark.h>

#include <vector>

namespace {

void BM_Region(benchmark::State& state) {
  const int threads = static_cast<int>(state.range(0));
  const std::vector<double> a(20000, 1.0);
  for (auto _ : state) {
    double sum = 0.0;
#pragma omp parallel for num_threads(threads) reduction(+ : sum) schedule(static)
    for (int i = 0; i < static_cast<int>(a.size()); ++i) sum += a[static_cast<std::size_t>(i)];
    benchmark::DoNotOptimize(sum);
  }
}
BENCHMARK(BM_Region)->Arg(1)->Arg(2)->UseRealTime()->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
