#include "mocap/ocp_prior.h"

#include <Eigen/LU>
#include <Eigen/SVD>

#include <algorithm>
#include <cmath>
#include <vector>

namespace moreau::mocap::internal {
namespace {

// Position of `marker` at frame f carried rigidly from frame `ref` by the partners observed at
// both frames. Returns false when no partner is usable.
bool CarryRigidly(const Recording& in, const MarkerNetwork& net, int marker, std::int64_t ref,
                  std::int64_t f, Eigen::Vector3d& x) {
  std::vector<Eigen::Vector3d> p, q;
  for (int s : net.springs_of[static_cast<std::size_t>(marker)]) {
    const int k = net.Partner(s, marker);
    if (in.observed(ref, k) && in.observed(f, k)) {
      p.emplace_back(in.point(ref, k));
      q.emplace_back(in.point(f, k));
    }
  }
  if (p.empty()) return false;
  Eigen::Vector3d pc = Eigen::Vector3d::Zero(), qc = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < p.size(); ++i) {
    pc += p[i];
    qc += q[i];
  }
  pc /= static_cast<double>(p.size());
  qc /= static_cast<double>(q.size());
  const Eigen::Vector3d rel = in.point(ref, marker) - pc;
  if (p.size() < 3) {
    x = qc + rel;
    return true;
  }
  Eigen::Matrix3d h = Eigen::Matrix3d::Zero();
  for (std::size_t i = 0; i < p.size(); ++i) h += (p[i] - pc) * (q[i] - qc).transpose();
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(h, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d fix = Eigen::Matrix3d::Identity();
  fix(2, 2) = (svd.matrixV() * svd.matrixU().transpose()).determinant() < 0.0 ? -1.0 : 1.0;
  const Eigen::Matrix3d r = svd.matrixV() * fix * svd.matrixU().transpose();
  x = qc + r * rel;
  return true;
}

}  // namespace

GapTrack LinearGapFill(const Recording& in, const Gap& gap) {
  const std::int64_t before = gap.first - 1, after = gap.last + 1;
  const bool has_before = before >= 0, has_after = after < in.frames();
  GapTrack out(gap.length(), 3);
  for (std::int64_t f = gap.first; f <= gap.last; ++f) {
    Eigen::Vector3d x;
    if (has_before && has_after) {
      const double tau = static_cast<double>(f - before) / static_cast<double>(after - before);
      x = (1.0 - tau) * in.point(before, gap.marker) + tau * in.point(after, gap.marker);
    } else if (has_before) {
      x = in.point(before, gap.marker);
    } else if (has_after) {
      x = in.point(after, gap.marker);
    } else {
      x.setZero();
    }
    out.row(f - gap.first) = x.transpose();
  }
  return out;
}

GapTrack RigidGapFill(const Recording& in, const MarkerNetwork& net, const Gap& gap) {
  GapTrack out = LinearGapFill(in, gap);
  const std::int64_t before = gap.first - 1, after = gap.last + 1;
  const bool has_before = before >= 0, has_after = after < in.frames();
  for (std::int64_t f = gap.first; f <= gap.last; ++f) {
    Eigen::Vector3d xb, xa;
    const bool ok_b = has_before && CarryRigidly(in, net, gap.marker, before, f, xb);
    const bool ok_a = has_after && CarryRigidly(in, net, gap.marker, after, f, xa);
    Eigen::Vector3d x;
    if (ok_b && ok_a) {
      const double tau = static_cast<double>(f - before) / static_cast<double>(after - before);
      x = (1.0 - tau) * xb + tau * xa;
    } else if (ok_b) {
      x = xb;
    } else if (ok_a) {
      x = xa;
    } else {
      continue;
    }
    out.row(f - gap.first) = x.transpose();
  }
  return out;
}

double DistanceDisagreement(const Recording& in, const MarkerNetwork& net, const Gap& gap,
                            const GapTrack& fill) {
  double sum = 0.0;
  long count = 0;
  for (std::int64_t f = gap.first; f <= gap.last; ++f) {
    const Eigen::Vector3d x = fill.row(f - gap.first).transpose();
    for (int s : net.springs_of[static_cast<std::size_t>(gap.marker)]) {
      const int k = net.Partner(s, gap.marker);
      if (!in.observed(f, k)) continue;
      const MarkerSpring& sp = net.springs[static_cast<std::size_t>(s)];
      // Scale: the spread, at least the margin of the spring's rest-length bounds.
      const double scale = std::max(sp.spread, sp.rest_max - sp.max);
      const double z = ((x - in.point(f, k)).norm() - sp.mean) / std::max(scale, 1e-12);
      sum += z * z;
      ++count;
    }
  }
  return count > 0 ? sum / static_cast<double>(count) : 0.0;
}

}  // namespace moreau::mocap::internal
