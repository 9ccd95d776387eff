// HDF5 trajectory size and write time for each storage setting (docs/io.md).
//
// Workload: the frames of examples/disks_1e5.toml: 11 frames of N = 10^5 disks of radius 0.5,
// 2D, ids 0 … N−1, positions uniform in that example's square [−280.25, 280.25]² (seeded; its
// random start) and moved a little from frame to frame. Each iteration writes the whole file
// (create, 11 frames, close with the sidecar) into a temporary folder.
//
//   BM_Hdf5Trajectory/single/compression    single = 0 (float64 positions) or 1 (float32),
//                                           compression = deflate level (0: none)
//
// Counters: s_per_frame, MB_per_s (of the float64 data handed to the writer) and file_MB (the
// size of trajectory.h5).
#include <benchmark/benchmark.h>

#include <cstdint>
#include <filesystem>
#include <numeric>
#include <string>
#include <vector>

#include <unistd.h>

#include "moreau/common/random.h"
#include "moreau/io/trajectory.h"

namespace {

constexpr std::int64_t kCount = 100000;
constexpr int kFrames = 11;
constexpr double kHalfWidth = 280.25;

struct Frames {
  std::vector<std::vector<double>> positions;
  std::vector<double> radii;
  std::vector<std::int64_t> ids;
};

Frames MakeFrames() {
  Frames f;
  moreau::SplitMix64 rng(2026);
  std::vector<double> x(2 * static_cast<std::size_t>(kCount));
  for (double& v : x) v = kHalfWidth * (2.0 * rng.Uniform01() - 1.0);
  for (int i = 0; i < kFrames; ++i) {
    f.positions.push_back(x);
    for (double& v : x) v = 0.99 * v + 0.01 * (2.0 * rng.Uniform01() - 1.0);
  }
  f.radii.assign(static_cast<std::size_t>(kCount), 0.5);
  f.ids.resize(static_cast<std::size_t>(kCount));
  std::iota(f.ids.begin(), f.ids.end(), 0);
  return f;
}

void BM_Hdf5Trajectory(benchmark::State& state) {
  const Frames frames = MakeFrames();
  moreau::io::Hdf5TrajectoryOptions options;
  options.precision = state.range(0) != 0 ? moreau::io::TrajectoryPrecision::kSingle
                                          : moreau::io::TrajectoryPrecision::kDouble;
  options.compression = static_cast<int>(state.range(1));
  const std::filesystem::path dir = std::filesystem::temp_directory_path() /
                                    ("moreau_trajectory_bench_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::filesystem::path path = dir / "trajectory.h5";
  for (auto _ : state) {
    auto writer = moreau::io::MakeHdf5Writer(path, options);
    for (int i = 0; i < kFrames; ++i) {
      const moreau::io::ParticleFrame frame{10 * i,
                                            0.2 * i,
                                            2,
                                            frames.positions[static_cast<std::size_t>(i)].data(),
                                            frames.ids.data(),
                                            frames.radii.data(),
                                            kCount,
                                            {}};
      writer->Write(frame);
    }
    writer->Close();
  }
  const auto bytes = static_cast<double>(std::filesystem::file_size(path));
  std::filesystem::remove_all(dir);
  state.counters["file_MB"] = bytes / 1e6;
  state.counters["s_per_frame"] = benchmark::Counter(
      kFrames, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  state.counters["MB_per_s"] = benchmark::Counter(
      kFrames * static_cast<double>(kCount) * 4 * 8 / 1e6,  // positions, radii, ids: 32 B each
      benchmark::Counter::kIsIterationInvariantRate);
}

}  // namespace

BENCHMARK(BM_Hdf5Trajectory)
    ->ArgNames({"single", "compression"})
    ->Args({0, 0})
    ->Args({1, 0})
    ->Args({0, 1})
    ->Args({1, 1})
    ->Args({1, 4})
    ->Args({1, 9})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

BENCHMARK_MAIN();
