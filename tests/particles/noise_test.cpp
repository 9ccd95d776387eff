// The counter-based generator: Philox known answers, the noise stream's distribution (moments and
// a Kolmogorov–Smirnov test), its batches, and the Euler–Maruyama increments.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "moreau/common/random.h"
#include "particles/noise.h"
#include "particles/test_util.h"

namespace moreau::particles {
namespace {

TEST(ParticleNoise, PhiloxKnownAnswers) {
  // Random123 tests/kat_vectors, the three "philox4x32 10" lines (counter, key → result).
  using W4 = std::array<std::uint32_t, 4>;
  EXPECT_EQ(Philox4x32({0, 0, 0, 0}, {0, 0}), (W4{0x6627e8d5, 0xe169c58d, 0xbc57ac4c, 0x9b00dbd8}));
  EXPECT_EQ(Philox4x32({0xffffffff, 0xffffffff, 0xffffffff, 0xffffffff}, {0xffffffff, 0xffffffff}),
            (W4{0x408f276d, 0x41c83b0e, 0xa20bc7c6, 0x6d5451fd}));
  EXPECT_EQ(Philox4x32({0x243f6a88, 0x85a308d3, 0x13198a2e, 0x03707344}, {0xa4093822, 0x299f31d0}),
            (W4{0xd16cfe09, 0x94fdcceb, 0x5001e420, 0x24126ea1}));
}

TEST(ParticleNoise, DependsOnlyOnSeedIdAndStep) {
  double a[3], b[3], c[3];
  GaussianNoise(7, 12, 3, 3, a);
  GaussianNoise(7, 12, 3, 3, b);
  for (int i = 0; i < 3; ++i) EXPECT_EQ(a[i], b[i]);
  GaussianNoise(7, 12, 4, 3, c);
  EXPECT_NE(a[0], c[0]);
  GaussianNoise(8, 12, 3, 3, c);
  EXPECT_NE(a[0], c[0]);
  GaussianNoise(7, 13, 3, 3, c);
  EXPECT_NE(a[0], c[0]);
}

// The batches (the engine's prediction) give GaussianNoise's bits for every key: ids beyond 2^32,
// negative keys and steps, both dimensions, any batch length.
TEST(ParticleNoise, BatchesGiveTheSameBitsAsSingleDraws) {
  std::vector<std::int64_t> keys;
  for (std::int64_t i = 0; i < 300; ++i) keys.push_back(i);
  for (std::int64_t i = 0; i < 300; ++i) keys.push_back((std::int64_t{1} << 33) + 7 * i - i * i);
  for (const int k : {2, 3}) {
    for (const std::int64_t step : {std::int64_t{0}, std::int64_t{-1}, std::int64_t{1} << 40}) {
      for (const int m : {1, 3, 600}) {
        const int stride = m + 5;
        std::vector<double> out(static_cast<std::size_t>(3 * stride), 0.0);
        internal::GaussianNoiseBatch(11, keys.data(), step, k, m, stride, out.data());
        for (int i = 0; i < m; ++i) {
          double xi[3];
          GaussianNoise(11, keys[static_cast<std::size_t>(i)], step, k, xi);
          for (int a = 0; a < k; ++a) {
            ASSERT_EQ(out[static_cast<std::size_t>(a * stride + i)], xi[a])
                << "k " << k << " step " << step << " m " << m << " i " << i << " a " << a;
          }
        }
      }
    }
  }
}

// 10^6 normals of the stream (ξ_0, ξ_1 of ids 0 … 5·10^5 − 1 at one step, seed fixed): the sample
// mean, variance and excess kurtosis within 5 standard errors of 0, 1, 0 (standard errors √(1/M),
// √(2/M), √(24/M)), and the Kolmogorov–Smirnov distance to the normal law below the 1e−6 quantile
// of Kolmogorov's distribution: P(√M D > λ) ≈ 2 exp(−2 λ²) gives λ = √(ln(2e6)/2) = 2.69.
TEST(ParticleNoise, StreamIsStandardNormalByMomentsAndKolmogorovSmirnov) {
  const int pairs = 500000;
  std::vector<std::int64_t> keys(static_cast<std::size_t>(pairs));
  for (int i = 0; i < pairs; ++i) keys[static_cast<std::size_t>(i)] = i;
  std::vector<double> z(static_cast<std::size_t>(2 * pairs));
  internal::GaussianNoiseBatch(20261202, keys.data(), 3, 2, pairs, pairs, z.data());
  const double M = static_cast<double>(z.size());
  double sum = 0.0;
  for (double v : z) sum += v;
  const double mean = sum / M;
  double m2 = 0.0, m4 = 0.0;
  for (double v : z) {
    const double d2 = (v - mean) * (v - mean);
    m2 += d2;
    m4 += d2 * d2;
  }
  m2 /= M;
  m4 /= M;
  EXPECT_LT(std::abs(mean), 5.0 / std::sqrt(M));
  EXPECT_LT(std::abs(m2 - 1.0), 5.0 * std::sqrt(2.0 / M));
  EXPECT_LT(std::abs(m4 / (m2 * m2) - 3.0), 5.0 * std::sqrt(24.0 / M));
  std::sort(z.begin(), z.end());
  double d = 0.0;
  for (std::size_t i = 0; i < z.size(); ++i) {
    const double cdf = 0.5 * std::erfc(-z[i] / std::sqrt(2.0));
    d = std::max({d, static_cast<double>(i + 1) / M - cdf, cdf - static_cast<double>(i) / M});
  }
  const double lambda = std::sqrt(0.5 * std::log(2.0 / 1e-6));
  EXPECT_LT(d, lambda / std::sqrt(M)) << "KS distance " << d;
}

// Free particles (no constraint can act: far apart, no walls) for one step: the displacement is
// exactly √(2Dh) ξ. Over M samples per component the sample mean has standard deviation
// σ/√M and the sample variance ≈ σ² (1 ± √(2/M)) (Gaussian fourth moment); we allow 5 standard
// errors, a false-alarm rate below 1e−6 per check, with the seed fixed.
TEST(ParticleNoise, EulerMaruyamaIncrementsHaveMeanZeroAndVariance2Dh) {
  for (const int k : {2, 3}) {
    ParticleModel m;
    m.dimension = k;
    const int n = 20000;
    m.radius.assign(n, 0.01);
    std::vector<double> x0(static_cast<std::size_t>(k * n), 0.0);
    for (int i = 0; i < n; ++i) x0[static_cast<std::size_t>(k * i)] = 10.0 * i;  // far apart
    Forces f;
    f.diffusion = 0.7;
    EngineOptions o;
    o.h = 0.01;
    o.seed = 2024;
    const double var = 2.0 * f.diffusion * o.h;
    std::vector<double> sum(static_cast<std::size_t>(k), 0.0),
        sum2(static_cast<std::size_t>(k), 0.0);
    std::int64_t samples = 0;
    Engine e(m, f, o, x0);
    std::vector<double> prev = x0;
    for (int step = 0; step < 10; ++step) {
      ASSERT_TRUE(e.Step());
      const std::vector<double> x = e.Positions();
      for (int i = 0; i < n; ++i) {
        for (int a = 0; a < k; ++a) {
          const double d =
              x[static_cast<std::size_t>(k * i + a)] - prev[static_cast<std::size_t>(k * i + a)];
          sum[static_cast<std::size_t>(a)] += d;
          sum2[static_cast<std::size_t>(a)] += d * d;
        }
      }
      prev = x;
      samples += n;
    }
    EXPECT_EQ(e.summary().stats.projections, 0);
    const double M = static_cast<double>(samples);
    for (int a = 0; a < k; ++a) {
      const double mean = sum[static_cast<std::size_t>(a)] / M;
      const double v = sum2[static_cast<std::size_t>(a)] / M - mean * mean;
      EXPECT_LT(std::abs(mean), 5.0 * std::sqrt(var / M)) << "k " << k << " axis " << a;
      EXPECT_LT(std::abs(v - var), 5.0 * var * std::sqrt(2.0 / M)) << "k " << k << " axis " << a;
    }
  }
}

TEST(ParticleNoise, ComponentsAreUncorrelatedAndGaussianTailed) {
  // Correlation of the two components and the fraction beyond 2σ (4.55 % for a normal law).
  const int M = 400000;
  double sxy = 0.0;
  int beyond = 0;
  for (int i = 0; i < M; ++i) {
    double xi[2];
    GaussianNoise(1, i, 0, 2, xi);
    sxy += xi[0] * xi[1];
    beyond += std::abs(xi[0]) > 2.0 ? 1 : 0;
  }
  EXPECT_LT(std::abs(sxy / M), 5.0 / std::sqrt(M));
  const double p = 0.0455003;
  EXPECT_NEAR(static_cast<double>(beyond) / M, p, 5.0 * std::sqrt(p * (1 - p) / M));
}

}  // namespace
}  // namespace moreau::particles
