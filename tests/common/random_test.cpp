// The seeded generators' transforms: the branch-free logarithm, cosine and sine of BoxMullerNormals
// against long-double references, and BoxMullerNormals against the textbook Box–Muller of the same
// uniform and angle; every instruction-set copy of PhiloxNormalsBatch against the single draws.
// (Philox's known answers: tests/particles/noise_test.cpp; the distribution of
// the engine's noise stream: the same file.)
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <vector>

#include "moreau/common/random.h"

namespace moreau {
namespace {

constexpr long double kPi = 3.141592653589793238462643383279502884L;

// 64-bit long double (x87) has 11 bits more than double: references good to ~2^−63.
static_assert(std::numeric_limits<long double>::digits >= 64);

TEST(BoxMuller, LogOfUnitIsWithinFourUlpOfTheLogarithm) {
  // Uniformly spread mantissas and every binade of [2^−53, 1), and the ends.
  SplitMix64 rng(17);
  double worst = 0.0;
  auto check = [&](double u) {
    const long double ref = std::log(static_cast<long double>(u));
    const double got = random_internal::LogOfUnit(u);
    if (ref != 0.0L) {
      worst = std::max(worst,
                       static_cast<double>(std::fabs((static_cast<long double>(got) - ref) / ref)));
    } else {
      EXPECT_EQ(got, 0.0);
    }
  };
  for (int e = 1; e <= 53; ++e) {
    for (int i = 0; i < 2000; ++i) check(std::ldexp(1.0 + rng.Uniform01(), -e));
  }
  check(0x1.0p-53);
  check(1.0 - 0x1.0p-53);
  check(std::nextafter(std::sqrt(0.5), 0.0));
  check(std::sqrt(0.5));
  check(std::nextafter(std::sqrt(0.5), 1.0));
  EXPECT_LT(worst, 4.0 * 0x1.0p-53);
}

TEST(BoxMuller, CosSinQuarterAreWithinFourUlp) {
  double worst_c = 0.0, worst_s = 0.0;
  for (int i = -100000; i <= 100000; ++i) {
    const double t = 0.5 * i / 100000.0;
    double c, s;
    random_internal::CosSinQuarter(t, &c, &s);
    // The same rounded angle as the series sees.
    const long double x = static_cast<long double>(1.5707963267948966 * t);
    const long double rc = std::cos(x), rs = std::sin(x);
    worst_c =
        std::max(worst_c, static_cast<double>(std::fabs((static_cast<long double>(c) - rc) / rc)));
    if (rs != 0.0L)
      worst_s = std::max(worst_s,
                         static_cast<double>(std::fabs((static_cast<long double>(s) - rs) / rs)));
  }
  EXPECT_LT(worst_c, 4.0 * 0x1.0p-53);
  EXPECT_LT(worst_s, 4.0 * 0x1.0p-53);
}

// The documented bound: within 2e−15 ρ of ρ (cos φ, sin φ) with ρ, φ exact for the given words.
TEST(BoxMuller, MatchesTheTextbookTransformOfTheSameBits) {
  SplitMix64 rng(2024);
  double worst = 0.0;
  auto check = [&](std::uint32_t w0, std::uint32_t w1, std::uint32_t w2) {
    double z0, z1;
    BoxMullerNormals(w0, w1, w2, &z0, &z1);
    const std::uint64_t m = (static_cast<std::uint64_t>(w0) << 20) | (w1 >> 12);
    const long double u = (2.0L * static_cast<long double>(m) + 1.0L) * 0x1.0p-53L;
    const long double rho = std::sqrt(-2.0L * std::log(u));
    const long double t = (static_cast<long double>(w2 & 0x3FFFFFFFu) + 0.5L) * 0x1.0p-30L - 0.5L;
    const long double phi = 0.5L * kPi * (static_cast<long double>(w2 >> 30) + t);
    const double e0 =
        static_cast<double>(std::fabs(static_cast<long double>(z0) - rho * std::cos(phi)) / rho);
    const double e1 =
        static_cast<double>(std::fabs(static_cast<long double>(z1) - rho * std::sin(phi)) / rho);
    worst = std::max({worst, e0, e1});
  };
  for (int i = 0; i < 200000; ++i) {
    const std::uint64_t a = rng.Next(), b = rng.Next();
    check(static_cast<std::uint32_t>(a), static_cast<std::uint32_t>(a >> 32),
          static_cast<std::uint32_t>(b));
  }
  // The smallest and largest u (ρ = 8.57 and ρ ≈ 1.5e−8) and the quadrant boundaries.
  for (std::uint32_t w2 : {0u, 0x3FFFFFFFu, 0x40000000u, 0x7FFFFFFFu, 0x80000000u, 0xFFFFFFFFu}) {
    check(0, 0, w2);
    check(0xFFFFFFFFu, 0xFFFFFFFFu, w2);
  }
  EXPECT_LT(worst, 2e-15);
}

// Every copy of PhiloxNormalsBatch this processor runs (portable; on x86-64 AVX2 and AVX-512 where
// present) gives, bit for bit, Philox4x32 then BoxMullerNormals of one counter at a time (compiled
// here in this file's plain build): 3 keys × 2^17 counters with random first words, in batch
// lengths that leave every tail length of the vector lanes and cross the 256-counter tiles.
TEST(PhiloxNormals, EveryInstructionSetGivesTheBitsOfSingleDraws) {
  using random_internal::InstructionSet;
  SplitMix64 rng(20261202);
  const int n = 1 << 17;
  std::vector<std::uint32_t> c0(n), c1(n);
  for (int i = 0; i < n; ++i) {
    const std::uint64_t r = rng.Next();
    c0[static_cast<std::size_t>(i)] = static_cast<std::uint32_t>(r);
    c1[static_cast<std::size_t>(i)] = static_cast<std::uint32_t>(r >> 32);
  }
  int sets_run = 0;
  for (const auto set :
       {InstructionSet::kPortable, InstructionSet::kAvx2, InstructionSet::kAvx512}) {
    if (!random_internal::Supports(set)) continue;
    ++sets_run;
    for (int trial = 0; trial < 3; ++trial) {
      const std::uint64_t k = rng.Next(), c = rng.Next();
      const std::array<std::uint32_t, 2> key{static_cast<std::uint32_t>(k),
                                             static_cast<std::uint32_t>(k >> 32)};
      const auto c2 = static_cast<std::uint32_t>(c), c3 = static_cast<std::uint32_t>(c >> 32);
      std::vector<double> z0(n), z1(n);
      for (int begin = 0, len = 1; begin < n; begin += len, len = len % 600 + 7) {
        const int m = std::min(len, n - begin);
        random_internal::PhiloxNormalsBatchOn(
            set, m, &c0[static_cast<std::size_t>(begin)], &c1[static_cast<std::size_t>(begin)], c2,
            c3, key, &z0[static_cast<std::size_t>(begin)], &z1[static_cast<std::size_t>(begin)]);
      }
      for (std::size_t i = 0; i < static_cast<std::size_t>(n); ++i) {
        const auto w = Philox4x32({c0[i], c1[i], c2, c3}, key);
        double a, b;
        BoxMullerNormals(w[0], w[1], w[2], &a, &b);
        ASSERT_EQ(z0[i], a) << "set " << static_cast<int>(set) << " counter " << i;
        ASSERT_EQ(z1[i], b) << "set " << static_cast<int>(set) << " counter " << i;
      }
    }
  }
  EXPECT_TRUE(random_internal::Supports(random_internal::BestInstructionSet()));
  RecordProperty("instruction_sets_compared", sets_run);
}

TEST(BoxMuller, RadiusRangeIsTheDocumentedOne) {
  double z0, z1;
  BoxMullerNormals(0, 0, 0, &z0, &z1);  // u = 2^−53, φ = −π/4 + 2^−31 π/2
  EXPECT_NEAR(std::hypot(z0, z1), std::sqrt(106.0 * std::numbers::ln2), 1e-14);
  EXPECT_GT(z0, 0.0);
  EXPECT_LT(z1, 0.0);
}

}  // namespace
}  // namespace moreau
