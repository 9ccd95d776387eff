// The engine's profile: wall-clock seconds per named stage, accumulated by scoped timers, and
// reported as EngineStats' *_seconds (the keys of the summary and the checkpoint).
#pragma once

#include <array>
#include <chrono>
#include <cstddef>

#include "moreau/particles/engine.h"

namespace moreau::particles::internal {

// The stages of the engine's work. A step is a prediction (drift, noise, attraction, density),
// list builds when needed (with the storage reorder), the projection sweeps and the overlap
// monitor; kTotal times whole steps, repopulations and relaxations; kSetup the constructor.
enum class Stage { kSetup, kPrediction, kListBuild, kSweep, kMonitor, kTotal };
inline constexpr std::size_t kStageCount = 6;

class StageProfile {
 public:
  using Clock = std::chrono::steady_clock;

  // Adds the wall-clock time from its construction to the end of its scope to one stage.
  class Timer {
   public:
    Timer(StageProfile* profile, Stage stage)
        : seconds_(&profile->seconds_[Index(stage)]), start_(Clock::now()) {}
    ~Timer() { *seconds_ += std::chrono::duration<double>(Clock::now() - start_).count(); }
    Timer(const Timer&) = delete;
    Timer& operator=(const Timer&) = delete;

   private:
    double* seconds_;
    Clock::time_point start_;
  };

  [[nodiscard]] Timer Time(Stage stage) { return Timer(this, stage); }
  double seconds(Stage stage) const { return seconds_[Index(stage)]; }
  void Clear(Stage stage) { seconds_[Index(stage)] = 0.0; }

  // The stages into EngineStats: setup_seconds, force_seconds (kPrediction), neighbour_seconds
  // (kListBuild), sweep_seconds, monitor_seconds, total_seconds; and the profile of such stats
  // (a checkpoint's, whose timings carry on).
  void Report(EngineStats* stats) const {
    for (std::size_t s = 0; s < kStageCount; ++s) stats->*kFields[s] = seconds_[s];
  }
  static StageProfile Of(const EngineStats& stats) {
    StageProfile profile;
    for (std::size_t s = 0; s < kStageCount; ++s) profile.seconds_[s] = stats.*kFields[s];
    return profile;
  }

 private:
  static constexpr std::size_t Index(Stage stage) { return static_cast<std::size_t>(stage); }
  static constexpr std::array<double EngineStats::*, kStageCount> kFields = {
      &EngineStats::setup_seconds, &EngineStats::force_seconds,   &EngineStats::neighbour_seconds,
      &EngineStats::sweep_seconds, &EngineStats::monitor_seconds, &EngineStats::total_seconds};

  std::array<double, kStageCount> seconds_{};
};

}  // namespace moreau::particles::internal
