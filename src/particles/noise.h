// The engine's Brownian noise in batches: ξ(seed, key, step) of forces.h (GaussianNoise) for many
// particles at once, in a loop that the compiler vectorises (PhiloxNormalsBatch of common/random.h:
// Philox4x32-10 and the branch-free Box–Muller). Every value is the same as GaussianNoise's for its
// key, so it depends on neither the batch nor the thread that draws it.
#pragma once

#include <cstdint>

namespace moreau::particles::internal {

// Particles per batch in the prediction (a stack buffer of 3 · kNoiseBatch doubles).
inline constexpr int kNoiseBatch = 256;

// out[a · stride + i] = ξ_a(seed, key[i], step) for i < m, a < k (k = 2 or 3).
void GaussianNoiseBatch(std::uint64_t seed, const std::int64_t* key, std::int64_t step, int k,
                        int m, int stride, double* out);

}  // namespace moreau::particles::internal
