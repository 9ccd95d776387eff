// Built with -fno-math-errno (CMakeLists.txt): with errno, a square root is a call that may set
// it, and the normals' loop would not vectorise. The square root itself is IEEE either way.
// Floating-point contraction is off (ISO C++20, no GNU extensions: GCC's -ffp-contract=off), so no
// copy below fuses a multiply and an add even where the instruction set has FMA.
#include "moreau/common/random.h"

#include <algorithm>

// GCC on x86-64: AVX2 and AVX-512 copies of the normals' loop, chosen at run time.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define MOREAU_RANDOM_X86_COPIES 1
#include <immintrin.h>
#else
#define MOREAU_RANDOM_X86_COPIES 0
#endif

namespace moreau {

std::uint64_t SplitMix64::Next() {
  std::uint64_t z = (state_ += 0x9E3779B97F4A7C15ULL);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}

double SplitMix64::Uniform01() { return static_cast<double>(Next() >> 11) * 0x1.0p-53; }

std::array<std::uint32_t, 4> Philox4x32(std::array<std::uint32_t, 4> c,
                                        std::array<std::uint32_t, 2> k) {
  random_internal::Philox4x32Rounds(&c[0], &c[1], &c[2], &c[3], k);
  return c;
}

namespace random_internal {

namespace {

// Counters per tile: the words and radii of a tile stay in L1.
constexpr int kTile = 256;

// The Box–Muller part of PhiloxNormalsBatch on a tile's words, inlined into each instruction-set
// copy: the radii, then the rotations (two short loops that vectorise).
[[gnu::always_inline]] inline void BoxMullerLoops(int n, const std::uint32_t* w0,
                                                  const std::uint32_t* w1, const std::uint32_t* w2,
                                                  double* radius, double* z0, double* z1) {
  for (int i = 0; i < n; ++i) radius[i] = BoxMullerRadius(w0[i], w1[i]);
  for (int i = 0; i < n; ++i) BoxMullerRotate(w2[i], radius[i], &z0[i], &z1[i]);
}

// The portable copy: the rounds over a tile's counters in turn (independent lanes, so the
// compiler vectorises them with SSE2), then the Box–Muller loops.
void PhiloxNormalsPortable(int n, const std::uint32_t* c0, const std::uint32_t* c1,
                           std::uint32_t c2, std::uint32_t c3, std::array<std::uint32_t, 2> key,
                           double* z0, double* z1) {
  std::uint32_t w0[kTile], w1[kTile], w2[kTile], w3[kTile];
  double radius[kTile];
  for (int begin = 0; begin < n; begin += kTile) {
    const int len = std::min(kTile, n - begin);
    for (int i = 0; i < len; ++i) {
      w0[i] = c0[begin + i];
      w1[i] = c1[begin + i];
      w2[i] = c2;
      w3[i] = c3;
    }
    std::array<std::uint32_t, 2> k = key;
    for (int round = 0; round < 10; ++round) {
      for (int i = 0; i < len; ++i) {
        // One round of Philox4x32Rounds on lane i.
        const std::uint64_t p0 = kPhiloxM0 * w0[i];
        const std::uint64_t p1 = kPhiloxM1 * w2[i];
        const auto next0 = static_cast<std::uint32_t>(p1 >> 32) ^ w1[i] ^ k[0];
        const auto next2 = static_cast<std::uint32_t>(p0 >> 32) ^ w3[i] ^ k[1];
        w1[i] = static_cast<std::uint32_t>(p1);
        w3[i] = static_cast<std::uint32_t>(p0);
        w0[i] = next0;
        w2[i] = next2;
      }
      k[0] += kPhiloxW0;
      k[1] += kPhiloxW1;
    }
    BoxMullerLoops(len, w0, w1, w2, radius, z0 + begin, z1 + begin);
  }
}

#if MOREAU_RANDOM_X86_COPIES
// The x86 copies keep each 32-bit word in the low half of a 64-bit lane (the high half is junk
// that no result reads): _mm*_mul_epu32 multiplies the low halves into the full 64-bit product,
// whose halves are the round's hi and lo words. The tail of a tile (fewer counters than lanes)
// runs Philox4x32Rounds one counter at a time; integer operations, so the same words.

// Counters i … n − 1 one at a time (the tail of a tile shorter than a register).
void PhiloxWordsOneByOne(int i, int n, const std::uint32_t* c0, const std::uint32_t* c1,
                         std::uint32_t c2, std::uint32_t c3, std::array<std::uint32_t, 2> key,
                         std::uint32_t* w0, std::uint32_t* w1, std::uint32_t* w2) {
  for (; i < n; ++i) {
    std::uint32_t a = c0[i], b = c1[i], c = c2, d = c3;
    Philox4x32Rounds(&a, &b, &c, &d, key);
    w0[i] = a;
    w1[i] = b;
    w2[i] = c;
  }
}

// The key word of a round: key_word + round · increment (mod 2^32).
constexpr std::uint32_t RoundKey(std::uint32_t key_word, std::uint32_t increment, int round) {
  return key_word + increment * static_cast<std::uint32_t>(round);
}

// The low halves of v's four 64-bit lanes into w[0 … 3] (low_words: 0, 2, 4, 6 twice).
__attribute__((target("avx2"), always_inline)) inline void StoreLowWords(__m256i v,
                                                                         __m256i low_words,
                                                                         std::uint32_t* w) {
  _mm_storeu_si128(reinterpret_cast<__m128i*>(w),
                   _mm256_castsi256_si128(_mm256_permutevar8x32_epi32(v, low_words)));
}

// The words of counters (c0[i], c1[i], c2, c3) for i < n into w0, w1, w2, four at a time.
__attribute__((target("avx2"))) void PhiloxWordsAvx2(
    int n, const std::uint32_t* c0, const std::uint32_t* c1, std::uint32_t c2, std::uint32_t c3,
    std::array<std::uint32_t, 2> key, std::uint32_t* w0, std::uint32_t* w1, std::uint32_t* w2) {
  __m256i k0[10], k1[10];
  for (int round = 0; round < 10; ++round) {
    k0[round] = _mm256_set1_epi64x(RoundKey(key[0], kPhiloxW0, round));
    k1[round] = _mm256_set1_epi64x(RoundKey(key[1], kPhiloxW1, round));
  }
  const __m256i m0 = _mm256_set1_epi64x(kPhiloxM0), m1 = _mm256_set1_epi64x(kPhiloxM1);
  const __m256i low_words = _mm256_setr_epi32(0, 2, 4, 6, 0, 2, 4, 6);
  int i = 0;
  for (; i + 4 <= n; i += 4) {
    __m256i a = _mm256_cvtepu32_epi64(_mm_loadu_si128(reinterpret_cast<const __m128i*>(c0 + i)));
    __m256i b = _mm256_cvtepu32_epi64(_mm_loadu_si128(reinterpret_cast<const __m128i*>(c1 + i)));
    __m256i c = _mm256_set1_epi64x(c2), d = _mm256_set1_epi64x(c3);
#pragma GCC unroll 10
    for (int round = 0; round < 10; ++round) {
      const __m256i p0 = _mm256_mul_epu32(a, m0), p1 = _mm256_mul_epu32(c, m1);
      a = _mm256_xor_si256(_mm256_xor_si256(_mm256_srli_epi64(p1, 32), b), k0[round]);
      c = _mm256_xor_si256(_mm256_xor_si256(_mm256_srli_epi64(p0, 32), d), k1[round]);
      b = p1;
      d = p0;
    }
    StoreLowWords(a, low_words, w0 + i);
    StoreLowWords(b, low_words, w1 + i);
    StoreLowWords(c, low_words, w2 + i);
  }
  PhiloxWordsOneByOne(i, n, c0, c1, c2, c3, key, w0, w1, w2);
}

// The same, eight at a time. GCC 12 warns of the deliberately undefined vector inside its own
// AVX-512 intrinsics (_mm512_undefined_epi32) as maybe uninitialised: a false alarm, silenced here.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
__attribute__((target("avx512f"))) void PhiloxWordsAvx512(
    int n, const std::uint32_t* c0, const std::uint32_t* c1, std::uint32_t c2, std::uint32_t c3,
    std::array<std::uint32_t, 2> key, std::uint32_t* w0, std::uint32_t* w1, std::uint32_t* w2) {
  __m512i k0[10], k1[10];
  for (int round = 0; round < 10; ++round) {
    k0[round] = _mm512_set1_epi64(RoundKey(key[0], kPhiloxW0, round));
    k1[round] = _mm512_set1_epi64(RoundKey(key[1], kPhiloxW1, round));
  }
  const __m512i m0 = _mm512_set1_epi64(kPhiloxM0), m1 = _mm512_set1_epi64(kPhiloxM1);
  int i = 0;
  for (; i + 8 <= n; i += 8) {
    __m512i a = _mm512_cvtepu32_epi64(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(c0 + i)));
    __m512i b = _mm512_cvtepu32_epi64(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(c1 + i)));
    __m512i c = _mm512_set1_epi64(c2), d = _mm512_set1_epi64(c3);
#pragma GCC unroll 10
    for (int round = 0; round < 10; ++round) {
      const __m512i p0 = _mm512_mul_epu32(a, m0), p1 = _mm512_mul_epu32(c, m1);
      // 0x96: the three-way exclusive or.
      a = _mm512_ternarylogic_epi64(_mm512_srli_epi64(p1, 32), b, k0[round], 0x96);
      c = _mm512_ternarylogic_epi64(_mm512_srli_epi64(p0, 32), d, k1[round], 0x96);
      b = p1;
      d = p0;
    }
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(w0 + i), _mm512_cvtepi64_epi32(a));
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(w1 + i), _mm512_cvtepi64_epi32(b));
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(w2 + i), _mm512_cvtepi64_epi32(c));
  }
  PhiloxWordsOneByOne(i, n, c0, c1, c2, c3, key, w0, w1, w2);
}

