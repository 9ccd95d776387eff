// The mass–spring–damper network of the control problem (thesis section 6.1, dynamics (38)).
//
// A SpringNetwork is an immutable model: dimension d (1, 2 or 3), nodes that are either free
// (mass m_j > 0, initial position and velocity) or fixed (prescribed position p_j + w_j t, where
// w_j is a constant velocity, zero for a wall anchor), and springs (a, b) with stiffness κ,
// damping ξ and rest-length bounds [L−, L+]. The rest length of each spring is the control.
//
// The state z stacks, for every free node j in order, z_j = (x_j[0..d), v_j[0..d)) as in (36);
// its size is 2 d M with M the number of free nodes. The dual ρ has the same layout,
// ρ_j = (λ_j, ζ_j). Units: any consistent set (the examples use SI-like units: length, mass, s).
//
// The force of spring s = (a, b) on node b is, with Δx = x_b − x_a, l = |Δx|, u = Δx / l and
// Δv = v_b − v_a,  F = u [κ (L − l) − ξ (u · Δv)],  and −F on node a (equation (38)).
#pragma once

#include <Eigen/Core>
#include <functional>
#include <string>
#include <vector>

namespace moreau::control {

// One node of the network.
struct NetworkNode {
  bool fixed = false;                                  // true: prescribed position, no mass
  double mass = 1.0;                                   // m_j > 0 for free nodes; ignored when fixed
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  // free: x_j(0); fixed: p_j (only the
                                                       // first d entries are used)
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();  // free: v_j(0); fixed: w_j, the node
                                                       // moves as p_j + w_j t
  // Fixed nodes only, optional: a general prescribed motion t ↦ (position, velocity) (d entries
  // each) that replaces p_j + w_j t. Must be smooth enough for the scheme (C¹ in t).
  std::function<void(double t, double* position, double* velocity)> motion;
};

// One spring–damper unit between nodes a and b (indices into the node list, a != b).
struct NetworkSpring {
  int a = 0;
  int b = 1;
  double stiffness = 1.0;  // κ >= 0
  double damping = 0.0;    // ξ >= 0
  double rest_min = 1.0;   // L− >= 0
  double rest_max = 1.0;   // L+ >= L−
};

class SpringNetwork {
 public:
  // Validates and stores the network. Throws InputError, the message starting with the scenario
  // key of the offending entry ("network.nodes[3].mass: ..."), when: d is not 1, 2 or 3; there is
  // no free node; a free node has mass <= 0 or a non-finite entry; a spring names a missing node,
  // connects a node to itself or joins two fixed nodes; κ < 0, ξ < 0, L− < 0 or L− > L+; two
  // connected nodes coincide at t = 0 (the spring direction (37) is undefined); the network is not
  // connected (every node must be reachable from every other through springs).
  SpringNetwork(int dimension, std::vector<NetworkNode> nodes, std::vector<NetworkSpring> springs);

  int dimension() const { return dimension_; }
  int num_nodes() const { return static_cast<int>(nodes_.size()); }
  int num_springs() const { return static_cast<int>(springs_.size()); }
  int num_free() const { return num_free_; }
  // Size of z (and of ρ): 2 d M.
  int state_size() const { return 2 * dimension_ * num_free_; }

  const std::vector<NetworkNode>& nodes() const { return nodes_; }
  const std::vector<NetworkSpring>& springs() const { return springs_; }
  const NetworkNode& node(int j) const { return nodes_[static_cast<std::size_t>(j)]; }
  const NetworkSpring& spring(int s) const { return springs_[static_cast<std::size_t>(s)]; }

  // Index of node j among the free nodes (its block in z is [2 d k, 2 d (k + 1))), or −1 if fixed.
  int free_index(int j) const { return free_index_[static_cast<std::size_t>(j)]; }
  // Node index of the k-th free node.
  int free_node(int k) const { return free_nodes_[static_cast<std::size_t>(k)]; }

  // Initial state z(0) (size state_size()).
  Eigen::VectorXd InitialState() const;

  // Position (d entries) and velocity of fixed node j at time t: p_j + w_j t and w_j, or the
  // node's `motion` when it has one.
  void FixedNodeState(int j, double t, double* position, double* velocity) const;

  // Position of node j at t = 0 (3 entries, the first d used).
  Eigen::Vector3d PositionAtStart(int j) const;

  // Largest and smallest rest-length bounds over all springs (L_max, L_min of section 6.2).
  double MaxRestLength() const;
  double MinRestLength() const;

  // Returns a copy in which every κ is multiplied by stiffness_scale and every ξ by
  // damping_scale (both > 0); used by continuation (section 8.2).
  SpringNetwork Scaled(double stiffness_scale, double damping_scale) const;

 private:
  int dimension_;
  std::vector<NetworkNode> nodes_;
  std::vector<NetworkSpring> springs_;
  std::vector<int> free_index_;
  std::vector<int> free_nodes_;
  int num_free_ = 0;
};

// Dynamics (38): f(z, L) for the rest lengths L (size num_springs) at time t (through fixed
// nodes). Writes dz/dt (size state_size()) into `rate`.
void EvaluateDynamics(const SpringNetwork& network, double t, const Eigen::VectorXd& z,
                      const Eigen::VectorXd& rest_lengths, Eigen::VectorXd& rate);

}  // namespace moreau::control
