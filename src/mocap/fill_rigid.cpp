// Rigid-body (pattern) fill: donors carried by a least-squares rigid motion (Kabsch).
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <utility>

#include <Eigen/Geometry>
#include <Eigen/SVD>

#include "fill_internal.h"

namespace moreau::mocap {

namespace {

// The rotation and translation (x ↦ R x + t) that best maps `from` onto `to` in least squares
// (both 3 × k, k ≥ 3, matching columns; a proper rotation, det R = +1).
Eigen::Isometry3d FitRigidMotion(const Eigen::Matrix3Xd& from, const Eigen::Matrix3Xd& to) {
  const Eigen::Vector3d from_mean = from.rowwise().mean();
  const Eigen::Vector3d to_mean = to.rowwise().mean();
  const Eigen::Matrix3d h = (from.colwise() - from_mean) * (to.colwise() - to_mean).transpose();
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(h, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d flip = Eigen::Matrix3d::Identity();
  flip(2, 2) = (svd.matrixV() * svd.matrixU().transpose()).determinant() < 0.0 ? -1.0 : 1.0;
  Eigen::Isometry3d motion = Eigen::Isometry3d::Identity();
  motion.linear() = svd.matrixV() * flip * svd.matrixU().transpose();
  motion.translation() = to_mean - motion.linear() * from_mean;
  return motion;
}

// Standard deviation of the distance between markers a and b over the frames where both are
// observed; nullopt when fewer than `min_frames` such frames.
std::optional<double> DistanceSpread(const Recording& in, int a, int b, int min_frames) {
  double sum = 0.0, sum_sq = 0.0;
  std::int64_t n = 0;
  for (std::int64_t f = 0; f < in.frames(); ++f) {
    if (!in.observed(f, a) || !in.observed(f, b)) continue;
    const double d = (in.point(f, a) - in.point(f, b)).norm();
    sum += d;
    sum_sq += d * d;
    ++n;
  }
  if (n < min_frames) return std::nullopt;
  const double mean = sum / static_cast<double>(n);
  return std::sqrt(std::max(0.0, sum_sq / static_cast<double>(n) - mean * mean));
}

// The donors: markers observed at frames first − 1 … last + 1, ordered by how little their
// distance to the gapped marker varies (ties by index), at most `count`.
std::vector<int> ChooseDonors(const Recording& in, const Gap& gap, const RigidFillOptions& o) {
  std::vector<std::pair<double, int>> candidates;
  for (int c = 0; c < in.markers(); ++c) {
    if (c == gap.marker || !in.is_marker(c) ||
        !internal::ObservedThroughout(in, c, gap.first - 1, gap.last + 1)) {
      continue;
    }
    if (auto spread = DistanceSpread(in, gap.marker, c, o.min_common_frames)) {
      candidates.emplace_back(*spread, c);
    }
  }
  std::sort(candidates.begin(), candidates.end());
  std::vector<int> donors;
  for (const auto& [spread, c] : candidates) {
    if (static_cast<int>(donors.size()) == o.donors) break;
    donors.push_back(c);
  }
  return donors;
}

Eigen::Matrix3Xd DonorPositions(const Recording& in, const std::vector<int>& donors,
                                std::int64_t frame) {
  Eigen::Matrix3Xd p(3, static_cast<Eigen::Index>(donors.size()));
  for (std::size_t k = 0; k < donors.size(); ++k) {
    p.col(static_cast<Eigen::Index>(k)) = in.point(frame, donors[k]);
  }
  return p;
}

// True when the donors span a plane (their second singular value is not negligible).
bool SpansPlane(const Eigen::Matrix3Xd& p) {
  const Eigen::Matrix3Xd centred = p.colwise() - p.rowwise().mean();
  const Eigen::Vector3d sv = Eigen::JacobiSVD<Eigen::Matrix3Xd>(centred).singularValues();
  return sv[1] > 1e-9 * sv[0];
}

}  // namespace

GapFill FillGapRigid(const Recording& in, const Gap& gap, const FillOptions& options) {
  if (auto edge = internal::EdgeStatus(in, gap)) return *edge;
  const std::vector<int> donors = ChooseDonors(in, gap, options.rigid);
  if (static_cast<int>(donors.size()) < options.rigid.donors) {
    return {GapStatus::kNoDonors,
            fmt::format("{} marker(s) observed from frame {} to {} with {} frames in common "
                        "with the gapped marker; {} donors needed",
                        donors.size(), gap.first - 1, gap.last + 1, options.rigid.min_common_frames,
                        options.rigid.donors),
            {}};
  }
  const std::int64_t a = gap.first - 1;
  const std::int64_t b = gap.last + 1;
  const Eigen::Matrix3Xd donors_a = DonorPositions(in, donors, a);
  const Eigen::Matrix3Xd donors_b = DonorPositions(in, donors, b);
  if (!SpansPlane(donors_a) || !SpansPlane(donors_b)) {
    return {GapStatus::kNoDonors, "the donors are collinear (rotation undetermined)", {}};
  }
  const Eigen::Vector3d pa = in.point(a, gap.marker);
  const Eigen::Vector3d pb = in.point(b, gap.marker);
  GapFill fill;
  fill.points.resize(3, gap.length());
  for (std::int64_t f = gap.first; f <= gap.last; ++f) {
    const Eigen::Matrix3Xd donors_f = DonorPositions(in, donors, f);
    const Eigen::Vector3d from_a = FitRigidMotion(donors_a, donors_f) * pa;
    const Eigen::Vector3d from_b = FitRigidMotion(donors_b, donors_f) * pb;
    const double w = static_cast<double>(f - a) / static_cast<double>(b - a);
    fill.points.col(f - gap.first) = (1.0 - w) * from_a + w * from_b;
  }
  std::string names;
  for (int d : donors) {
    names += (names.empty() ? "" : ", ") + in.labels()[static_cast<std::size_t>(d)];
  }
  fill.message = "donors: " + names;
  return fill;
}

}  // namespace moreau::mocap
