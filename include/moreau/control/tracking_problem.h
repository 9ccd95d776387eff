// The optimal tracking problem: steer a SpringNetwork with its rest lengths so that the free
// nodes follow reference trajectories (thesis sections 6.1 and 9).
//
//   minimise  ∫_0^T h(z(t), t) dt + g(z(T))  subject to  dz/dt = f(z, L),  L_s ∈ [L−_s, L+_s],
//   h(z, t) = Σ_j w_j(t) [ μ_x |x_j − X_j(t)|² + μ_v |v_j − V_j(t)|² ],
//   g(z)    = Σ_j w_j(T) [ η_x |x_j − X_j(T)|² + η_v |v_j − V_j(T)|² ]   (default η = 0: g = 0).
//
// The per-node, per-instant weight w_j(t) >= 0 marks missing data with 0 (an occlusion gap).
// The Hamiltonian is regularised with the parameter γ > 0 of section 6.3.
#pragma once

#include <Eigen/Core>
#include <functional>
#include <string>

#include "moreau/control/spring_network.h"

namespace moreau::control {

// Reference at time t for all free nodes, in free-node order: positions X (d M entries,
// node-major), velocities V (d M) and weights w (M). All three pointers are non-null.
using ReferenceFunction =
    std::function<void(double t, double* positions, double* velocities, double* weights)>;

// Cost weights (all >= 0).
struct CostWeights {
  double position = 1.0;           // μ_x: running cost on |x − X|² (mu1 = 100 in preSymbolic.m)
  double velocity = 0.0;           // μ_v: running cost on |v − V|²
  double terminal_position = 0.0;  // η_x: terminal cost on |x(T) − X(T)|²
  double terminal_velocity = 0.0;  // η_v: terminal cost on |v(T) − V(T)|²
};

class TrackingProblem {
 public:
  // Throws InputError ("problem.horizon: ...", "regularization.gamma: ...", "cost.<field>: ...")
  // if T <= 0, γ <= 0, a weight is negative or not finite, or the reference is empty.
  TrackingProblem(SpringNetwork network, double horizon, ReferenceFunction reference,
                  CostWeights weights, double gamma);

  const SpringNetwork& network() const { return network_; }
  double horizon() const { return horizon_; }
  const CostWeights& weights() const { return weights_; }
  double gamma() const { return gamma_; }
  const ReferenceFunction& reference() const { return reference_; }

  // δ = ½ ln2 · n · (L_max − L_min) · γ: the bound of section 6.3 on |H − H^δ|.
  double RegularizationDelta() const;

  // Same problem with another network (continuation in κ, ξ) or another γ.
  TrackingProblem WithNetwork(SpringNetwork network) const;
  TrackingProblem WithGamma(double gamma) const;

 private:
  SpringNetwork network_;
  double horizon_;
  ReferenceFunction reference_;
  CostWeights weights_;
  double gamma_;
};

// A reference given by samples at F >= 2 equally spaced frames t_k = k T / (F − 1), linearly
// interpolated in time. positions: F × (d M); velocities: F × (d M) or empty (then zero);
// weights: F × M or empty (then 1). A weight between two frames is interpolated only when both
// frames have data; otherwise it is 0 (no data). Throws InputError naming `key` when a matrix has
// the wrong number of rows or columns, or holds a non-finite value or a negative weight.
ReferenceFunction SampledReference(const SpringNetwork& network, double horizon,
                                   Eigen::MatrixXd positions, Eigen::MatrixXd velocities,
                                   Eigen::MatrixXd weights, const std::string& key);

}  // namespace moreau::control
