#include "moreau/control/spring_network.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numeric>

#include "moreau/common/error.h"

namespace moreau::control {
namespace {

[[noreturn]] void Fail(const std::string& key, const std::string& reason) {
  throw InputError(fmt::format("{}: {}", key, reason));
}

std::string NodeKey(std::size_t j, const char* field) {
  return fmt::format("network.nodes[{}].{}", j, field);
}
std::string SpringKey(std::size_t s, const char* field) {
  return fmt::format("network.springs[{}].{}", s, field);
}

int FindRoot(std::vector<int>& parent, int i) {
  while (parent[static_cast<std::size_t>(i)] != i) {
    auto& p = parent[static_cast<std::size_t>(i)];
    p = parent[static_cast<std::size_t>(p)];
    i = p;
  }
  return i;
}

}  // namespace

SpringNetwork::SpringNetwork(int dimension, std::vector<NetworkNode> nodes,
                             std::vector<NetworkSpring> springs)
    : dimension_(dimension), nodes_(std::move(nodes)), springs_(std::move(springs)) {
  if (dimension_ < 1 || dimension_ > 3) {
    Fail("network.dimension", fmt::format("must be 1, 2 or 3, got {}", dimension_));
  }
  const std::size_t num_nodes = nodes_.size();
  free_index_.assign(num_nodes, -1);
  for (std::size_t j = 0; j < num_nodes; ++j) {
    const NetworkNode& node = nodes_[j];
    for (int k = 0; k < dimension_; ++k) {
      if (!std::isfinite(node.position[k])) Fail(NodeKey(j, "position"), "is not finite");
      if (!std::isfinite(node.velocity[k])) Fail(NodeKey(j, "velocity"), "is not finite");
    }
    if (!node.fixed) {
      if (!(node.mass > 0.0) || !std::isfinite(node.mass)) {
        Fail(NodeKey(j, "mass"), fmt::format("must be positive and finite, got {}", node.mass));
      }
      free_index_[j] = num_free_++;
      free_nodes_.push_back(static_cast<int>(j));
    }
  }
  if (num_free_ == 0) Fail("network.nodes", "needs at least one free (non-fixed) node");
  for (std::size_t j = 0; j < num_nodes; ++j) {
    if (nodes_[j].motion && !nodes_[j].fixed) {
      Fail(NodeKey(j, "motion"), "only a fixed node can have a prescribed motion");
    }
  }
  if (springs_.empty()) Fail("network.springs", "needs at least one spring");

  std::vector<int> parent(num_nodes);
  std::iota(parent.begin(), parent.end(), 0);
  for (std::size_t s = 0; s < springs_.size(); ++s) {
    const NetworkSpring& sp = springs_[s];
    const int n = static_cast<int>(num_nodes);
    if (sp.a < 0 || sp.a >= n || sp.b < 0 || sp.b >= n) {
      Fail(SpringKey(s, "nodes"),
           fmt::format("node index out of range [0, {}): ({}, {})", n, sp.a, sp.b));
    }
    if (sp.a == sp.b) Fail(SpringKey(s, "nodes"), "connects a node to itself");
    const NetworkNode& na = nodes_[static_cast<std::size_t>(sp.a)];
    const NetworkNode& nb = nodes_[static_cast<std::size_t>(sp.b)];
    if (na.fixed && nb.fixed) {
      Fail(SpringKey(s, "nodes"),
           fmt::format("joins two fixed nodes ({}, {}); it can do nothing", sp.a, sp.b));
    }
    if (!(sp.stiffness >= 0.0) || !std::isfinite(sp.stiffness)) {
      Fail(SpringKey(s, "stiffness"), fmt::format("must be >= 0, got {}", sp.stiffness));
    }
    if (!(sp.damping >= 0.0) || !std::isfinite(sp.damping)) {
      Fail(SpringKey(s, "damping"), fmt::format("must be >= 0, got {}", sp.damping));
    }
    if (!(sp.rest_min >= 0.0) || !std::isfinite(sp.rest_min)) {
      Fail(SpringKey(s, "rest_min"), fmt::format("must be >= 0, got {}", sp.rest_min));
    }
    if (!std::isfinite(sp.rest_max) || sp.rest_min > sp.rest_max) {
      Fail(SpringKey(s, "rest_max"),
           fmt::format("L- = {} exceeds L+ = {} (need L- <= L+)", sp.rest_min, sp.rest_max));
    }
    const Eigen::Vector3d pa = PositionAtStart(sp.a), pb = PositionAtStart(sp.b);
    double length2 = 0.0, scale = 1.0;
    for (int i = 0; i < dimension_; ++i) {
      length2 += (pb[i] - pa[i]) * (pb[i] - pa[i]);
      scale = std::max({scale, std::abs(pa[i]), std::abs(pb[i])});
    }
    const double length = std::sqrt(length2);
    if (!(length > 1e-12 * scale)) {
      Fail(SpringKey(s, "nodes"),
           fmt::format("nodes {} and {} coincide at t = 0; the spring direction is undefined "
                       "(assumption (37))",
                       sp.a, sp.b));
    }
    parent[static_cast<std::size_t>(FindRoot(parent, sp.a))] = FindRoot(parent, sp.b);
  }
  const int root = FindRoot(parent, 0);
  for (std::size_t j = 1; j < num_nodes; ++j) {
    if (FindRoot(parent, static_cast<int>(j)) != root) {
      Fail("network.springs",
           fmt::format("the network is disconnected: node {} is not linked to node 0", j));
    }
  }
}

Eigen::Vector3d SpringNetwork::PositionAtStart(int j) const {
  const NetworkNode& node = nodes_[static_cast<std::size_t>(j)];
  if (!node.fixed || !node.motion) return node.position;
  Eigen::Vector3d x = Eigen::Vector3d::Zero(), v = Eigen::Vector3d::Zero();
  node.motion(0.0, x.data(), v.data());
  return x;
}

Eigen::VectorXd SpringNetwork::InitialState() const {
  const int d = dimension_;
  Eigen::VectorXd z(state_size());
  for (int k = 0; k < num_free_; ++k) {
    const NetworkNode& node =
        nodes_[static_cast<std::size_t>(free_nodes_[static_cast<std::size_t>(k)])];
    z.segment(2 * d * k, d) = node.position.head(d);
    z.segment(2 * d * k + d, d) = node.velocity.head(d);
  }
  return z;
}

void SpringNetwork::FixedNodeState(int j, double t, double* position, double* velocity) const {
  const NetworkNode& node = nodes_[static_cast<std::size_t>(j)];
  if (node.motion) {
    node.motion(t, position, velocity);
    return;
  }
  for (int k = 0; k < dimension_; ++k) {
    position[k] = node.position[k] + node.velocity[k] * t;
    velocity[k] = node.velocity[k];
  }
}

double SpringNetwork::MaxRestLength() const {
  double m = 0.0;
  for (const auto& s : springs_) m = std::max(m, s.rest_max);
  return m;
}

double SpringNetwork::MinRestLength() const {
  double m = springs_.front().rest_min;
  for (const auto& s : springs_) m = std::min(m, s.rest_min);
  return m;
}

SpringNetwork SpringNetwork::Scaled(double stiffness_scale, double damping_scale) const {
  std::vector<NetworkSpring> springs = springs_;
  for (auto& s : springs) {
    s.stiffness *= stiffness_scale;
    s.damping *= damping_scale;
  }
  return SpringNetwork(dimension_, nodes_, std::move(springs));
}

void EvaluateDynamics(const SpringNetwork& network, double t, const Eigen::VectorXd& z,
                      const Eigen::VectorXd& rest_lengths, Eigen::VectorXd& rate) {
  const int d = network.dimension();
  rate.setZero(network.state_size());
  for (int k = 0; k < network.num_free(); ++k) {
    rate.segment(2 * d * k, d) = z.segment(2 * d * k + d, d);
  }
  double xa[3], va[3], xb[3], vb[3];
  auto node_state = [&](int j, double* x, double* v) {
    const int k = network.free_index(j);
    if (k < 0) {
      network.FixedNodeState(j, t, x, v);
    } else {
      for (int i = 0; i < d; ++i) {
        x[i] = z[2 * d * k + i];
        v[i] = z[2 * d * k + d + i];
      }
    }
  };
  for (int s = 0; s < network.num_springs(); ++s) {
    const NetworkSpring& sp = network.spring(s);
    node_state(sp.a, xa, va);
    node_state(sp.b, xb, vb);
    double dx[3], l2 = 0.0;
    for (int i = 0; i < d; ++i) {
      dx[i] = xb[i] - xa[i];
      l2 += dx[i] * dx[i];
    }
    const double l = std::sqrt(l2);
    double uv = 0.0;
    for (int i = 0; i < d; ++i) uv += dx[i] / l * (vb[i] - va[i]);
    const double magnitude = sp.stiffness * (rest_lengths[s] - l) - sp.damping * uv;
    const int ka = network.free_index(sp.a);
    const int kb = network.free_index(sp.b);
    for (int i = 0; i < d; ++i) {
      const double f = magnitude * dx[i] / l;
      if (kb >= 0) rate[2 * d * kb + d + i] += f / network.node(sp.b).mass;
      if (ka >= 0) rate[2 * d * ka + d + i] -= f / network.node(sp.a).mass;
    }
  }
}

}  // namespace moreau::control
