// Random particle configurations for the tests of the engine's parts (cell list, neighbour list,
// colouring, prediction).
#pragma once

#include <vector>

#include "moreau/common/random.h"
#include "moreau/particles/engine.h"

namespace moreau::particles::testing {

// N polydisperse particles (radii in [0.2, 0.6)) placed by random sequential addition in
// [0, L]^k, periodic on the given axes.
struct RandomConfiguration {
  ParticleModel model;
  std::vector<double> x;

  RandomConfiguration(int k, std::array<bool, 3> periodic, int n, double L, std::uint64_t seed) {
    model.dimension = k;
    SplitMix64 rng(seed);
    for (int i = 0; i < n; ++i) model.radius.push_back(0.2 + 0.4 * rng.Uniform01());
    model.periodic = periodic;
    model.domain_lo = {0, 0, 0};
    model.domain_hi = {L, L, L};
    x = RandomSequentialAddition(model, {0, 0, 0}, {L, L, L}, seed + 1);
  }
};

}  // namespace moreau::particles::testing
