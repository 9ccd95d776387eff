// Synthetic, complete motion-capture recordings with known structure, for tests and benchmarks:
// straight lines, polynomials in time, one rigid body, low-rank motion, and a multi-segment
// body (55 markers on 15 segments, walking-like joint motion).
#pragma once

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <Eigen/Geometry>

#include "moreau/common/random.h"
#include "moreau/mocap/recording.h"

namespace moreau::mocap::testing {

// A complete recording with position(marker, t) at t = f / rate (units "mm").
inline Recording MakeRecording(int markers, std::int64_t frames, double rate,
                               const std::function<Eigen::Vector3d(int, double)>& position) {
  std::vector<std::string> labels;
  for (int m = 0; m < markers; ++m) labels.push_back(fmt::format("M{}", m));
  Recording r(labels, frames, rate, "mm");
  for (std::int64_t f = 0; f < frames; ++f) {
    for (int m = 0; m < markers; ++m) {
      r.SetPoint(f, m, position(m, static_cast<double>(f) / rate));
    }
  }
  return r;
}

// Markers moving on straight lines at constant speed (different directions and speeds).
inline Recording MakeLineRecording(int markers, std::int64_t frames, double rate) {
  return MakeRecording(markers, frames, rate, [](int m, double t) {
    const Eigen::Vector3d start(100.0 * m, -50.0 + 10.0 * m, 900.0);
    const Eigen::Vector3d velocity(800.0 - 30.0 * m, 120.0 + 5.0 * m, -40.0 * m);
    return Eigen::Vector3d(start + velocity * t);
  });
}

// Markers following cubic polynomials in time.
inline Recording MakeCubicRecording(int markers, std::int64_t frames, double rate) {
  return MakeRecording(markers, frames, rate, [](int m, double t) {
    const double s = t - 0.4;
    return Eigen::Vector3d(10.0 * m + 300.0 * s - 500.0 * s * s * s,
                           20.0 - 80.0 * s * s + 900.0 * s * s * s * (1.0 + 0.1 * m),
                           1000.0 + 50.0 * s + 200.0 * s * s - 300.0 * s * s * s);
  });
}

// A rigid body: `markers` points fixed in the body (seeded), turning about a moving axis while
// translating; R(t) = exp of a smooth rotation vector.
inline Recording MakeRigidBodyRecording(int markers, std::int64_t frames, double rate,
                                        std::uint64_t seed) {
  SplitMix64 rng(seed);
  std::vector<Eigen::Vector3d> body;
  for (int m = 0; m < markers; ++m) {
    body.emplace_back(200.0 * (rng.Uniform01() - 0.5), 200.0 * (rng.Uniform01() - 0.5),
                      200.0 * (rng.Uniform01() - 0.5));
  }
  return MakeRecording(markers, frames, rate, [body](int m, double t) {
    const Eigen::Vector3d rotation(0.8 * std::sin(2.1 * t), 1.5 * t, 0.5 * std::cos(1.3 * t));
    const Eigen::AngleAxisd turn(rotation.norm(), rotation.normalized());
    const Eigen::Vector3d shift(600.0 * t, 100.0 * std::sin(3.0 * t), 900.0 + 40.0 * t * t);
    return Eigen::Vector3d(turn * body[static_cast<std::size_t>(m)] + shift);
  });
}

// Low-rank motion: every coordinate is a fixed (seeded) linear combination of `rank` smooth time
// signals plus an offset, so the centred data matrix has rank ≤ rank.
inline Recording MakeLowRankRecording(int markers, std::int64_t frames, double rate, int rank,
                                      std::uint64_t seed) {
  SplitMix64 rng(seed);
  Eigen::MatrixXd mix(3 * markers, rank);
  Eigen::VectorXd offset(3 * markers);
  for (Eigen::Index i = 0; i < mix.rows(); ++i) {
    for (Eigen::Index j = 0; j < rank; ++j) mix(i, j) = 100.0 * (rng.Uniform01() - 0.5);
    offset[i] = 1000.0 * (rng.Uniform01() - 0.5);
  }
  return MakeRecording(markers, frames, rate, [mix, offset, rank](int m, double t) {
    Eigen::VectorXd signal(rank);
    for (int j = 0; j < rank; ++j) {
      signal[j] = std::sin(2.0 * M_PI * (0.6 + 0.45 * j) * t + 0.7 * j);
    }
    return Eigen::Vector3d(offset.segment<3>(3 * m) + mix.middleRows(3 * m, 3) * signal);
  });
}

// A walking-like multi-segment body in mm: 15 segments (pelvis, trunk, head, upper arms,
// forearms, hands, thighs, shanks, feet) with 55 markers fixed on them (seeded offsets); each
// joint swings about its own axis at the 1 Hz stride frequency, the pelvis moves forward at
// 1.2 m/s with a vertical bob and a small yaw.
inline Recording MakeWalkingRecording(std::int64_t frames, double rate, std::uint64_t seed) {
  struct Segment {
    int parent;
    Eigen::Vector3d joint;  // joint position in the parent's frame
    Eigen::Vector3d axis;
    double amplitude, phase;
    int markers;
  };
  const Eigen::Vector3d x = Eigen::Vector3d::UnitX(), y = Eigen::Vector3d::UnitY();
  const std::vector<Segment> segments = {
      {-1, {0, 0, 0}, Eigen::Vector3d::UnitZ(), 0.1, 0.0, 4},  // pelvis
      {0, {0, 0, 100}, y, 0.08, 1.0, 5},                       // trunk
      {1, {0, 0, 450}, y, 0.1, 2.0, 4},                        // head
      {1, {0, 180, 400}, y, 0.5, 0.0, 3},                      // upper arm L
      {3, {0, 0, -300}, y, 0.4, 0.5, 3},                       // forearm L
      {4, {0, 0, -260}, x, 0.2, 1.0, 3},                       // hand L
      {1, {0, -180, 400}, y, 0.5, M_PI, 3},                    // upper arm R
      {6, {0, 0, -300}, y, 0.4, M_PI + 0.5, 3},                // forearm R
      {7, {0, 0, -260}, x, 0.2, M_PI + 1.0, 3},                // hand R
      {0, {0, 90, -50}, y, 0.5, M_PI, 4},                      // thigh L
      {9, {0, 0, -420}, y, 0.6, M_PI + 1.2, 4},                // shank L
      {10, {0, 0, -400}, y, 0.3, M_PI + 2.0, 4},               // foot L
      {0, {0, -90, -50}, y, 0.5, 0.0, 4},                      // thigh R
      {12, {0, 0, -420}, y, 0.6, 1.2, 4},                      // shank R
      {13, {0, 0, -400}, y, 0.3, 2.0, 4},                      // foot R
  };
  SplitMix64 rng(seed);
  std::vector<std::pair<int, Eigen::Vector3d>> markers;  // (segment, position in its frame)
  for (std::size_t s = 0; s < segments.size(); ++s) {
    const Eigen::Vector3d along =
        s + 1 < segments.size() && segments[s + 1].parent == static_cast<int>(s)
            ? segments[s + 1].joint
            : Eigen::Vector3d(0, 0, -150);
    for (int k = 0; k < segments[s].markers; ++k) {
      const Eigen::Vector3d jitter(120.0 * (rng.Uniform01() - 0.5), 120.0 * (rng.Uniform01() - 0.5),
                                   60.0 * (rng.Uniform01() - 0.5));
      markers.emplace_back(static_cast<int>(s), along * (0.2 + 0.6 * rng.Uniform01()) + jitter);
    }
  }
  return MakeRecording(
      static_cast<int>(markers.size()), frames, rate, [segments, markers](int m, double t) {
        std::vector<Eigen::Isometry3d> pose(segments.size());
        for (std::size_t s = 0; s < segments.size(); ++s) {
          const Segment& seg = segments[s];
          const double angle = seg.amplitude * std::sin(2.0 * M_PI * t + seg.phase);
          Eigen::Isometry3d local = Eigen::Isometry3d::Identity();
          local.translate(seg.joint).rotate(Eigen::AngleAxisd(angle, seg.axis));
          if (seg.parent < 0) {
            local.pretranslate(
                Eigen::Vector3d(1200.0 * t, 0.0, 950.0 + 20.0 * std::sin(4.0 * M_PI * t)));
            pose[s] = local;
          } else {
            pose[s] = pose[static_cast<std::size_t>(seg.parent)] * local;
          }
        }
        const auto& [segment, local] = markers[static_cast<std::size_t>(m)];
        return Eigen::Vector3d(pose[static_cast<std::size_t>(segment)] * local);
      });
}

// Hides marker m over frames first … last and returns the gap.
inline Gap Hide(Recording& rec, int marker, std::int64_t first, std::int64_t last) {
  for (std::int64_t f = first; f <= last; ++f) rec.ClearPoint(f, marker);
  return Gap{marker, first, last};
}

// Largest distance between the filled and true positions over a gap; +∞ when a frame of the gap
// is still unobserved in `filled`.
inline double GapMaxError(const Recording& filled, const Recording& truth, const Gap& gap) {
  double e = 0.0;
  for (std::int64_t f = gap.first; f <= gap.last; ++f) {
    if (!filled.observed(f, gap.marker)) return std::numeric_limits<double>::infinity();
    e = std::max(e, (filled.point(f, gap.marker) - truth.point(f, gap.marker)).norm());
  }
  return e;
}

}  // namespace moreau::mocap::testing
