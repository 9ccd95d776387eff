// Built with -fno-math-errno (CMakeLists.txt): with errno, a square root is a call that may set
// it, and BoxMullerBatch would not vectorise. The square root itself is IEEE either way.
#include "moreau/common/random.h"

namespace moreau {

std::uint64_t SplitMix64::Next() {
  std::uint64_t z = (state_ += 0x9E3779B97F4A7C15ULL);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}

double SplitMix64::Uniform01() { return static_cast<double>(Next() >> 11) * 0x1.0p-53; }

namespace {

constexpr std::uint64_t kM0 = 0xD2511F53u;
constexpr std::uint64_t kM1 = 0xCD9E8D57u;
constexpr std::uint32_t kW0 = 0x9E3779B9u;
constexpr std::uint32_t kW1 = 0xBB67AE85u;

}  // namespace

std::array<std::uint32_t, 4> Philox4x32(std::array<std::uint32_t, 4> c,
                                        std::array<std::uint32_t, 2> k) {
  Philox4x32Batch(1, &c[0], &c[1], &c[2], &c[3], k);
  return c;
}

void Philox4x32Batch(int n, std::uint32_t* c0, std::uint32_t* c1, std::uint32_t* c2,
                     std::uint32_t* c3, std::array<std::uint32_t, 2> k) {
  for (int round = 0; round < 10; ++round) {
    for (int i = 0; i < n; ++i) {
      const std::uint64_t p0 = kM0 * c0[i];
      const std::uint64_t p1 = kM1 * c2[i];
      const auto next0 = static_cast<std::uint32_t>(p1 >> 32) ^ c1[i] ^ k[0];
      const auto next2 = static_cast<std::uint32_t>(p0 >> 32) ^ c3[i] ^ k[1];
      c1[i] = static_cast<std::uint32_t>(p1);
      c3[i] = static_cast<std::uint32_t>(p0);
      c0[i] = next0;
      c2[i] = next2;
    }
    k[0] += kW0;
    k[1] += kW1;
  }
}

// On x86-64 an AVX2 copy too, chosen at load time (about twice as fast). Without FMA (not part of
// the avx2 target) both copies round every operation the same way: the same bits.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
__attribute__((target_clones("avx2", "default")))
#endif
void BoxMullerBatch(int n, const std::uint32_t* w0, const std::uint32_t* w1,
                    const std::uint32_t* w2, double* z0, double* z1, double* radius) {
  // Two loops: each is shorter, so more of its iterations overlap in the processor.
  for (int i = 0; i < n; ++i) radius[i] = random_internal::BoxMullerRadius(w0[i], w1[i]);
  for (int i = 0; i < n; ++i) random_internal::BoxMullerRotate(w2[i], radius[i], &z0[i], &z1[i]);
}

}  // namespace moreau