#pragma GCC diagnostic pop

// Tile by tile: the words, then the Box–Muller loops in the copy's instruction set.
#define MOREAU_PHILOX_NORMALS_TILES(words)                           \
  std::uint32_t w0[kTile], w1[kTile], w2[kTile];                     \
  double radius[kTile];                                              \
  for (int begin = 0; begin < n; begin += kTile) {                   \
    const int len = std::min(kTile, n - begin);                      \
    words(len, c0 + begin, c1 + begin, c2, c3, key, w0, w1, w2);     \
    BoxMullerLoops(len, w0, w1, w2, radius, z0 + begin, z1 + begin); \
  }

__attribute__((target("avx2"))) void PhiloxNormalsAvx2(int n, const std::uint32_t* c0,
                                                       const std::uint32_t* c1, std::uint32_t c2,
                                                       std::uint32_t c3,
                                                       std::array<std::uint32_t, 2> key, double* z0,
                                                       double* z1) {
  MOREAU_PHILOX_NORMALS_TILES(PhiloxWordsAvx2)
}

__attribute__((target("avx512f,prefer-vector-width=512"))) void PhiloxNormalsAvx512(
    int n, const std::uint32_t* c0, const std::uint32_t* c1, std::uint32_t c2, std::uint32_t c3,
    std::array<std::uint32_t, 2> key, double* z0, double* z1) {
  MOREAU_PHILOX_NORMALS_TILES(PhiloxWordsAvx512)
}
#undef MOREAU_PHILOX_NORMALS_TILES
#endif

}  // namespace

