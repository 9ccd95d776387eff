// Initial states of the particle model: the feasibility check of given positions and random
// sequential addition. Both search their pairs with the particle core's cell grid (O(N) for
// bounded density), so they sit above the lists, beside the engine.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "moreau/particles/model.h"

namespace moreau::particles {

// Feasibility of positions (size k·N, id order) for the model, with tolerance tol ≥ 0 on every
// constraint (a pair may overlap by at most tol·(r_i + r_j), a particle may be inside a wall or
// obstacle by at most tol·r_i). Throws InputError naming the first violation found, e.g.
//   "initial state: particles 3 and 17 overlap by 0.05 (fix it with FixOverlaps / --fix-overlaps)"
//   "initial state: particle 5 is inside walls[2] by 0.1"
//   "initial state: particle 9 is inside spheres[0] by 0.2", "… inside segments[1] …",
//   "initial state: position of particle 4 is not finite",
//   "initial state: positions have 99 entries for 50 particles in 2D".
// Positions outside a periodic domain are fine (they are wrapped).
void CheckInitialState(const ParticleModel& model, std::span<const double> positions,
                       double tol = 1e-9);

// A random non-overlapping state by random sequential addition with a cell grid (O(N) expected
// for packing fractions below ~0.5 in 2D, ~0.3 in 3D): centres uniform in the box [lo + r_i,
// hi − r_i] on non-periodic axes and [lo, hi) on periodic ones (where lo, hi are the model's
// domain), clear of walls and obstacles. Reproducible from the seed (SplitMix64). Throws
// InputError when a particle cannot be placed in max_attempts tries.
std::vector<double> RandomSequentialAddition(const ParticleModel& model, const Vec3& lo,
                                             const Vec3& hi, std::uint64_t seed,
                                             std::int64_t max_attempts = 1000000);

}  // namespace moreau::particles
