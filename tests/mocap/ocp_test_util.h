// Synthetic recordings for the optimal-control gap-fill tests: markers fixed on moving rigid
// bodies, so distances within a body are exact and the truth of every hidden sample is known.
#pragma once

#include <fmt/format.h>
#include <Eigen/Geometry>
#include <cmath>
#include <string>
#include <vector>

#include "mocap/synthetic.h"
#include "moreau/common/error.h"
#include "moreau/mocap/fill.h"
#include "moreau/mocap/ocp_fill.h"
#include "moreau/mocap/recording.h"

namespace moreau::mocap::testing {

// `bodies` rigid bodies of `per_body` markers each (offsets up to ~0.1 m, non-coplanar), in metres,
// rotating and translating smoothly; body b is offset by 0.5 m along x and moves with its own
// phase, so distances between bodies vary.
inline Recording RigidBodies(int bodies, int per_body, std::int64_t frames, double rate) {
  const Eigen::Vector3d offsets[] = {{0.10, 0.00, 0.00},   {0.00, 0.08, 0.00},
                                     {0.00, 0.00, 0.09},   {-0.07, -0.05, 0.02},
                                     {0.05, -0.06, -0.07}, {-0.04, 0.07, 0.06}};
  std::vector<std::string> labels;
  for (int b = 0; b < bodies; ++b) {
    for (int k = 0; k < per_body; ++k) labels.push_back(fmt::format("B{}M{}", b, k));
  }
  Recording rec(labels, frames, rate, "m");
  for (std::int64_t f = 0; f < frames; ++f) {
    const double t = static_cast<double>(f) / rate;
    for (int b = 0; b < bodies; ++b) {
      const double phase = 1.3 * b;
      const double angle = 0.8 * std::sin(2.0 * M_PI * 0.7 * t + phase);
      const Eigen::Vector3d axis = Eigen::Vector3d(0.3, 1.0, 0.2 + 0.5 * b).normalized();
      const Eigen::Matrix3d r = Eigen::AngleAxisd(angle, axis).toRotationMatrix();
      const Eigen::Vector3d c(0.5 * b + 0.3 * t, 0.1 * std::sin(2.0 * M_PI * 0.5 * t + phase),
                              1.0 + 0.05 * std::cos(2.0 * M_PI * 0.9 * t));
      for (int k = 0; k < per_body; ++k) {
        rec.SetPoint(f, b * per_body + k, c + r * offsets[k % 6] * (1.0 + 0.1 * (k / 6)));
      }
    }
  }
  return rec;
}

// The message of the InputError that fill() throws, or "no error".
template <typename Fill>
std::string InputErrorOf(const Fill& fill) {
  try {
    fill();
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

// The baseline fills of `gaps` by each of `methods` (fill.h), as candidates of FillGapsOcp.
struct Baselines {
  std::vector<Recording> recordings;
  std::vector<CandidateFill> candidates;
  Baselines(const Recording& in, const std::vector<Gap>& gaps,
            const std::vector<FillMethod>& methods) {
    recordings.reserve(methods.size());
    for (const FillMethod m : methods) {
      FillOptions o;
      o.method = m;
      FillGaps(in, gaps, o, &recordings.emplace_back());
      candidates.push_back({std::string(ToString(m)), &recordings.back()});
    }
  }
};

}  // namespace moreau::mocap::testing
