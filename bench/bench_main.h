// The end of main() for the benchmarks that run with OpenMP waiting as moreau's command line
// chooses it (moreau/common/openmp_wait.h): Google Benchmark's flags, then every benchmark.
#pragma once

#include <benchmark/benchmark.h>

namespace moreau::bench {

inline int RunBenchmarks(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}

}  // namespace moreau::bench
