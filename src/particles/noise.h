// The engine's Brownian noise in batches: ξ(seed, key, step) of forces.h (GaussianNoise) for many
// particles at once, in a loop that the compiler vectorises (PhiloxNormalsBatch of common/random.h:
// Philox4x32-10 and the branch-free Box–Muller). Every value is the same as GaussianNoise's for its
// key, so it depends on neither the batch nor the thread that draws it.
#pragma once

#include <algorithm>
#include <cstdint>
#include <limits>

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

// What a prediction pass finds, reduced exactly over its batches (maxima, a minimum, a count).
struct PredictionTotals {
  double worst = 0.0;   // the largest ‖Y_i − X_i‖² of a finite row
  double extent = 0.0;  // the largest |Y_i,a| of a finite row
  double worst2 = 0.0;  // the exact skin bound's largest ‖Y_i − X_i^build‖²
  std::int64_t bad = std::numeric_limits<std::int64_t>::max();  // the smallest non-finite row's id
  std::int64_t far = 0;  // the exact skin bound's rows beyond skin/4
};

// The prediction's pass: the batches of kNoiseBatch slots of [0, n) in parallel (fixed by the
// slots, not the threads); each batch's noise is drawn first (Noise, BatchNoise: xi), then
// batch(begin, end, xi (null without noise), &totals) runs its rows. Returns the totals over all
// batches.
template <int K, bool Noise, typename Batch>
PredictionTotals OverNoiseBatches(int n, int threads, std::uint64_t seed, const std::int64_t* key,
                                  const int* id, std::int64_t step, Batch&& batch) {
  double worst = 0.0, extent = 0.0, worst2 = 0.0;
  std::int64_t bad = std::numeric_limits<std::int64_t>::max(), far = 0;
  const int batches = (n + kNoiseBatch - 1) / kNoiseBatch;
#pragma omp parallel for num_threads(threads) schedule(static) \
    reduction(max : worst, extent, worst2) reduction(min : bad) reduction(+ : far)
  for (int b = 0; b < batches; ++b) {
    const int begin = b * kNoiseBatch;
    const int end = std::min(n, begin + kNoiseBatch);
    [[maybe_unused]] double xi[3 * kNoiseBatch];
    if constexpr (Noise) BatchNoise<K>(seed, key, id, step, begin, end, xi);
    PredictionTotals t;
    batch(begin, end, Noise ? static_cast<const double*>(xi) : nullptr, &t);
    worst = std::max(worst, t.worst);
    extent = std::max(extent, t.extent);
    worst2 = std::max(worst2, t.worst2);
    bad = std::min(bad, t.bad);
    far += t.far;
  }
  return {worst, extent, worst2, bad, far};
}

}  // namespace moreau::particles::internal
