#include "particles/noise.h"

#include <algorithm>
#include <array>

#include "moreau/common/random.h"
#include "moreau/particles/forces.h"

namespace moreau::particles {

namespace internal {

void GaussianNoiseBatch(std::uint64_t seed, const std::int64_t* key, std::int64_t step, int k,
                        int m, int stride, double* out) {
  const std::array<std::uint32_t, 2> philox_key{static_cast<std::uint32_t>(seed),
                                                static_cast<std::uint32_t>(seed >> 32)};
  const auto ustep = static_cast<std::uint64_t>(step);
  const auto c2 = static_cast<std::uint32_t>(ustep), c3 = static_cast<std::uint32_t>(ustep >> 32);
  // The first two counter words of up to kNoiseBatch keys; the last normal of 3D lands in unused.
  std::uint32_t c0[kNoiseBatch], c1[kNoiseBatch];
  double unused[kNoiseBatch];
  for (int begin = 0; begin < m; begin += kNoiseBatch) {
    const int len = std::min(kNoiseBatch, m - begin);
    for (int block = 0; 2 * block < k; ++block) {
      for (int i = 0; i < len; ++i) {
        const auto id = static_cast<std::uint64_t>(key[begin + i]);
        c0[i] = static_cast<std::uint32_t>(id);
        c1[i] = static_cast<std::uint32_t>(block) | static_cast<std::uint32_t>(id >> 32) << 2;
      }
      double* first = out + 2 * block * stride + begin;
      double* second = 2 * block + 1 < k ? out + (2 * block + 1) * stride + begin : unused;
      PhiloxNormalsBatch(len, c0, c1, c2, c3, philox_key, first, second);
    }
  }
}

}  // namespace internal

void GaussianNoise(std::uint64_t seed, std::int64_t id, std::int64_t step, int k, double* out) {
  internal::GaussianNoiseBatch(seed, &id, step, k, 1, 1, out);
}

}  // namespace moreau::particles
