// Shared helpers for the particle engine tests.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <string>

#include "moreau/common/error.h"
#include "moreau/particles/engine.h"

namespace moreau::particles::testing {

// Runs f, expects an InputError whose message contains `needle`.
inline void ExpectInputError(const std::function<void()>& f, const std::string& needle) {
  try {
    f();
    ADD_FAILURE() << "no InputError; expected one mentioning '" << needle << "'";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(needle), std::string::npos)
        << "message '" << e.what() << "' does not mention '" << needle << "'";
  }
}

// O(N²) largest pair overlap with minimum images: an independent check of the engine's.
inline double BruteForceMaxOverlap(const ParticleModel& m, const std::vector<double>& x) {
  const int k = m.dimension;
  double worst = 0.0;
  for (int i = 0; i < m.count(); ++i) {
    for (int j = i + 1; j < m.count(); ++j) {
      double r2 = 0.0;
      for (int a = 0; a < k; ++a) {
        double d = x[static_cast<std::size_t>(k * i + a)] - x[static_cast<std::size_t>(k * j + a)];
        if (m.periodic[static_cast<std::size_t>(a)]) {
          const double L =
              m.domain_hi[static_cast<std::size_t>(a)] - m.domain_lo[static_cast<std::size_t>(a)];
          d -= L * std::round(d / L);
        }
        r2 += d * d;
      }
      const double c =
          m.radius[static_cast<std::size_t>(i)] + m.radius[static_cast<std::size_t>(j)];
      worst = std::max(worst, c - std::sqrt(r2));
    }
  }
  return worst;
}

}  // namespace moreau::particles::testing
