// Reading and writing motion-capture recordings: Qualisys.c3d (55 markers, 340 frames, float
// storage with 69 analog channels to skip; target < 20 ms per read), the DEC integer Gait.c3d,
// and writing the Qualisys recording as C3D, TRC and CSV.
//
//   build/release/mocap_bench
#include <benchmark/benchmark.h>

#include <filesystem>
#include <string>

#include "moreau/mocap/recording_io.h"

namespace {

using namespace moreau::mocap;

std::filesystem::path Sample(const std::string& name) {
  return std::filesystem::path(MOREAU_SOURCE_DIR) / ".." / "shared" / "data" / "mocap" / name;
}

void BM_ReadC3d(benchmark::State& state, const std::string& name) {
  const auto path = Sample(name);
  std::int64_t samples = 0;
  for (auto _ : state) {
    const Recording r = ReadRecording(path);
    samples = r.frames() * r.markers();
    benchmark::DoNotOptimize(r.positions().data());
  }
  state.counters["samples"] = static_cast<double>(samples);
}
BENCHMARK_CAPTURE(BM_ReadC3d, qualisys, std::string("Qualisys.c3d"))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_ReadC3d, gait_dec, std::string("Gait.c3d"))->Unit(benchmark::kMillisecond);

void BM_Write(benchmark::State& state, const std::string& extension) {
  const Recording r = ReadRecording(Sample("Qualisys.c3d"));
  const auto path = std::filesystem::temp_directory_path() / ("moreau_mocap_bench." + extension);
  for (auto _ : state) WriteRecording(r, path);
  std::filesystem::remove(path);
}
BENCHMARK_CAPTURE(BM_Write, c3d, std::string("c3d"))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Write, trc, std::string("trc"))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Write, csv, std::string("csv"))->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
