// Interpolating fills: linear, not-a-knot cubic spline, monotone cubic Hermite (pchip).
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <optional>

#include <Eigen/LU>

#include "fill_internal.h"
#include "moreau/common/error.h"

namespace moreau::mocap {

namespace internal {

std::optional<GapFill> EdgeStatus(const Recording& in, const Gap& gap) {
  if (gap.first == 0 || gap.last == in.frames() - 1) {
    return GapFill{GapStatus::kSkippedEdge,
                   gap.first == 0 ? "no observed sample before the gap (start of the recording)"
                                  : "no observed sample after the gap (end of the recording)",
                   {}};
  }
  return std::nullopt;
}

bool ObservedThroughout(const Recording& in, int marker, std::int64_t first, std::int64_t last) {
  for (std::int64_t f = first; f <= last; ++f) {
    if (!in.observed(f, marker)) return false;
  }
  return true;
}

}  // namespace internal

namespace {

// The observed samples around a gap: knots t (frame numbers, ascending) and positions (3 × n).
struct Samples {
  Eigen::VectorXd t;
  Eigen::Matrix3Xd y;
};

// Up to k samples of the observed run adjacent to the gap on each side; nullopt with a status
// when a side has fewer than `min_per_side`.
std::optional<GapFill> CollectSamples(const Recording& in, const Gap& gap, int k, int min_per_side,
                                      Samples* samples) {
  if (auto edge = internal::EdgeStatus(in, gap)) return edge;
  std::vector<std::int64_t> before, after;
  for (std::int64_t f = gap.first - 1;
       f >= 0 && in.observed(f, gap.marker) && static_cast<int>(before.size()) < k; --f) {
    before.push_back(f);
  }
  for (std::int64_t f = gap.last + 1;
       f < in.frames() && in.observed(f, gap.marker) && static_cast<int>(after.size()) < k; ++f) {
    after.push_back(f);
  }
  const auto least = static_cast<int>(std::min(before.size(), after.size()));
  if (least < min_per_side) {
    return GapFill{GapStatus::kTooFewSamples,
                   fmt::format("{} observed sample(s) before and {} after the gap; {} per side "
                               "needed",
                               before.size(), after.size(), min_per_side),
                   {}};
  }
  std::reverse(before.begin(), before.end());
  before.insert(before.end(), after.begin(), after.end());
  const auto n = static_cast<Eigen::Index>(before.size());
  samples->t.resize(n);
  samples->y.resize(3, n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const std::int64_t f = before[static_cast<std::size_t>(i)];
    samples->t[i] = static_cast<double>(f);
    samples->y.col(i) = in.point(f, gap.marker);
  }
  return std::nullopt;
}

// Index i of the interval [t_i, t_{i+1}] that holds x (t ascending, x inside).
Eigen::Index Interval(const Eigen::VectorXd& t, double x) {
  const auto it = std::upper_bound(t.data(), t.data() + t.size(), x);
  const auto i = static_cast<Eigen::Index>(it - t.data()) - 1;
  return std::clamp<Eigen::Index>(i, 0, t.size() - 2);
}

// Second derivatives (3 × n) of the not-a-knot cubic spline through n ≥ 4 samples.
Eigen::Matrix3Xd NotAKnotMoments(const Samples& s) {
  const Eigen::Index n = s.t.size();
  const Eigen::VectorXd h = s.t.tail(n - 1) - s.t.head(n - 1);
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(n, n);
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(n, 3);
  // Not-a-knot: the third derivative is continuous at t_1 and t_{n−2}.
  a(0, 0) = h[1];
  a(0, 1) = -(h[0] + h[1]);
  a(0, 2) = h[0];
  a(n - 1, n - 3) = h[n - 2];
  a(n - 1, n - 2) = -(h[n - 3] + h[n - 2]);
  a(n - 1, n - 1) = h[n - 3];
  for (Eigen::Index i = 1; i + 1 < n; ++i) {  // continuity of the first derivative at t_i
    a(i, i - 1) = h[i - 1];
    a(i, i) = 2.0 * (h[i - 1] + h[i]);
    a(i, i + 1) = h[i];
    rhs.row(i) =
        6.0 * ((s.y.col(i + 1) - s.y.col(i)) / h[i] - (s.y.col(i) - s.y.col(i - 1)) / h[i - 1])
                  .transpose();
  }
  return a.fullPivLu().solve(rhs).transpose();
}

// Monotone derivatives (3 × n) at the samples, per coordinate (Fritsch–Carlson with the
// Fritsch–Butland harmonic mean inside and the shape-preserving three-point formula at the ends).
Eigen::Matrix3Xd MonotoneSlopes(const Samples& s) {
  const Eigen::Index n = s.t.size();
  Eigen::Matrix3Xd d(3, n);
  for (int c = 0; c < 3; ++c) {
    Eigen::VectorXd h(n - 1), delta(n - 1);
    for (Eigen::Index i = 0; i + 1 < n; ++i) {
      h[i] = s.t[i + 1] - s.t[i];
      delta[i] = (s.y(c, i + 1) - s.y(c, i)) / h[i];
    }
    if (n == 2) {
      d(c, 0) = d(c, 1) = delta[0];
      continue;
    }
    for (Eigen::Index i = 1; i + 1 < n; ++i) {
      if (delta[i - 1] * delta[i] <= 0.0) {
        d(c, i) = 0.0;  // local extremum or flat: no overshoot
      } else {
        const double w1 = 2.0 * h[i] + h[i - 1];
        const double w2 = h[i] + 2.0 * h[i - 1];
        d(c, i) = (w1 + w2) / (w1 / delta[i - 1] + w2 / delta[i]);
      }
    }
    const auto end_slope = [](double h0, double h1, double d0, double d1) {
      double e = ((2.0 * h0 + h1) * d0 - h0 * d1) / (h0 + h1);
      if (e * d0 <= 0.0) return 0.0;
      if (d0 * d1 < 0.0 && std::abs(e) > 3.0 * std::abs(d0)) e = 3.0 * d0;
      return e;
    };
    d(c, 0) = end_slope(h[0], h[1], delta[0], delta[1]);
    d(c, n - 1) = end_slope(h[n - 2], h[n - 3], delta[n - 2], delta[n - 3]);
  }
  return d;
}

// The spline at x in [t_i, t_{i+1}] from its second derivatives m.
Eigen::Vector3d SplinePiece(const Samples& s, const Eigen::Matrix3Xd& m, Eigen::Index i, double x) {
  const double h = s.t[i + 1] - s.t[i];
  const double u = s.t[i + 1] - x;
  const double v = x - s.t[i];
  return (m.col(i) * u * u * u + m.col(i + 1) * v * v * v) / (6.0 * h) +
         (s.y.col(i) / h - m.col(i) * h / 6.0) * u +
         (s.y.col(i + 1) / h - m.col(i + 1) * h / 6.0) * v;
}

// The cubic Hermite interpolant at x in [t_i, t_{i+1}] from its derivatives d.
Eigen::Vector3d HermitePiece(const Samples& s, const Eigen::Matrix3Xd& d, Eigen::Index i,
                             double x) {
  const double h = s.t[i + 1] - s.t[i];
  const double u = (x - s.t[i]) / h;  // in [0, 1]
  const double h00 = (1.0 + 2.0 * u) * (1.0 - u) * (1.0 - u);
  const double h10 = u * (1.0 - u) * (1.0 - u);
  const double h01 = u * u * (3.0 - 2.0 * u);
  const double h11 = u * u * (u - 1.0);
  return h00 * s.y.col(i) + h10 * h * d.col(i) + h01 * s.y.col(i + 1) + h11 * h * d.col(i + 1);
}

// A piecewise cubic through the samples around the gap: `coefficients` (3 × n, per sample) from
// the samples, `piece` evaluates the cubic of one interval.
GapFill FillPiecewiseCubic(const Recording& in, const Gap& gap, const FillOptions& options,
                           Eigen::Matrix3Xd (*coefficients)(const Samples&),
                           Eigen::Vector3d (*piece)(const Samples&, const Eigen::Matrix3Xd&,
                                                    Eigen::Index, double)) {
  Samples s;
  if (auto status = CollectSamples(in, gap, options.interpolation.samples_per_side, 2, &s)) {
    return *status;
  }
  const Eigen::Matrix3Xd c = coefficients(s);
  GapFill fill;
  fill.points.resize(3, gap.length());
  for (std::int64_t f = gap.first; f <= gap.last; ++f) {
    const auto x = static_cast<double>(f);
    fill.points.col(f - gap.first) = piece(s, c, Interval(s.t, x), x);
  }
  return fill;
}

}  // namespace

GapFill FillGapLinear(const Recording& in, const Gap& gap, const FillOptions&) {
  if (auto edge = internal::EdgeStatus(in, gap)) return *edge;
  const std::int64_t a = gap.first - 1;
  const std::int64_t b = gap.last + 1;
  const Eigen::Vector3d pa = in.point(a, gap.marker);
  const Eigen::Vector3d pb = in.point(b, gap.marker);
  GapFill fill;
  fill.points.resize(3, gap.length());
  for (std::int64_t f = gap.first; f <= gap.last; ++f) {
    const double w = static_cast<double>(f - a) / static_cast<double>(b - a);
    fill.points.col(f - gap.first) = (1.0 - w) * pa + w * pb;
  }
  return fill;
}

GapFill FillGapSpline(const Recording& in, const Gap& gap, const FillOptions& options) {
  return FillPiecewiseCubic(in, gap, options, &NotAKnotMoments, &SplinePiece);
}

GapFill FillGapPchip(const Recording& in, const Gap& gap, const FillOptions& options) {
  return FillPiecewiseCubic(in, gap, options, &MonotoneSlopes, &HermitePiece);
}

}  // namespace moreau::mocap
