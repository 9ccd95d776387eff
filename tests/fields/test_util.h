// Shared helpers for the diffusing-field tests.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include "moreau/common/error.h"
#include "moreau/fields/field_set.h"

namespace moreau::fields::testing {

// A grid of n voxels of edge h per axis from the origin (n[2] ignored in 2D).
inline Grid GridOf(int dimension, std::array<int, 3> n, double h) {
  Grid g;
  g.dimension = dimension;
  g.spacing = h;
  for (int a = 0; a < 3; ++a) g.upper[a] = n[a] * h;
  return g;
}

inline Substrate SubstrateWith(double diffusion, double decay, BoundaryKind kind) {
  Substrate s;
  s.diffusion = diffusion;
  s.decay = decay;
  for (FaceBoundary& f : s.boundary) f.kind = kind;
  return s;
}

// Sets substrate s's values to f(centre) (k coordinates).
inline void Fill(FieldSet& fields, int s, const std::function<double(const double*)>& f) {
  std::span<double> c = fields.values(s);
  double x[3] = {0.0, 0.0, 0.0};
  for (std::size_t v = 0; v < c.size(); ++v) {
    fields.grid().Centre(static_cast<std::int64_t>(v), x);
    c[v] = f(x);
  }
}

// max_v |c_v − f(centre_v)|.
inline double MaxError(const FieldSet& fields, int s,
                       const std::function<double(const double*)>& f) {
  std::span<const double> c = fields.values(s);
  double x[3] = {0.0, 0.0, 0.0};
  double worst = 0.0;
  for (std::size_t v = 0; v < c.size(); ++v) {
    fields.grid().Centre(static_cast<std::int64_t>(v), x);
    worst = std::max(worst, std::abs(c[v] - f(x)));
  }
  return worst;
}

// The least-squares slope of log(error) against log(size).
inline double LogSlope(const std::vector<double>& size, const std::vector<double>& error) {
  double sx = 0.0, sy = 0.0, sxx = 0.0, sxy = 0.0;
  const double n = static_cast<double>(size.size());
  for (std::size_t i = 0; i < size.size(); ++i) {
    const double x = std::log(size[i]);
    const double y = std::log(error[i]);
    sx += x;
    sy += y;
    sxx += x * x;
    sxy += x * y;
  }
  return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

// Runs f, expects an InputError whose key is `key`.
inline void ExpectKeyError(const std::function<void()>& f, const std::string& key) {
  try {
    f();
    ADD_FAILURE() << "no InputError; expected one for '" << key << "'";
  } catch (const InputError& e) {
    EXPECT_EQ(e.key(), key) << e.what();
  }
}

}  // namespace moreau::fields::testing
