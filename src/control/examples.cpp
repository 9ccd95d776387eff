#include "moreau/control/examples.h"

#include <fmt/format.h>

#include <cmath>
#include <numbers>

#include "moreau/common/error.h"

namespace moreau::control {
namespace {

// One free mass at x(0) = start, at rest, on a spring–damper to a wall at 0 (d = 1).
template <typename Example>
SpringNetwork WallAndMass(const Example& ex, double start) {
  NetworkNode wall;
  wall.fixed = true;
  NetworkNode mass;
  mass.mass = ex.mass;
  mass.position[0] = start;
  NetworkSpring spring{0, 1, ex.stiffness, ex.damping, ex.rest_min, ex.rest_max};
  return SpringNetwork(1, {wall, mass}, {spring});
}

}  // namespace

TrackingProblem MakeOscillatorProblem(const OscillatorExample& ex, double p) {
  if (!(ex.move_time > 0.0)) {
    throw InputError(fmt::format("oscillator.move_time: must be positive, got {}", ex.move_time));
  }
  SpringNetwork network = WallAndMass(ex, ex.start);
  const double delta = p * (ex.target - ex.start);
  const double tm = ex.move_time;
  const double x0 = ex.start;
  ReferenceFunction reference = [delta, tm, x0](double t, double* x, double* v, double* w) {
    const double tau = std::min(t / tm, 1.0);
    const double two_pi = 2.0 * std::numbers::pi;
    x[0] = x0 + delta * (tau - std::sin(two_pi * tau) / two_pi);
    v[0] = t < tm ? delta * (1.0 - std::cos(two_pi * tau)) / tm : 0.0;
    w[0] = 1.0;
  };
  CostWeights weights;
  weights.position = ex.position_weight;
  weights.velocity = ex.velocity_weight;
  return TrackingProblem(std::move(network), ex.horizon, std::move(reference), weights, ex.gamma);
}

void ArmReference(const ArmExample& ex, double p, double t, double* x, double* v) {
  const double deg = std::numbers::pi / 180.0;
  const double f = 2.0 * std::numbers::pi * ex.periods / ex.horizon;
  // α(t) = p α_max (1 − cos f t) / 2, α' = p α_max f sin(f t) / 2.
  auto angle = [&](double max_deg, double& a, double& da) {
    a = p * max_deg * deg * 0.5 * (1.0 - std::cos(f * t));
    da = p * max_deg * deg * 0.5 * f * std::sin(f * t);
  };
  double th1, dth1, th2, dth2, ph1, dph1, ph2, dph2;
  angle(ex.angle_ab_deg, th1, dth1);
  angle(ex.angle_bc_deg, th2, dth2);
  angle(ex.angle_34_deg, ph1, dph1);
  angle(ex.angle_12_deg, ph2, dph2);
  const double bx = ex.anchor[0] + ex.upper_bone * std::cos(th1);
  const double by = ex.anchor[1] + ex.upper_bone * std::sin(th1);
  const double bvx = -ex.upper_bone * std::sin(th1) * dth1;
  const double bvy = ex.upper_bone * std::cos(th1) * dth1;
  const double cx = bx + ex.lower_bone * std::cos(th2);
  const double cy = by + ex.lower_bone * std::sin(th2);
  const double cvx = bvx - ex.lower_bone * std::sin(th2) * dth2;
  const double cvy = bvy + ex.lower_bone * std::cos(th2) * dth2;
  // Marker at centre + r (cos β, sin β), β = base + offset.
  auto marker = [&](int node, double ox, double oy, double ovx, double ovy, double r, double beta,
                    double dbeta) {
    x[2 * node] = ox + r * std::cos(beta);
    x[2 * node + 1] = oy + r * std::sin(beta);
    v[2 * node] = ovx - r * std::sin(beta) * dbeta;
    v[2 * node + 1] = ovy + r * std::cos(beta) * dbeta;
  };
  const double half_pi = 0.5 * std::numbers::pi;
  marker(0, cx, cy, cvx, cvy, ex.hand_half_width, th2 + ph2 + half_pi, dth2 + dph2);
  marker(1, cx, cy, cvx, cvy, ex.hand_half_width, th2 + ph2 - half_pi, dth2 + dph2);
  marker(2, bx, by, bvx, bvy, ex.elbow_half_width, th1 + ph1 + half_pi, dth1 + dph1);
  marker(3, bx, by, bvx, bvy, ex.elbow_half_width, th1 + ph1 - half_pi, dth1 + dph1);
}

TrackingProblem MakeArmProblem(const ArmExample& ex, double p) {
  if (!(ex.spring_limit >= 0.0 && ex.spring_limit < 1.0)) {
    throw InputError(fmt::format("arm.spring_limit: must be in [0, 1), got {}", ex.spring_limit));
  }
  if (!(ex.horizon > 0.0)) {
    throw InputError(fmt::format("problem.horizon: must be positive, got {}", ex.horizon));
  }
  double x0[8], v0[8], xb[8], vb[8];
  ArmReference(ex, p, 0.0, x0, v0);
  ArmReference(ex, 1.0, ex.bounds_time, xb, vb);
  std::vector<NetworkNode> nodes(6);
  for (int j = 0; j < 4; ++j) {
    nodes[static_cast<std::size_t>(j)].mass = ex.mass;
    nodes[static_cast<std::size_t>(j)].position = Eigen::Vector3d(x0[2 * j], x0[2 * j + 1], 0.0);
  }
  nodes[4].fixed = true;
  nodes[4].position = Eigen::Vector3d(0.0, 0.0, 0.0);
  nodes[5].fixed = true;
  nodes[5].position = Eigen::Vector3d(0.0, 1.0, 0.0);
  // Thesis springs 3–1, 4–1, 2–1, 4–2, 5–3, 6–3, 4–3, 6–4 (1-based) in 0-based indices.
  const int pairs[8][2] = {{2, 0}, {3, 0}, {1, 0}, {3, 1}, {4, 2}, {5, 2}, {3, 2}, {5, 3}};
  auto position_at_bounds = [&](int j) {
    if (j < 4) return Eigen::Vector2d(xb[2 * j], xb[2 * j + 1]);
    return Eigen::Vector2d(nodes[static_cast<std::size_t>(j)].position.head<2>());
  };
  std::vector<NetworkSpring> springs;
  for (const auto& pr : pairs) {
    const double length = (position_at_bounds(pr[1]) - position_at_bounds(pr[0])).norm();
    springs.push_back(NetworkSpring{pr[0], pr[1], ex.stiffness, ex.damping,
                                    (1.0 - ex.spring_limit) * length,
                                    (1.0 + ex.spring_limit) * length});
  }
  SpringNetwork network(2, std::move(nodes), std::move(springs));
  ReferenceFunction reference = [ex, p](double t, double* x, double* v, double* w) {
    ArmReference(ex, p, t, x, v);
    for (int j = 0; j < 4; ++j) w[j] = 1.0;
  };
  CostWeights weights;
  weights.position = ex.position_weight;
  weights.velocity = ex.velocity_weight;
  return TrackingProblem(std::move(network), ex.horizon, std::move(reference), weights, ex.gamma);
}

TrackingProblem MakeSaturatingProblem(const SaturatingExample& ex, double p) {
  if (!(ex.period > 0.0)) {
    throw InputError(fmt::format("saturating.period: must be positive, got {}", ex.period));
  }
  SpringNetwork network = WallAndMass(ex, ex.centre);
  const double amplitude = p * ex.amplitude;
  const double omega = 2.0 * std::numbers::pi / ex.period;
  const double centre = ex.centre;
  ReferenceFunction reference = [=](double t, double* x, double* v, double* w) {
    x[0] = centre + amplitude * std::sin(omega * t);
    v[0] = amplitude * omega * std::cos(omega * t);
    w[0] = 1.0;
  };
  CostWeights weights;
  weights.position = ex.position_weight;
  weights.velocity = ex.velocity_weight;
  return TrackingProblem(std::move(network), ex.horizon, std::move(reference), weights, ex.gamma);
}

}  // namespace moreau::control
