// Low-rank (PCA) fill after Gløersen & Federolf (2016), iterated to its least-squares fixed point.
//
// Products use Eigen's lazy (coefficient-based) evaluation so that the result never depends on
// Eigen's OpenMP blocking, and hence not on the number of threads of the caller.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <optional>

#include <Eigen/Eigenvalues>

#include "fill_internal.h"

namespace moreau::mocap {

namespace {

// The markers used for one gap: the gapped one first, then the candidates, with each candidate's
// mean distance to the gapped marker.
struct PcaMarkers {
  std::vector<int> markers;
  std::vector<double> distance;  // per candidate (markers[1…])
};

// Mean distance between markers a and b over the frames where both are observed (nullopt if none).
std::optional<double> MeanDistance(const Recording& in, int a, int b) {
  double sum = 0.0;
  std::int64_t n = 0;
  for (std::int64_t f = 0; f < in.frames(); ++f) {
    if (in.observed(f, a) && in.observed(f, b)) {
      sum += (in.point(f, a) - in.point(f, b)).norm();
      ++n;
    }
  }
  if (n == 0) return std::nullopt;
  return sum / static_cast<double>(n);
}

// Candidates: observed throughout the gap and seen together with the gapped marker; those that
// have missing samples elsewhere and lie beyond distal_threshold × the mean distance are dropped.
PcaMarkers ChooseMarkers(const Recording& in, const Gap& gap, const PcaFillOptions& o) {
  PcaMarkers all;
  for (int c = 0; c < in.markers(); ++c) {
    if (c == gap.marker || !in.is_marker(c) ||
        !internal::ObservedThroughout(in, c, gap.first, gap.last)) {
      continue;
    }
    if (auto d = MeanDistance(in, gap.marker, c)) {
      all.markers.push_back(c);
      all.distance.push_back(*d);
    }
  }
  PcaMarkers kept{{gap.marker}, {}};
  if (all.markers.empty()) return kept;
  double mean = 0.0;
  for (double d : all.distance) mean += d;
  mean /= static_cast<double>(all.distance.size());
  for (std::size_t k = 0; k < all.markers.size(); ++k) {
    const bool has_gaps = in.ObservedCount(all.markers[k]) < in.frames();
    if (has_gaps && all.distance[k] > o.distal_threshold * mean) continue;
    kept.markers.push_back(all.markers[k]);
    kept.distance.push_back(all.distance[k]);
  }
  return kept;
}

// Rows: positions of `markers` at each frame relative to the mean of markers[1…] (the gapped
// marker's columns 0…2 are left at zero where it is missing).
Eigen::MatrixXd RelativePositions(const Recording& in, const std::vector<int>& markers,
                                  const std::vector<std::int64_t>& frames) {
  const auto cols = static_cast<Eigen::Index>(3 * markers.size());
  Eigen::MatrixXd x = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(frames.size()), cols);
  for (std::size_t r = 0; r < frames.size(); ++r) {
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    for (std::size_t j = 1; j < markers.size(); ++j) centre += in.point(frames[r], markers[j]);
    centre /= static_cast<double>(markers.size() - 1);
    for (std::size_t j = 0; j < markers.size(); ++j) {
      if (!in.observed(frames[r], markers[j])) continue;
      x.row(static_cast<Eigen::Index>(r)).segment<3>(static_cast<Eigen::Index>(3 * j)) =
          (in.point(frames[r], markers[j]) - centre).transpose();
    }
  }
  return x;
}

// The leading principal directions (columns) of the rows of z: the fewest whose singular values
// sum to ≥ fraction of the total.
Eigen::MatrixXd PrincipalDirections(const Eigen::MatrixXd& z, double fraction) {
  const Eigen::MatrixXd gram = z.transpose().lazyProduct(z);
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(gram);
  const Eigen::Index n = gram.rows();
  const Eigen::VectorXd sv = eig.eigenvalues().cwiseMax(0.0).cwiseSqrt().reverse();
  const double total = sv.sum();
  Eigen::Index k = 0;
  double sum = 0.0;
  while (k < n && sum < fraction * total) sum += sv[k++];
  k = std::max<Eigen::Index>(k, 1);
  return eig.eigenvectors().rightCols(k).rowwise().reverse();
}

}  // namespace

