// A progress bar on stderr, drawn only when stderr is a terminal (never in pipes, files or CI).
#pragma once

#include <chrono>
#include <cstdint>
#include <string>

namespace moreau::cli {

class ProgressBar {
 public:
  ProgressBar(std::string label, std::int64_t total);
  ~ProgressBar();
  ProgressBar(const ProgressBar&) = delete;
  ProgressBar& operator=(const ProgressBar&) = delete;

  // Cheap when called every step: redraws at most ten times a second.
  void Update(std::int64_t done);
  void Finish();

 private:
  std::string label_;
  std::int64_t total_;
  bool enabled_;
  bool finished_ = false;
  std::chrono::steady_clock::time_point start_;
  std::chrono::steady_clock::time_point last_draw_;
};

}  // namespace moreau::cli
