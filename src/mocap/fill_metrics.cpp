#include "moreau/mocap/fill_metrics.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <utility>

#include "moreau/common/error.h"

namespace moreau::mocap {

namespace {

constexpr double kUndefined = std::numeric_limits<double>::quiet_NaN();

// The warped cutoff Ω of the section (ZeroLagLowPassSection).
double WarpedCutoff(double rate_hz, double cutoff_hz) {
  if (!(cutoff_hz > 0.0) || !(cutoff_hz < 0.5 * rate_hz)) {
    throw InputError("filter_hz",
                     fmt::format("must be in (0, {}) Hz, below the Nyquist frequency of a "
                                 "recording at {} Hz (got {})",
                                 0.5 * rate_hz, rate_hz, cutoff_hz));
  }
  return std::tan(M_PI * cutoff_hz / rate_hz) / WinterCorrection(2);
}

// Runs `s` over x in place, from the first sample to the last, starting at rest at x[0].
void RunSection(const Biquad& s, std::vector<double>& x) {
  double x1 = x.front(), x2 = x.front(), y1 = x.front(), y2 = x.front();
  for (double& v : x) {
    const double y = s.b0 * v + s.b1 * x1 + s.b2 * x2 - s.a1 * y1 - s.a2 * y2;
    x2 = x1;
    x1 = v;
    y2 = y1;
    y1 = y;
    v = y;
  }
}

// The row padded by odd reflection with `pad` samples at each end, filtered forward and backward.
std::vector<double> FilterPadded(const Eigen::Ref<const Eigen::RowVectorXd>& row, std::int64_t pad,
                                 const Biquad& section) {
  const std::int64_t n = row.size();
  std::vector<double> x(static_cast<std::size_t>(n + 2 * pad));
  for (std::int64_t i = 0; i < n; ++i) x[static_cast<std::size_t>(pad + i)] = row[i];
  for (std::int64_t k = 1; k <= pad; ++k) {
    x[static_cast<std::size_t>(pad - k)] = 2.0 * row[0] - row[k];
    x[static_cast<std::size_t>(pad + n - 1 + k)] = 2.0 * row[n - 1] - row[n - 1 - k];
  }
  RunSection(section, x);
  std::reverse(x.begin(), x.end());
  RunSection(section, x);
  std::reverse(x.begin(), x.end());
  return x;
}

void CheckSamples(std::int64_t n) {
  if (n < 2) throw InputError(fmt::format("the low-pass filter needs ≥ 2 samples (got {})", n));
}

}  // namespace

double Percentile(std::vector<double> values, double p) {
  if (values.empty()) return kUndefined;
  std::sort(values.begin(), values.end());
  const double rank = p / 100.0 * static_cast<double>(values.size() - 1);
  const auto lo = static_cast<std::size_t>(std::floor(rank));
  const std::size_t hi = std::min(lo + 1, values.size() - 1);
  const double w = rank - static_cast<double>(lo);
  return (1.0 - w) * values[lo] + w * values[hi];
}

double WinterCorrection(int passes) {
  MOREAU_ASSERT(passes >= 1);
  return std::pow(std::pow(2.0, 1.0 / passes) - 1.0, 0.25);
}

Biquad ZeroLagLowPassSection(double rate_hz, double cutoff_hz) {
  const double w = WarpedCutoff(rate_hz, cutoff_hz);
  const double d = 1.0 + std::sqrt(2.0) * w + w * w;
  Biquad s;
  s.b0 = w * w / d;
  s.b1 = 2.0 * s.b0;
  s.b2 = s.b0;
  s.a1 = 2.0 * (w * w - 1.0) / d;
  s.a2 = (1.0 - std::sqrt(2.0) * w + w * w) / d;
  return s;
}

double ZeroLagLowPassGain(double frequency_hz, double rate_hz, double cutoff_hz) {
  const double r = std::tan(M_PI * frequency_hz / rate_hz) / WarpedCutoff(rate_hz, cutoff_hz);
  return 1.0 / (1.0 + std::pow(r, 4));
}

std::int64_t LowPassPadding(std::int64_t n, double rate_hz, double cutoff_hz) {
  const auto periods = static_cast<std::int64_t>(std::ceil(3.0 * rate_hz / cutoff_hz));
  return std::max<std::int64_t>(0, std::min(n - 1, periods));
}

Eigen::MatrixXd ZeroLagLowPass(const Eigen::MatrixXd& samples, double rate_hz, double cutoff_hz) {
  const std::int64_t n = samples.cols();
  CheckSamples(n);
  const Biquad section = ZeroLagLowPassSection(rate_hz, cutoff_hz);
  const std::int64_t pad = LowPassPadding(n, rate_hz, cutoff_hz);
  Eigen::MatrixXd out(samples.rows(), n);
  for (Eigen::Index r = 0; r < samples.rows(); ++r) {
    const std::vector<double> y = FilterPadded(samples.row(r), pad, section);
    for (std::int64_t i = 0; i < n; ++i) out(r, i) = y[static_cast<std::size_t>(pad + i)];
  }
  return out;
}

FilteredKinematics FilterAndDifferentiate(const Eigen::Matrix3Xd& samples, double rate_hz,
                                          double cutoff_hz) {
  const std::int64_t n = samples.cols();
  CheckSamples(n);
  const Biquad section = ZeroLagLowPassSection(rate_hz, cutoff_hz);
  const std::int64_t pad = LowPassPadding(n, rate_hz, cutoff_hz);
  FilteredKinematics k{Eigen::Matrix3Xd(3, n), Eigen::Matrix3Xd(3, n), Eigen::Matrix3Xd(3, n)};
  for (Eigen::Index r = 0; r < 3; ++r) {
    const std::vector<double> y = FilterPadded(samples.row(r), pad, section);
    const auto at = [&](std::int64_t i) { return y[static_cast<std::size_t>(pad + i)]; };
    for (std::int64_t i = 0; i < n; ++i) {
      k.position(r, i) = at(i);
      k.velocity(r, i) = (at(i + 1) - at(i - 1)) * rate_hz / 2.0;
      k.acceleration(r, i) = (at(i + 1) - 2.0 * at(i) + at(i - 1)) * rate_hz * rate_hz;
    }
  }
  return k;
}

Eigen::Matrix3Xd MarkerTrack(const Recording& recording, int marker, std::int64_t first,
                             std::int64_t last) {
  Eigen::Matrix3Xd track(3, last - first + 1);
  for (std::int64_t f = first; f <= last; ++f) track.col(f - first) = recording.point(f, marker);
  return track;
}

PositionError PositionErrorInGap(const Recording& truth, const Recording& filled, const Gap& gap) {
  std::vector<double> errors;
  double sum = 0.0, max = 0.0;
  for (std::int64_t f = gap.first; f <= gap.last; ++f) {
    const double e = (filled.point(f, gap.marker) - truth.point(f, gap.marker)).norm();
    if (!std::isfinite(e)) return {kUndefined, kUndefined, kUndefined};
    errors.push_back(e);
    sum += e;
    max = std::max(max, e);
  }
  return {sum / static_cast<double>(gap.length()), Percentile(std::move(errors), 90.0), max};
}

DerivativeError FilteredDerivativeErrorInGap(const Recording& truth, const Recording& filled,
                                             const Gap& gap, double cutoff_hz) {
  const double rate = truth.rate();
  const auto margin = static_cast<std::int64_t>(std::ceil(rate / cutoff_hz));
  const std::int64_t first = std::max<std::int64_t>(0, gap.first - margin);
  const std::int64_t last = std::min(truth.frames() - 1, gap.last + margin);
  const Eigen::Matrix3Xd fill_track = MarkerTrack(filled, gap.marker, first, last);
  const Eigen::Matrix3Xd true_track = MarkerTrack(truth, gap.marker, first, last);
  if (!fill_track.allFinite() || !true_track.allFinite() || last == first) {
    return {kUndefined, kUndefined, kUndefined, kUndefined};
  }
  const FilteredKinematics a = FilterAndDifferentiate(fill_track, rate, cutoff_hz);
  const FilteredKinematics b = FilterAndDifferentiate(true_track, rate, cutoff_hz);
  DerivativeError e;
  for (std::int64_t f = gap.first; f <= gap.last; ++f) {
    const double v = (a.velocity.col(f - first) - b.velocity.col(f - first)).norm();
    const double acc = (a.acceleration.col(f - first) - b.acceleration.col(f - first)).norm();
    e.velocity_mean += v;
    e.acceleration_mean += acc;
    e.velocity_max = std::max(e.velocity_max, v);
    e.acceleration_max = std::max(e.acceleration_max, acc);
  }
  e.velocity_mean /= static_cast<double>(gap.length());
  e.acceleration_mean /= static_cast<double>(gap.length());
  return e;
}

VelocityJump VelocityJumpAtGapEnds(const Recording& filled, const Gap& gap) {
  // ‖(x[c] − x[b]) − (x[b] − x[a])‖ rate, NaN unless a, b, c are frames with finite samples.
  const auto jump = [&](std::int64_t a, std::int64_t b, std::int64_t c) {
    if (std::min({a, b, c}) < 0 || std::max({a, b, c}) >= filled.frames()) return kUndefined;
    const Eigen::Vector3d xa = filled.point(a, gap.marker), xb = filled.point(b, gap.marker),
                          xc = filled.point(c, gap.marker);
    if (!xa.allFinite() || !xb.allFinite() || !xc.allFinite()) return kUndefined;
    return ((xc - xb) - (xb - xa)).norm() * filled.rate();
  };
  return {jump(gap.first - 2, gap.first - 1, gap.first),
          jump(gap.last + 2, gap.last + 1, gap.last)};
}

DistanceStatistics MarkerDistanceStatistics(const Recording& observed, int a, int b) {
  const auto distance = [&](std::int64_t f) {
    return (observed.point(f, a) - observed.point(f, b)).norm();
  };
  DistanceStatistics s;
  double sum = 0.0;
  for (std::int64_t f = 0; f < observed.frames(); ++f) {
    if (!observed.observed(f, a) || !observed.observed(f, b)) continue;
    sum += distance(f);
    ++s.frames;
  }
  if (s.frames == 0) return {kUndefined, kUndefined, 0};
  s.mean = sum / static_cast<double>(s.frames);
  double squares = 0.0;
  for (std::int64_t f = 0; f < observed.frames(); ++f) {
    if (!observed.observed(f, a) || !observed.observed(f, b)) continue;
    squares += (distance(f) - s.mean) * (distance(f) - s.mean);
  }
  s.sd = std::sqrt(squares / static_cast<double>(s.frames));
  return s;
}

RigidPartners FindRigidPartners(const Recording& observed, int marker, int count, int min_frames) {
  std::vector<std::pair<double, int>> order;
  std::vector<DistanceStatistics> stats(static_cast<std::size_t>(observed.markers()));
  for (int c = 0; c < observed.markers(); ++c) {
    if (c == marker || !observed.is_marker(c)) continue;
    stats[static_cast<std::size_t>(c)] = MarkerDistanceStatistics(observed, marker, c);
    if (stats[static_cast<std::size_t>(c)].frames >= std::max(1, min_frames)) {
      order.emplace_back(stats[static_cast<std::size_t>(c)].sd, c);
    }
  }
  std::sort(order.begin(), order.end());
  RigidPartners partners;
  for (const auto& [sd, c] : order) {
    if (static_cast<int>(partners.markers.size()) == count) break;
    partners.markers.push_back(c);
    partners.mean.push_back(stats[static_cast<std::size_t>(c)].mean);
    partners.sd.push_back(sd);
  }
  return partners;
}

DistanceDeviation PartnerDistanceDeviation(const Recording& filled, const Gap& gap,
                                           const RigidPartners& partners) {
  double sum = 0.0, sum_z = 0.0;
  std::int64_t n = 0;
  for (std::int64_t f = gap.first; f <= gap.last; ++f) {
    const Eigen::Vector3d x = filled.point(f, gap.marker);
    for (std::size_t p = 0; p < partners.markers.size(); ++p) {
      const double deviation =
          std::abs((x - filled.point(f, partners.markers[p])).norm() - partners.mean[p]);
      if (!std::isfinite(deviation)) continue;
      sum += deviation;
      sum_z += deviation / std::max(partners.sd[p], 1e-6 * partners.mean[p]);
      ++n;
    }
  }
  if (n == 0) return {kUndefined, kUndefined};
  return {sum / static_cast<double>(n), sum_z / static_cast<double>(n)};
}

FilledGapMeasures MeasureFilledGap(const Recording& truth, const Recording& filled, const Gap& gap,
                                   const RigidPartners& partners, double cutoff_hz) {
  constexpr double none = std::numeric_limits<double>::quiet_NaN();
  FilledGapMeasures m;
  m.position = PositionErrorInGap(truth, filled, gap);
  m.derivative = cutoff_hz < 0.5 * filled.rate()
                     ? FilteredDerivativeErrorInGap(truth, filled, gap, cutoff_hz)
                     : DerivativeError{none, none, none, none};
  m.jump = VelocityJumpAtGapEnds(filled, gap);
  m.distance = PartnerDistanceDeviation(filled, gap, partners);
  return m;
}

}  // namespace moreau::mocap
