#include "moreau/mocap/fill_metrics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <complex>

#include "mocap/synthetic.h"
#include "moreau/common/error.h"

namespace moreau::mocap {
namespace {

using testing::Hide;
using testing::MakeRecording;

constexpr double kRate = 200.0;
constexpr double kCutoff = 6.0;

// |H(e^{iω})|² of the section from its coefficients.
double SectionPower(const Biquad& s, double frequency_hz, double rate_hz) {
  const std::complex<double> z = std::polar(1.0, -2.0 * M_PI * frequency_hz / rate_hz);
  const std::complex<double> h = (s.b0 + s.b1 * z + s.b2 * z * z) / (1.0 + s.a1 * z + s.a2 * z * z);
  return std::norm(h);
}

// A 1 × n row of A sin(2π f t) at t = i / rate.
Eigen::MatrixXd Sine(double amplitude, double f, std::int64_t n) {
  Eigen::MatrixXd x(1, n);
  for (std::int64_t i = 0; i < n; ++i) x(0, i) = amplitude * std::sin(2.0 * M_PI * f * i / kRate);
  return x;
}

TEST(ZeroLagLowPass, SectionResponseIsTheStatedGainWithMinus3DbAtTheCutoff) {
  EXPECT_NEAR(WinterCorrection(2), std::pow(std::sqrt(2.0) - 1.0, 0.25), 1e-15);
  EXPECT_NEAR(WinterCorrection(2), 0.802, 5e-4);
  EXPECT_DOUBLE_EQ(WinterCorrection(1), 1.0);
  for (double rate : {50.0, 120.0, 200.0}) {
    const Biquad s = ZeroLagLowPassSection(rate, kCutoff);
    EXPECT_NEAR(ZeroLagLowPassGain(kCutoff, rate, kCutoff), 1.0 / std::sqrt(2.0), 1e-14);
    EXPECT_NEAR(SectionPower(s, 0.0, rate), 1.0, 1e-14);  // unit gain at 0 Hz
    for (double f : {0.5, 2.0, 6.0, 10.0, 0.4 * rate}) {
      EXPECT_NEAR(SectionPower(s, f, rate), ZeroLagLowPassGain(f, rate, kCutoff), 1e-12) << f;
    }
  }
}

TEST(ZeroLagLowPass, SinesPassWithTheExactGainAndNoPhaseLag) {
  const std::int64_t n = 2000;
  for (double f : {1.0, kCutoff, 15.0}) {
    const Eigen::MatrixXd x = Sine(10.0, f, n);
    const Eigen::MatrixXd y = ZeroLagLowPass(x, kRate, kCutoff);
    const double gain = ZeroLagLowPassGain(f, kRate, kCutoff);
    // Away from the ends (the reflection's transient has decayed), y = G x sample by sample: the
    // amplitude is the gain and the phase is zero.
    for (std::int64_t i = 300; i < n - 300; ++i) {
      ASSERT_NEAR(y(0, i), gain * x(0, i), 1e-9) << f << " Hz, sample " << i;
    }
  }
  EXPECT_NEAR(ZeroLagLowPassGain(1.0, kRate, kCutoff), 1.0, 5e-4);  // well below: gain ≈ 1
  EXPECT_LT(ZeroLagLowPassGain(15.0, kRate, kCutoff), 0.06);
}

TEST(ZeroLagLowPass, EndsFollowALineAndBadCutoffsAreInputErrors) {
  // A straight line is its own odd reflection, and the zero-lag filter keeps lines: it comes out
  // unchanged, ends included, once the padding (100 samples) has let the start at rest decay.
  Eigen::MatrixXd line(2, 400);
  for (int i = 0; i < 400; ++i) line.col(i) << 3.0 - 0.5 * i, 7.0;
  EXPECT_LT((ZeroLagLowPass(line, kRate, kCutoff) - line).cwiseAbs().maxCoeff(), 1e-6);
  EXPECT_THROW(ZeroLagLowPassSection(kRate, 0.0), InputError);
  EXPECT_THROW(ZeroLagLowPassSection(kRate, 100.0), InputError);
  EXPECT_THROW(ZeroLagLowPass(Eigen::MatrixXd(1, 1), kRate, kCutoff), InputError);
  EXPECT_EQ(LowPassPadding(1000, kRate, kCutoff), 100);
  EXPECT_EQ(LowPassPadding(10, kRate, kCutoff), 9);
}

TEST(FilterAndDifferentiate, CentralDifferencesOfAnAnalyticTrajectory) {
  // Each coordinate a sine well below the cutoff: after the filter (gain G) the central
  // differences are exactly G A sin(ωh)/h cos(ωt) and G A (2 cos(ωh) − 2)/h² sin(ωt), so they are
  // within (1 − G) + (ωh)²/6 (velocity) and (1 − G) + (ωh)²/12 (acceleration), relative, of the
  // analytic derivatives.
  const std::int64_t n = 1200;
  const double h = 1.0 / kRate;
  const Eigen::Vector3d f(0.5, 1.0, 2.0), a(30.0, 20.0, 10.0);
  Eigen::Matrix3Xd x(3, n);
  for (std::int64_t i = 0; i < n; ++i) {
    for (int r = 0; r < 3; ++r) x(r, i) = a[r] * std::sin(2.0 * M_PI * f[r] * i * h);
  }
  const FilteredKinematics k = FilterAndDifferentiate(x, kRate, kCutoff);
  for (int r = 0; r < 3; ++r) {
    const double w = 2.0 * M_PI * f[r], g = ZeroLagLowPassGain(f[r], kRate, kCutoff);
    for (std::int64_t i = 300; i < n - 300; ++i) {
      const double t = i * h;
      ASSERT_NEAR(k.velocity(r, i), g * a[r] * std::sin(w * h) / h * std::cos(w * t), 1e-7);
      ASSERT_NEAR(k.acceleration(r, i),
                  g * a[r] * (2.0 * std::cos(w * h) - 2.0) / (h * h) * std::sin(w * t), 1e-5);
      const double bound = 1.0 - g + (w * h) * (w * h) / 6.0 + 1e-9;
      ASSERT_NEAR(k.velocity(r, i), a[r] * w * std::cos(w * t), bound * a[r] * w);
      ASSERT_NEAR(k.acceleration(r, i), -a[r] * w * w * std::sin(w * t), bound * a[r] * w * w);
    }
  }
  // Constant acceleration: the zero-lag filter keeps it exactly in the interior.
  Eigen::Matrix3Xd q(3, 400);
  for (int i = 0; i < 400; ++i)
    q.col(i) = Eigen::Vector3d(1.0, -2.0, 4.5) * 0.5 * (i * h) * (i * h);
  const FilteredKinematics kq = FilterAndDifferentiate(q, kRate, kCutoff);
  for (int i = 150; i < 250; ++i) {
    ASSERT_LT((kq.acceleration.col(i) - Eigen::Vector3d(1.0, -2.0, 4.5)).norm(), 1e-6) << i;
  }
}

// Three markers in smooth motion (mm), 100 frames at kRate; marker 0 has a gap at 40 … 59.
Recording Moving(double curvature) {
  return MakeRecording(3, 100, kRate, [curvature](int m, double t) {
    return Eigen::Vector3d(100.0 * m + 300.0 * t + curvature * t * t, 50.0 * std::sin(3.0 * t),
                           10.0 * m);
  });
}

// `truth` with gap `g` filled by truth + offset(f).
template <typename Offset>
Recording FilledWith(const Recording& truth, const Gap& g, Offset offset) {
  Recording filled = truth;
  for (std::int64_t f = g.first; f <= g.last; ++f) {
    filled.SetPoint(f, g.marker, truth.point(f, g.marker) + offset(f));
  }
  return filled;
}

TEST(FillMeasures, PositionAndFilteredDerivativeErrors) {
  const Recording truth = Moving(0.0);
  const Gap g{0, 40, 59};
  const PositionError exact = PositionErrorInGap(truth, truth, g);
  EXPECT_EQ(exact.max, 0.0);
  const PositionError offset = PositionErrorInGap(
      truth, FilledWith(truth, g, [](auto) { return Eigen::Vector3d(3, 4, 0); }), g);
  EXPECT_NEAR(offset.mean, 5.0, 1e-12);
  EXPECT_NEAR(offset.p90, 5.0, 1e-12);
  EXPECT_NEAR(offset.max, 5.0, 1e-12);
  const DerivativeError none = FilteredDerivativeErrorInGap(truth, truth, g, kCutoff);
  EXPECT_EQ(none.velocity_max, 0.0);
  EXPECT_EQ(none.acceleration_max, 0.0);
  // The errors depend only on fill − truth (the filter is linear): the same offsets on another
  // truth give the same errors, and twice the offsets twice the errors.
  const auto bump = [&](std::int64_t f) {
    const double s = std::sin(M_PI * static_cast<double>(f - 39) / 21.0);
    return Eigen::Vector3d(2.0 * s, -s, 0.5 * s * s);
  };
  const DerivativeError e =
      FilteredDerivativeErrorInGap(truth, FilledWith(truth, g, bump), g, kCutoff);
  const Recording other = Moving(800.0);
  const DerivativeError e2 =
      FilteredDerivativeErrorInGap(other, FilledWith(other, g, bump), g, kCutoff);
  const DerivativeError e3 = FilteredDerivativeErrorInGap(
      truth, FilledWith(truth, g, [&](auto f) { return Eigen::Vector3d(2.0 * bump(f)); }), g,
      kCutoff);
  EXPECT_GT(e.velocity_mean, 0.0);
  EXPECT_GT(e.acceleration_max, e.acceleration_mean);
  EXPECT_NEAR(e2.velocity_mean, e.velocity_mean, 1e-9 * e.velocity_mean);
  EXPECT_NEAR(e2.acceleration_mean, e.acceleration_mean, 1e-9 * e.acceleration_mean);
  EXPECT_NEAR(e3.velocity_mean, 2.0 * e.velocity_mean, 1e-9 * e.velocity_mean);
  EXPECT_NEAR(e3.acceleration_max, 2.0 * e.acceleration_max, 1e-9 * e.acceleration_max);
  Recording holed = truth;
  Hide(holed, 0, 40, 59);
  EXPECT_TRUE(std::isnan(FilteredDerivativeErrorInGap(truth, holed, g, kCutoff).velocity_mean));
  EXPECT_TRUE(std::isnan(PositionErrorInGap(truth, holed, g).mean));
}

TEST(FillMeasures, VelocityJumpAtTheGapEnds) {
  // Constant velocity: the truth has no jump; an offset δ inside the gap jumps by |δ| rate at both
  // ends; at the recording's start there is no jump to measure.
  const Recording truth = Moving(0.0);
  Recording line = MakeRecording(2, 100, kRate, [](int m, double t) {
    return Eigen::Vector3d(300.0 * t + m, -40.0 * t, 7.0);
  });
  const Gap g{1, 40, 59};
  const VelocityJump none = VelocityJumpAtGapEnds(line, g);
  EXPECT_NEAR(none.start, 0.0, 1e-9);
  EXPECT_NEAR(none.end, 0.0, 1e-9);
  const VelocityJump jump = VelocityJumpAtGapEnds(
      FilledWith(line, g, [](auto) { return Eigen::Vector3d(0, 0.3, 0.4); }), g);
  EXPECT_NEAR(jump.start, 0.5 * kRate, 1e-9);
  EXPECT_NEAR(jump.end, 0.5 * kRate, 1e-9);
  const VelocityJump edge = VelocityJumpAtGapEnds(truth, Gap{0, 0, 9});
  EXPECT_TRUE(std::isnan(edge.start));
  const Eigen::Vector3d second = truth.point(11, 0) - 2.0 * truth.point(10, 0) + truth.point(9, 0);
  EXPECT_NEAR(edge.end, second.norm() * kRate, 1e-9);
  EXPECT_TRUE(std::isnan(VelocityJumpAtGapEnds(truth, Gap{0, 1, 9}).start));
}

TEST(FillMeasures, RigidPartnersAndTheirDistanceDeviation) {
  // Markers 0–4 on one rigid body, marker 5 moving on its own: the partners of marker 0 are three
  // of the body's, whose distances do not vary.
  const Recording body = testing::MakeRigidBodyRecording(5, 120, kRate, 4);
  Recording rec = MakeRecording(6, 120, kRate, [&](int m, double t) {
    const auto f = static_cast<std::int64_t>(std::llround(t * kRate));
    if (m < 5) return Eigen::Vector3d(body.point(f, m));
    return Eigen::Vector3d(200.0 * std::sin(5.0 * t), 100.0 * t, 30.0 * std::cos(2.0 * t));
  });
  const Recording truth = rec;
  const Gap g = Hide(rec, 0, 50, 69);
  const RigidPartners partners = FindRigidPartners(rec, 0);
  ASSERT_EQ(partners.markers.size(), 3u);
  for (std::size_t p = 0; p < 3; ++p) {
    EXPECT_LT(partners.markers[p], 5);
    EXPECT_LT(partners.sd[p], 1e-9);
    EXPECT_NEAR(partners.mean[p], (truth.point(0, 0) - truth.point(0, partners.markers[p])).norm(),
                1e-9);
  }
  EXPECT_EQ(FindRigidPartners(rec, 0, 10).markers.size(), 5u);
  const DistanceDeviation exact = PartnerDistanceDeviation(truth, g, partners);
  EXPECT_LT(exact.mean, 1e-9);
  // An offset of length 2 away from the first partner changes that distance by exactly 2 and the
  // others by at most 2 (triangle inequality).
  const auto away = [&](std::int64_t f) {
    return Eigen::Vector3d(2.0 *
                           (truth.point(f, 0) - truth.point(f, partners.markers[0])).normalized());
  };
  const DistanceDeviation off = PartnerDistanceDeviation(FilledWith(truth, g, away), g, partners);
  EXPECT_GT(off.mean, 2.0 / 3.0 - 1e-9);
  EXPECT_LE(off.mean, 2.0 + 1e-9);
  EXPECT_GT(off.z, 1e3);  // sd floored at 10⁻⁶ of the mean distance
  EXPECT_TRUE(std::isnan(PartnerDistanceDeviation(rec, g, partners).mean));
}

TEST(FillMeasures, PercentileInterpolatesBetweenOrderStatistics) {
  EXPECT_DOUBLE_EQ(Percentile({4.0, 1.0, 3.0, 2.0}, 50.0), 2.5);
  EXPECT_DOUBLE_EQ(Percentile({4.0, 1.0, 3.0, 2.0}, 90.0), 3.7);
  EXPECT_DOUBLE_EQ(Percentile({5.0}, 90.0), 5.0);
  EXPECT_TRUE(std::isnan(Percentile({}, 50.0)));
}

}  // namespace
}  // namespace moreau::mocap