bool Supports(InstructionSet set) {
  switch (set) {
    case InstructionSet::kPortable:
      return true;
#if MOREAU_RANDOM_X86_COPIES
    case InstructionSet::kAvx2:
      return __builtin_cpu_supports("avx2");
    case InstructionSet::kAvx512:
      return __builtin_cpu_supports("avx512f");
#endif
    default:
      return false;
  }
}

InstructionSet BestInstructionSet() {
  static const InstructionSet best = Supports(InstructionSet::kAvx512) ? InstructionSet::kAvx512
                                     : Supports(InstructionSet::kAvx2) ? InstructionSet::kAvx2
                                                                       : InstructionSet::kPortable;
  return best;
}

void PhiloxNormalsBatchOn(InstructionSet set, int n, const std::uint32_t* c0,
                          const std::uint32_t* c1, std::uint32_t c2, std::uint32_t c3,
                          std::array<std::uint32_t, 2> key, double* z0, double* z1) {
  switch (set) {
#if MOREAU_RANDOM_X86_COPIES
    case InstructionSet::kAvx2:
      PhiloxNormalsAvx2(n, c0, c1, c2, c3, key, z0, z1);
      return;
    case InstructionSet::kAvx512:
      PhiloxNormalsAvx512(n, c0, c1, c2, c3, key, z0, z1);
      return;
#endif
    default:
      PhiloxNormalsPortable(n, c0, c1, c2, c3, key, z0, z1);
  }
}

}  // namespace random_internal

void PhiloxNormalsBatch(int n, const std::uint32_t* c0, const std::uint32_t* c1, std::uint32_t c2,
                        std::uint32_t c3, std::array<std::uint32_t, 2> key, double* z0,
                        double* z1) {
  random_internal::PhiloxNormalsBatchOn(random_internal::BestInstructionSet(), n, c0, c1, c2, c3,
                                        key, z0, z1);
}

}  // namespace moreau
