// Seeded random spring networks and problems for the control tests.
#pragma once

#include <cmath>
#include <random>
#include <vector>

#include "moreau/control/tracking_problem.h"

namespace moreau::control::testing {

// A connected network in dimension d with `free_nodes` free and `fixed_nodes` fixed nodes on a
// jittered grid (so connected nodes never coincide): a spanning chain plus a few extra springs.
// Fixed nodes move slowly (non-zero w) so that time-dependent anchors are exercised.
inline SpringNetwork RandomNetwork(int d, int free_nodes, int fixed_nodes, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::uniform_real_distribution<double> pos(0.5, 2.0);
  const int total = free_nodes + fixed_nodes;
  std::vector<NetworkNode> nodes(static_cast<std::size_t>(total));
  for (int j = 0; j < total; ++j) {
    NetworkNode& node = nodes[static_cast<std::size_t>(j)];
    node.fixed = j >= free_nodes;
    node.mass = pos(rng);
    for (int k = 0; k < d; ++k) {
      node.position[k] = 1.3 * ((j + k) % 3) + 1.1 * j * (k == 0) + 0.2 * u(rng);
      node.velocity[k] = 0.3 * u(rng);
    }
  }
  std::vector<NetworkSpring> springs;
  auto add = [&](int a, int b) {
    const double length =
        (nodes[static_cast<std::size_t>(b)].position - nodes[static_cast<std::size_t>(a)].position)
            .head(d)
            .norm();
    springs.push_back(NetworkSpring{a, b, pos(rng) * 3.0, pos(rng), 0.6 * length, 1.4 * length});
  };
  for (int j = 1; j < total; ++j) {
    if (nodes[static_cast<std::size_t>(j)].fixed && nodes[static_cast<std::size_t>(j - 1)].fixed) {
      add(0, j);
    } else {
      add(j - 1, j);
    }
  }
  if (free_nodes >= 3) add(0, 2);
  if (total >= 4 && free_nodes >= 2) add(1, total - 1);
  return SpringNetwork(d, std::move(nodes), std::move(springs));
}

// A smooth random reference (sines) with weights in {0, 0.5 .. 1.5} per node.
inline ReferenceFunction RandomReference(const SpringNetwork& net, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const int d = net.dimension();
  const int m = net.num_free();
  std::vector<double> amp(static_cast<std::size_t>(d * m)), freq(amp.size()), base(amp.size());
  std::vector<double> weight(static_cast<std::size_t>(m));
  const Eigen::VectorXd z0 = net.InitialState();
  for (int k = 0; k < m; ++k) {
    weight[static_cast<std::size_t>(k)] = (k % 3 == 2) ? 0.0 : 1.0 + 0.5 * u(rng);
    for (int i = 0; i < d; ++i) {
      const auto idx = static_cast<std::size_t>(d * k + i);
      amp[idx] = 0.2 * u(rng);
      freq[idx] = 1.0 + u(rng);
      base[idx] = z0[2 * d * k + i];
    }
  }
  return [amp, freq, base, weight, d, m](double t, double* x, double* v, double* w) {
    for (int i = 0; i < d * m; ++i) {
      const auto idx = static_cast<std::size_t>(i);
      x[i] = base[idx] + amp[idx] * std::sin(freq[idx] * t);
      v[i] = amp[idx] * freq[idx] * std::cos(freq[idx] * t);
    }
    for (int k = 0; k < m; ++k) w[k] = weight[static_cast<std::size_t>(k)];
  };
}

inline TrackingProblem RandomProblem(int d, int free_nodes, int fixed_nodes, double gamma,
                                     std::mt19937& rng, bool terminal_cost = true) {
  SpringNetwork net = RandomNetwork(d, free_nodes, fixed_nodes, rng);
  ReferenceFunction ref = RandomReference(net, rng);
  CostWeights w;
  w.position = 2.0;
  w.velocity = 0.5;
  if (terminal_cost) {
    w.terminal_position = 1.5;
    w.terminal_velocity = 0.25;
  }
  return TrackingProblem(std::move(net), 1.0, std::move(ref), w, gamma);
}

inline Eigen::VectorXd RandomVector(Eigen::Index n, double scale, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::VectorXd v(n);
  for (Eigen::Index i = 0; i < n; ++i) v[i] = scale * u(rng);
  return v;
}

}  // namespace moreau::control::testing
