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

// The noise ξ of slots [begin, end) (at most kNoiseBatch), keyed by key[s] (or id[s]), into
// xi[a · kNoiseBatch + s − begin].
template <int K>
inline void BatchNoise(std::uint64_t seed, const std::int64_t* key, const int* id,
                       std::int64_t step, int begin, int end, double* xi) {
  std::int64_t keys[kNoiseBatch];
  for (int s = begin; s < end; ++s) keys[s - begin] = key != nullptr ? key[s] : id[s];
  GaussianNoiseBatch(seed, keys, step, K, end - begin, kNoiseBatch, xi);
}

}  // namespace moreau::particles::internal
