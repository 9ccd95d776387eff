#include "moreau/control/tracking_problem.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "moreau/common/error.h"

namespace moreau::control {

TrackingProblem::TrackingProblem(SpringNetwork network, double horizon, ReferenceFunction reference,
                                 CostWeights weights, double gamma)
    : network_(std::move(network)),
      horizon_(horizon),
      reference_(std::move(reference)),
      weights_(weights),
      gamma_(gamma) {
  if (!(horizon_ > 0.0) || !std::isfinite(horizon_)) {
    throw InputError(fmt::format("problem.horizon: must be positive and finite, got {}", horizon_));
  }
  if (!(gamma_ > 0.0) || !std::isfinite(gamma_)) {
    throw InputError(fmt::format("regularization.gamma: must be positive, got {}", gamma_));
  }
  const std::pair<const char*, double> fields[] = {
      {"position", weights_.position},
      {"velocity", weights_.velocity},
      {"terminal_position", weights_.terminal_position},
      {"terminal_velocity", weights_.terminal_velocity}};
  for (const auto& [name, value] : fields) {
    if (!(value >= 0.0) || !std::isfinite(value)) {
      throw InputError(fmt::format("cost.{}: must be >= 0 and finite, got {}", name, value));
    }
  }
  if (!reference_) throw InputError("reference: no reference trajectory given");
}

double TrackingProblem::RegularizationDelta() const {
  return 0.5 * std::log(2.0) * network_.num_springs() *
         (network_.MaxRestLength() - network_.MinRestLength()) * gamma_;
}

TrackingProblem TrackingProblem::WithNetwork(SpringNetwork network) const {
  return TrackingProblem(std::move(network), horizon_, reference_, weights_, gamma_);
}

TrackingProblem TrackingProblem::WithGamma(double gamma) const {
  return TrackingProblem(network_, horizon_, reference_, weights_, gamma);
}

ReferenceFunction SampledReference(const SpringNetwork& network, double horizon,
                                   Eigen::MatrixXd positions, Eigen::MatrixXd velocities,
                                   Eigen::MatrixXd weights, const std::string& key) {
  const int d = network.dimension();
  const int m = network.num_free();
  const Eigen::Index frames = positions.rows();
  if (frames < 2) {
    throw InputError(fmt::format("{}.positions: needs at least 2 frames, got {}", key, frames));
  }
  if (positions.cols() != d * m) {
    throw InputError(
        fmt::format("{}.positions: reference of the wrong length: each frame must hold d * (free "
                    "nodes) = {} values, got {}",
                    key, d * m, positions.cols()));
  }
  if (velocities.size() == 0) velocities = Eigen::MatrixXd::Zero(frames, d * m);
  if (weights.size() == 0) weights = Eigen::MatrixXd::Ones(frames, m);
  if (velocities.rows() != frames || velocities.cols() != d * m) {
    throw InputError(
        fmt::format("{}.velocities: expected {} x {} values (frames x d M), got {} x {}", key,
                    frames, d * m, velocities.rows(), velocities.cols()));
  }
  if (weights.rows() != frames || weights.cols() != m) {
    throw InputError(
        fmt::format("{}.weights: expected {} x {} values (frames x free nodes), got {} x {}", key,
                    frames, m, weights.rows(), weights.cols()));
  }
  if (!positions.allFinite()) throw InputError(fmt::format("{}.positions: non-finite value", key));
  if (!velocities.allFinite()) {
    throw InputError(fmt::format("{}.velocities: non-finite value", key));
  }
  if (!weights.allFinite() || weights.minCoeff() < 0.0) {
    throw InputError(fmt::format("{}.weights: weights must be finite and >= 0", key));
  }
  const double frame_dt = horizon / static_cast<double>(frames - 1);
  return [positions = std::move(positions), velocities = std::move(velocities),
          weights = std::move(weights), frame_dt, frames, d,
          m](double t, double* x, double* v, double* w) {
    double s = std::clamp(t / frame_dt, 0.0, static_cast<double>(frames - 1));
    Eigen::Index k = std::min<Eigen::Index>(static_cast<Eigen::Index>(std::floor(s)), frames - 2);
    double theta = s - static_cast<double>(k);
    // Snap to a frame when t is (numerically) on it so that a frame's own weight is used.
    if (theta < 1e-9) theta = 0.0;
    if (theta > 1.0 - 1e-9) theta = 1.0;
    for (int i = 0; i < d * m; ++i) {
      x[i] = (1.0 - theta) * positions(k, i) + theta * positions(k + 1, i);
      v[i] = (1.0 - theta) * velocities(k, i) + theta * velocities(k + 1, i);
    }
    for (int j = 0; j < m; ++j) {
      const double w0 = weights(k, j), w1 = weights(k + 1, j);
      if (theta == 0.0) {
        w[j] = w0;
      } else if (theta == 1.0) {
        w[j] = w1;
      } else {
        w[j] = (w0 == 0.0 || w1 == 0.0) ? 0.0 : (1.0 - theta) * w0 + theta * w1;
      }
    }
  };
}

}  // namespace moreau::control
