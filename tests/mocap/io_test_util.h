// Helpers for the recording reader/writer tests: the sample data, a scratch directory and a
// sample-by-sample comparison of two recordings.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <cmath>
#include <filesystem>
#include <string>

#include "moreau/mocap/recording.h"

namespace moreau::mocap::testing {

inline std::filesystem::path MocapData(const std::string& name) {
  return std::filesystem::path(MOREAU_SOURCE_DIR) / ".." / "shared" / "data" / "mocap" / name;
}

// A fresh directory under the system temp directory, removed with everything in it.
class ScratchDir {
 public:
  ScratchDir() {
    static std::atomic<int> counter{0};
    path_ = std::filesystem::temp_directory_path() /
            ("moreau_mocap_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~ScratchDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;
  std::filesystem::path operator/(const std::string& name) const { return path_ / name; }
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

// Same labels, frames, first frame, units, rate (to float precision), observed masks, and
// positions within `tolerance` (absolute, in the recordings' units).
inline void ExpectSameRecording(const Recording& a, const Recording& b, double tolerance) {
  ASSERT_EQ(a.labels(), b.labels());
  ASSERT_EQ(a.frames(), b.frames());
  EXPECT_EQ(a.first_frame(), b.first_frame());
  EXPECT_EQ(a.units(), b.units());
  EXPECT_NEAR(a.rate(), b.rate(), 1e-6 * a.rate());
  std::int64_t mismatched_mask = 0;
  double worst = 0.0;
  for (std::int64_t f = 0; f < a.frames(); ++f) {
    for (int m = 0; m < a.markers(); ++m) {
      if (a.observed(f, m) != b.observed(f, m)) {
        ++mismatched_mask;
      } else if (a.observed(f, m)) {
        worst = std::max(worst, (a.point(f, m) - b.point(f, m)).cwiseAbs().maxCoeff());
      }
    }
  }
  EXPECT_EQ(mismatched_mask, 0);
  EXPECT_LE(worst, tolerance);
}

}  // namespace moreau::mocap::testing
