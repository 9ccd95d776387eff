#include "moreau/control/hamiltonian.h"

#include <algorithm>
#include <cmath>

#include "control/jet.h"

namespace moreau::control {
namespace {

using internal::Apply;
using internal::Jet2;

// One local variable of a spring term as a linear combination of at most two global variables
// (index into the stacked (z, ρ) vector of size 2n) plus a constant (fixed nodes).
struct LocalMap {
  int count = 0;
  int index[2] = {0, 0};
  double coef[2] = {0.0, 0.0};
  void Add(int i, double c) {
    index[count] = i;
    coef[count] = c;
    ++count;
  }
};

// Per-spring local quantities: Δx, Δv, e (d each) with their maps to (z, ρ).
struct SpringLocal {
  double dx[3] = {0, 0, 0};
  double dv[3] = {0, 0, 0};
  double e[3] = {0, 0, 0};
  LocalMap map[9];
};

void GatherSpring(const SpringNetwork& net, const Instant& instant, const Eigen::VectorXd& z,
                  const Eigen::VectorXd& rho, const NetworkSpring& sp, SpringLocal& loc) {
  const int d = net.dimension();
  const int n = net.state_size();
  for (int i = 0; i < 3 * d; ++i) loc.map[i] = LocalMap{};
  const int ends[2] = {sp.a, sp.b};
  const double sign[2] = {-1.0, 1.0};
  for (int side = 0; side < 2; ++side) {
    const int j = ends[side];
    const int k = net.free_index(j);
    const double s = sign[side];
    for (int i = 0; i < d; ++i) {
      if (k < 0) {
        loc.dx[i] += s * instant.fixed_position[d * j + i];
        loc.dv[i] += s * instant.fixed_velocity[d * j + i];
      } else {
        const int base = 2 * d * k;
        const double inv_m = 1.0 / net.node(j).mass;
        loc.dx[i] += s * z[base + i];
        loc.dv[i] += s * z[base + d + i];
        loc.e[i] += s * inv_m * rho[base + d + i];
        loc.map[i].Add(base + i, s);
        loc.map[d + i].Add(base + d + i, s);
        loc.map[2 * d + i].Add(n + base + d + i, s * inv_m);
      }
    }
  }
}

double LogCosh(double y) {
  const double a = std::abs(y);
  return a + std::log1p(std::exp(-2.0 * a)) - std::log(2.0);
}

// φ(Δx, Δv, e) = S^γ(κ e·u) − κ e·Δx − ξ (e·u)(u·Δv) with its derivatives in the 3d local
// variables (Δx, Δv, e).
template <int D>
Jet2<3 * D> SpringJet(const SpringLocal& loc, const NetworkSpring& sp, double gamma) {
  using J = Jet2<3 * D>;
  J dx[D], dv[D], e[D];
  for (int i = 0; i < D; ++i) {
    dx[i] = J::Variable(loc.dx[i], i);
    dv[i] = J::Variable(loc.dv[i], D + i);
    e[i] = J::Variable(loc.e[i], 2 * D + i);
  }
  J l2 = dx[0] * dx[0];
  J edx = e[0] * dx[0];
  J dxdv = dx[0] * dv[0];
  for (int i = 1; i < D; ++i) {
    l2 = l2 + dx[i] * dx[i];
    edx = edx + e[i] * dx[i];
    dxdv = dxdv + dx[i] * dv[i];
  }
  const double q = l2.v;
  const double inv_l = 1.0 / std::sqrt(q);
  const J rinv_l = Apply(l2, inv_l, -0.5 * inv_l / q, 0.75 * inv_l / (q * q));
  const J rinv_l2 = Apply(l2, 1.0 / q, -1.0 / (q * q), 2.0 / (q * q * q));
  const J p = sp.stiffness * (edx * rinv_l);
  const SmoothMin s = RegularizedSpringMin(p.v, sp.rest_min, sp.rest_max, gamma);
  const J smin = Apply(p, s.value, s.slope, s.curvature);
  return smin - sp.stiffness * edx - sp.damping * (edx * dxdv * rinv_l2);
}

template <int D>
void AddSprings(const TrackingProblem& problem, const Instant& instant, const Eigen::VectorXd& z,
                const Eigen::VectorXd& rho, HamiltonianOrder order, HamiltonianEval& out) {
  const SpringNetwork& net = problem.network();
  const int n = net.state_size();
  SpringLocal loc;
  for (const NetworkSpring& sp : net.springs()) {
    loc = SpringLocal{};
    GatherSpring(net, instant, z, rho, sp, loc);
    const Jet2<3 * D> phi = SpringJet<D>(loc, sp, problem.gamma());
    out.value += phi.v;
    for (int a = 0; a < 3 * D; ++a) {
      const LocalMap& ma = loc.map[a];
      for (int r = 0; r < ma.count; ++r) {
        const int gi = ma.index[r];
        const double g = ma.coef[r] * phi.g[a];
        if (gi < n) {
          out.dz[gi] += g;
        } else {
          out.drho[gi - n] += g;
        }
      }
    }
    if (order != HamiltonianOrder::kHessian) continue;
    for (int a = 0; a < 3 * D; ++a) {
      const LocalMap& ma = loc.map[a];
      for (int b = 0; b < 3 * D; ++b) {
        const LocalMap& mb = loc.map[b];
        const double hab = phi.h(a, b);
        if (hab == 0.0) continue;
        for (int r = 0; r < ma.count; ++r) {
          for (int c = 0; c < mb.count; ++c) {
            const int gi = ma.index[r], gj = mb.index[c];
            const double v = ma.coef[r] * mb.coef[c] * hab;
            if (gi < n && gj < n) {
              out.zz(gi, gj) += v;
            } else if (gi >= n && gj < n) {
              out.rho_z(gi - n, gj) += v;
            } else if (gi >= n && gj >= n) {
              out.rho_rho(gi - n, gj - n) += v;
            }
            // (z row, ρ column) entries are the transpose of rho_z; added from the other order.
          }
        }
      }
    }
  }
}

}  // namespace

Instant MakeInstant(const TrackingProblem& problem, double t) {
  const SpringNetwork& net = problem.network();
  const int d = net.dimension();
  const int m = net.num_free();
  Instant in;
  in.t = t;
  in.fixed_position.setZero(d * net.num_nodes());
  in.fixed_velocity.setZero(d * net.num_nodes());
  for (int j = 0; j < net.num_nodes(); ++j) {
    if (net.free_index(j) < 0) {
      net.FixedNodeState(j, t, in.fixed_position.data() + d * j, in.fixed_velocity.data() + d * j);
    }
  }
  in.ref_position.setZero(d * m);
  in.ref_velocity.setZero(d * m);
  in.ref_weight.setZero(m);
  problem.reference()(t, in.ref_position.data(), in.ref_velocity.data(), in.ref_weight.data());
  return in;
}

SmoothMin RegularizedSpringMin(double p, double rest_min, double rest_max, double gamma) {
  const double a = 0.5 * (rest_min - rest_max);
  const double b = 0.5 * (rest_min + rest_max);
  const double y = p / gamma;
  const double th = std::tanh(y);
  SmoothMin s;
  s.value = a * gamma * LogCosh(y) + b * p;
  s.slope = a * th + b;
  // 1 − tanh² computed without cancellation for large |y|: 4 e^{−2|y|} / (1 + e^{−2|y|})².
  const double ex = std::exp(-2.0 * std::abs(y));
  const double sech2 = 4.0 * ex / ((1.0 + ex) * (1.0 + ex));
  s.curvature = a * sech2 / gamma;
  return s;
}

void EvaluateRegularizedHamiltonian(const TrackingProblem& problem, const Instant& instant,
                                    const Eigen::VectorXd& z, const Eigen::VectorXd& rho,
                                    HamiltonianOrder order, HamiltonianEval& out) {
  const SpringNetwork& net = problem.network();
  const int d = net.dimension();
  const int n = net.state_size();
  const CostWeights& w = problem.weights();
  out.value = 0.0;
  out.dz.setZero(n);
  out.drho.setZero(n);
  if (order == HamiltonianOrder::kHessian) {
    out.zz.setZero(n, n);
    out.rho_z.setZero(n, n);
    out.rho_rho.setZero(n, n);
  }
  for (int k = 0; k < net.num_free(); ++k) {
    const int base = 2 * d * k;
    const double wk = instant.ref_weight[k];
    for (int i = 0; i < d; ++i) {
      const int ix = base + i, iv = base + d + i;
      // λ · v
      out.value += rho[ix] * z[iv];
      out.dz[iv] += rho[ix];
      out.drho[ix] += z[iv];
      // running cost h
      const double ex = z[ix] - instant.ref_position[d * k + i];
      const double ev = z[iv] - instant.ref_velocity[d * k + i];
      out.value += wk * (w.position * ex * ex + w.velocity * ev * ev);
      out.dz[ix] += 2.0 * wk * w.position * ex;
      out.dz[iv] += 2.0 * wk * w.velocity * ev;
      if (order == HamiltonianOrder::kHessian) {
        out.rho_z(ix, iv) += 1.0;
        out.zz(ix, ix) += 2.0 * wk * w.position;
        out.zz(iv, iv) += 2.0 * wk * w.velocity;
      }
    }
  }
  switch (d) {
    case 1:
      AddSprings<1>(problem, instant, z, rho, order, out);
      break;
    case 2:
      AddSprings<2>(problem, instant, z, rho, order, out);
      break;
    default:
      AddSprings<3>(problem, instant, z, rho, order, out);
      break;
  }
  out.running_cost = out.value - rho.dot(out.drho);
}

void SwitchingFunctions(const TrackingProblem& problem, const Instant& instant,
                        const Eigen::VectorXd& z, const Eigen::VectorXd& rho, Eigen::VectorXd& p) {
  const SpringNetwork& net = problem.network();
  const int d = net.dimension();
  p.setZero(net.num_springs());
  SpringLocal loc;
  for (int s = 0; s < net.num_springs(); ++s) {
    loc = SpringLocal{};
    GatherSpring(net, instant, z, rho, net.spring(s), loc);
    double l2 = 0.0, edx = 0.0;
    for (int i = 0; i < d; ++i) {
      l2 += loc.dx[i] * loc.dx[i];
      edx += loc.e[i] * loc.dx[i];
    }
    p[s] = net.spring(s).stiffness * edx / std::sqrt(l2);
  }
}

void EffectiveRestLengths(const TrackingProblem& problem, const Instant& instant,
                          const Eigen::VectorXd& z, const Eigen::VectorXd& rho,
                          Eigen::VectorXd& rest_lengths) {
  SwitchingFunctions(problem, instant, z, rho, rest_lengths);
  const SpringNetwork& net = problem.network();
  for (int s = 0; s < net.num_springs(); ++s) {
    const NetworkSpring& sp = net.spring(s);
    rest_lengths[s] =
        RegularizedSpringMin(rest_lengths[s], sp.rest_min, sp.rest_max, problem.gamma()).slope;
  }
}

double EvaluateHamiltonian(const TrackingProblem& problem, const Instant& instant,
                           const Eigen::VectorXd& z, const Eigen::VectorXd& rho,
                           Eigen::VectorXd* minimiser) {
  const SpringNetwork& net = problem.network();
  Eigen::VectorXd p;
  SwitchingFunctions(problem, instant, z, rho, p);
  Eigen::VectorXd rest(net.num_springs());
  for (int s = 0; s < net.num_springs(); ++s) {
    const NetworkSpring& sp = net.spring(s);
    rest[s] = p[s] < 0.0 ? sp.rest_max : sp.rest_min;
  }
  // H = ρ · f(z, L*) + h(z, t) with the bang-bang minimiser L*.
  Eigen::VectorXd rate;
  EvaluateDynamics(net, instant.t, z, rest, rate);
  if (minimiser != nullptr) *minimiser = rest;
  return rho.dot(rate) + RunningCost(problem, instant, z);
}

double RunningCost(const TrackingProblem& problem, const Instant& instant,
                   const Eigen::VectorXd& z) {
  const SpringNetwork& net = problem.network();
  const int d = net.dimension();
  const CostWeights& w = problem.weights();
  double h = 0.0;
  for (int k = 0; k < net.num_free(); ++k) {
    const int base = 2 * d * k;
    for (int i = 0; i < d; ++i) {
      const double ex = z[base + i] - instant.ref_position[d * k + i];
      const double ev = z[base + d + i] - instant.ref_velocity[d * k + i];
      h += instant.ref_weight[k] * (w.position * ex * ex + w.velocity * ev * ev);
    }
  }
  return h;
}

double TerminalCost(const TrackingProblem& problem, const Instant& terminal,
                    const Eigen::VectorXd& z, Eigen::VectorXd* gradient,
                    Eigen::VectorXd* hessian_diagonal) {
  const SpringNetwork& net = problem.network();
  const int d = net.dimension();
  const CostWeights& w = problem.weights();
  if (gradient != nullptr) gradient->setZero(net.state_size());
  if (hessian_diagonal != nullptr) hessian_diagonal->setZero(net.state_size());
  double g = 0.0;
  for (int k = 0; k < net.num_free(); ++k) {
    const int base = 2 * d * k;
    const double wk = terminal.ref_weight[k];
    for (int i = 0; i < d; ++i) {
      const double ex = z[base + i] - terminal.ref_position[d * k + i];
      const double ev = z[base + d + i] - terminal.ref_velocity[d * k + i];
      g += wk * (w.terminal_position * ex * ex + w.terminal_velocity * ev * ev);
      if (gradient != nullptr) {
        (*gradient)[base + i] = 2.0 * wk * w.terminal_position * ex;
        (*gradient)[base + d + i] = 2.0 * wk * w.terminal_velocity * ev;
      }
      if (hessian_diagonal != nullptr) {
        (*hessian_diagonal)[base + i] = 2.0 * wk * w.terminal_position;
        (*hessian_diagonal)[base + d + i] = 2.0 * wk * w.terminal_velocity;
      }
    }
  }
  return g;
}

}  // namespace moreau::control
