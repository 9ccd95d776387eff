// Seeded generators, the same bits on every platform and thread count.
//
// SplitMix64: a small sequential generator for initial states (random sequential addition,
// random placements). Philox4x32-10: a counter-based generator; a value is a pure function of
// (counter, key), so noise for (seed, particle id, step) needs no per-thread state.
// BoxMullerNormals: two standard normals from 96 bits, branch-free; PhiloxNormalsBatch: both for
// many counters at once, vectorised (the noise of the particle engine draws through it), with
// the same bits as the single draws on every processor.
#pragma once

#include <array>
#include <bit>
#include <cstdint>

namespace moreau {

class SplitMix64 {
 public:
  explicit SplitMix64(std::uint64_t seed) : state_(seed) {}
  std::uint64_t Next();
  double Uniform01();  // in [0, 1), 53 random bits
 private:
  std::uint64_t state_;
};

// Philox4x32-10 of the 128-bit counter with a 64-bit key (Salmon et al., SC'11).
std::array<std::uint32_t, 4> Philox4x32(std::array<std::uint32_t, 4> counter,
                                        std::array<std::uint32_t, 2> key);

namespace random_internal {

// Philox4x32's round multipliers and key increments (Salmon et al.).
inline constexpr std::uint64_t kPhiloxM0 = 0xD2511F53u, kPhiloxM1 = 0xCD9E8D57u;
inline constexpr std::uint32_t kPhiloxW0 = 0x9E3779B9u, kPhiloxW1 = 0xBB67AE85u;

// The ten Philox4x32-10 rounds of Philox4x32, in place on the counter (c0, c1, c2, c3).
inline void Philox4x32Rounds(std::uint32_t* c0, std::uint32_t* c1, std::uint32_t* c2,
                             std::uint32_t* c3, std::array<std::uint32_t, 2> key) {
#pragma GCC unroll 10
  for (int round = 0; round < 10; ++round) {
    const std::uint64_t p0 = kPhiloxM0 * *c0;
    const std::uint64_t p1 = kPhiloxM1 * *c2;
    *c0 = static_cast<std::uint32_t>(p1 >> 32) ^ *c1 ^ key[0];
    *c2 = static_cast<std::uint32_t>(p0 >> 32) ^ *c3 ^ key[1];
    *c1 = static_cast<std::uint32_t>(p1);
    *c3 = static_cast<std::uint32_t>(p0);
    key[0] += kPhiloxW0;
    key[1] += kPhiloxW1;
  }
}

// ln u for u in [2^−53, 1): u = 2^e m with m in (√2/2, √2], ln m = 2 atanh(s), s = (m − 1)/(m + 1),
// |s| ≤ 0.1716, by its Taylor series to s^23 (truncation below 2^−60 relative). A few ulp.
inline double LogOfUnit(double u) {
  // Integer selects only: a floating-point operation under a condition would keep GCC from
  // vectorising the loop (it may trap).
  const auto bits = std::bit_cast<std::uint64_t>(u);
  const std::uint64_t mantissa = bits & 0x000FFFFFFFFFFFFFULL;
  // 1.mantissa > √2 by the 20 leading mantissa bits (√2 = 1.6A09E6… in hex), so m is in
  // (√2/2, √2] up to 2^−20: a 32-bit comparison (SSE2 has no 64-bit one).
  const auto leading = static_cast<std::int32_t>(bits >> 32 & 0xFFFFFu);
  const std::uint64_t high = leading > 0x6A09E ? 1 : 0;
  const double m = std::bit_cast<double>(mantissa | (0x3FF0000000000000ULL - (high << 52)));
  // The exponent (+1 when m was halved) as a double: 2^52 + E − (2^52 + 1023), exact.
  const double e =
      std::bit_cast<double>(((bits >> 52) + high) | 0x4330000000000000ULL) - (0x1.0p52 + 1023.0);
  const double s = (m - 1.0) / (m + 1.0);
  const double s2 = s * s;
  double p = 1.0 / 23.0;
#pragma GCC unroll 11
  for (int j = 10; j >= 0; --j) p = p * s2 + 1.0 / (2 * j + 1);
  return e * 0.6931471805599453 + 2.0 * s * p;
}

// cos and sin of θ = (π/2) t for |t| ≤ 1/2 by their Taylor series to θ^16 and θ^15 (truncation
// below 2^−53 relative). A few ulp.
inline void CosSinQuarter(double t, double* c, double* s) {
  const double x = 1.5707963267948966 * t;
  const double x2 = x * x;
  // 1/n! for n = 0 … 16 (exact integers up to 17! < 2^53, so each quotient is correctly rounded).
  constexpr std::array<double, 17> kInvFactorial = [] {
    std::array<double, 17> f{};
    double n_factorial = 1.0;
    for (int n = 0; n < 17; ++n) {
      if (n > 0) n_factorial *= n;
      f[static_cast<std::size_t>(n)] = 1.0 / n_factorial;
    }
    return f;
  }();
  double pc = kInvFactorial[16], ps = -kInvFactorial[15];
#pragma GCC unroll 8
  for (int j = 7; j >= 0; --j) {
    const double sign = (j % 2 == 0) ? 1.0 : -1.0;
    pc = pc * x2 + sign * kInvFactorial[static_cast<std::size_t>(2 * j)];
    if (j < 7) ps = ps * x2 + sign * kInvFactorial[static_cast<std::size_t>(2 * j + 1)];
  }
  *c = pc;
  *s = x * ps;
}

// ρ = √(−2 ln u) of BoxMullerNormals.
inline double BoxMullerRadius(std::uint32_t w0, std::uint32_t w1) {
  const std::uint64_t m = (static_cast<std::uint64_t>(w0) << 20) | (w1 >> 12);
  // 1 + m 2^−52, minus 1 (exact), plus 2^−53 (exact: 53 significant bits at most).
  const double u = (std::bit_cast<double>(m | 0x3FF0000000000000ULL) - 1.0) + 0x1.0p-53;
  return __builtin_sqrt(-2.0 * LogOfUnit(u));
}

// (z0, z1) = ρ (cos φ, sin φ) of BoxMullerNormals, φ from w2.
inline void BoxMullerRotate(std::uint32_t w2, double radius, double* z0, double* z1) {
  // 1 + f 2^−30 minus 3/2 (exact), plus 2^−31 (exact).
  const std::uint64_t f = static_cast<std::uint64_t>(w2 & 0x3FFFFFFFu) << 22;
  const double t = (std::bit_cast<double>(f | 0x3FF0000000000000ULL) - 1.5) + 0x1.0p-31;
  double c, s;
  CosSinQuarter(t, &c, &s);
  // Rotate by q quarter turns: (c, s) → (c, s), (−s, c), (−c, −s), (s, −c).
  const std::uint64_t q = w2 >> 30;
  const std::uint64_t odd = 0 - (q & 1u);  // all ones for q = 1, 3
  const auto cb = std::bit_cast<std::uint64_t>(c), sb = std::bit_cast<std::uint64_t>(s);
  const std::uint64_t flip_x = ((q + 1) >> 1 & 1u) << 63;
  const std::uint64_t flip_y = (q >> 1) << 63;
  *z0 = radius * std::bit_cast<double>(((sb & odd) | (cb & ~odd)) ^ flip_x);
  *z1 = radius * std::bit_cast<double>(((cb & odd) | (sb & ~odd)) ^ flip_y);
}

}  // namespace random_internal

// Two independent standard normals (z0, z1) = ρ (cos φ, sin φ) from three 32-bit words, with the
// Box–Muller radius ρ = √(−2 ln u) and angle φ:
//   u = (2 m + 1) 2^−53 with m = the 52 bits (w0 << 20) | (w1 >> 12), so u in [2^−53, 1) and
//     |z| ≤ 8.57 (the normal law's tail beyond is 1e−17);
//   φ = (π/2) (q + t) with q = w2 >> 30 (the quadrant) and t = ((w2 mod 2^30) + 1/2) 2^−30 − 1/2
//     (2^32 equally spaced angles).
// ln, cos and sin are the branch-free series of random_internal (a few ulp each); the results
// agree with the correctly rounded Box–Muller of the same u and φ to 2e−15 ρ (test).
inline void BoxMullerNormals(std::uint32_t w0, std::uint32_t w1, std::uint32_t w2, double* z0,
                             double* z1) {
  random_internal::BoxMullerRotate(w2, random_internal::BoxMullerRadius(w0, w1), z0, z1);
}

// (z0[i], z1[i]) = BoxMullerNormals(w0, w1, w2) of the words of Philox4x32((c0[i], c1[i], c2, c3),
// key), for i < n: the counters of one step differ in their first two words only. Per tile of 256
// counters the rounds, then the transform (the tile's words stay in L1), vectorised; on x86-64 an
// AVX-512 or AVX2 copy where the processor has one. All copies give the bits of the single draws:
// the same integer operations and the same +, −, ×, ÷, √ in the same order, each correctly rounded,
// none fused (test PhiloxNormals.EveryInstructionSetGivesTheBitsOfSingleDraws).
void PhiloxNormalsBatch(int n, const std::uint32_t* c0, const std::uint32_t* c1, std::uint32_t c2,
                        std::uint32_t c3, std::array<std::uint32_t, 2> key, double* z0, double* z1);

namespace random_internal {

// The copies of PhiloxNormalsBatch's loop (tests compare them).
enum class InstructionSet { kPortable, kAvx2, kAvx512 };
// Whether this processor (and build) runs the copy for `set`; kPortable always.
bool Supports(InstructionSet set);
// The widest supported copy, chosen once.
InstructionSet BestInstructionSet();
// PhiloxNormalsBatch by the copy for `set` (must be supported).
void PhiloxNormalsBatchOn(InstructionSet set, int n, const std::uint32_t* c0,
                          const std::uint32_t* c1, std::uint32_t c2, std::uint32_t c3,
                          std::array<std::uint32_t, 2> key, double* z0, double* z1);

}  // namespace random_internal

}  // namespace moreau