GapFill FillGapPca(const Recording& in, const Gap& gap, const FillOptions& options) {
  const PcaFillOptions& o = options.pca;
  const PcaMarkers used = ChooseMarkers(in, gap, o);
  if (used.markers.size() < 2) {
    return {GapStatus::kNoDonors, "no other marker is observed throughout the gap", {}};
  }
  std::vector<std::int64_t> complete, gap_frames;
  for (std::int64_t f = 0; f < in.frames(); ++f) {
    bool all = true;
    for (int m : used.markers) all = all && in.observed(f, m);
    if (all) complete.push_back(f);
  }
  if (static_cast<int>(complete.size()) < o.min_complete_frames) {
    return {GapStatus::kTooFewSamples,
            fmt::format("{} complete frames for {} markers; pca.min_complete_frames = {}",
                        complete.size(), used.markers.size(), o.min_complete_frames),
            {}};
  }
  for (std::int64_t f = gap.first; f <= gap.last; ++f) gap_frames.push_back(f);

  // Normalise (mean and standard deviation over the complete frames) and weight.
  const Eigen::MatrixXd xc = RelativePositions(in, used.markers, complete);
  const Eigen::RowVectorXd mean = xc.colwise().mean();
  Eigen::RowVectorXd sd = (xc.rowwise() - mean).colwise().squaredNorm().cwiseSqrt() /
                          std::sqrt(static_cast<double>(complete.size()));
  const double sd_max = sd.maxCoeff();
  for (Eigen::Index j = 0; j < sd.size(); ++j) {
    if (!(sd[j] > 1e-12 * sd_max)) sd[j] = 1.0;
  }
  const double sigma = o.weight_scale_m / MetresPerUnit(in.units());
  Eigen::RowVectorXd scale(sd.size());
  for (std::size_t j = 0; j < used.markers.size(); ++j) {
    const double w =
        j == 0 ? o.missing_marker_weight
               : std::exp(-used.distance[j - 1] * used.distance[j - 1] / (2.0 * sigma * sigma));
    for (int c = 0; c < 3; ++c) {
      const auto col = static_cast<Eigen::Index>(3 * j) + c;
      scale[col] = w / sd[col];
    }
  }
  const Eigen::MatrixXd zc = (xc.rowwise() - mean).array().rowwise() * scale.array();
  const Eigen::MatrixXd v = PrincipalDirections(zc, o.explained_fraction);

  // Iterate: gapped coordinates ← those of the projection onto the retained directions.
  const Eigen::MatrixXd xg = RelativePositions(in, used.markers, gap_frames);
  Eigen::MatrixXd zg = (xg.rowwise() - mean).array().rowwise() * scale.array();
  zg.leftCols<3>().setZero();
  const Eigen::MatrixXd v_gapped = v.topRows<3>().transpose();  // k × 3
  double change = 0.0;
  int iterations = 0;
  do {
    const Eigen::MatrixXd next = zg.lazyProduct(v).lazyProduct(v_gapped);
    // In standard deviations of the coordinate: Δx / sd = Δz / w.
    change = (next - zg.leftCols<3>()).cwiseAbs().maxCoeff() / o.missing_marker_weight;
    zg.leftCols<3>() = next;
    ++iterations;
  } while (change > o.tolerance && iterations < o.max_iterations);

  GapFill fill;
  fill.points.resize(3, gap.length());
  for (std::int64_t r = 0; r < gap.length(); ++r) {
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    for (std::size_t j = 1; j < used.markers.size(); ++j) {
      centre += in.point(gap.first + r, used.markers[j]);
    }
    centre /= static_cast<double>(used.markers.size() - 1);
    for (int c = 0; c < 3; ++c) {
      fill.points(c, r) = centre[c] + mean[c] + zg(r, c) / scale[c];
    }
  }
  fill.message = fmt::format("{} markers, {} complete frames, {} components, {} iterations",
                             used.markers.size(), complete.size(), v.cols(), iterations);
  if (change > o.tolerance) {
    fill.message += fmt::format("; not converged (last change {:.3g} sd)", change);
  }
  return fill;
}

}  // namespace moreau::mocap
