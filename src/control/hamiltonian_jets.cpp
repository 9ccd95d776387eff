// The forward-mode-jet evaluation of the spring terms: an independent implementation that
// cross-checks the closed form of spring_term.h in the tests.
#include <cmath>

#include "control/hamiltonian_internal.h"
#include "control/jet.h"

namespace moreau::control::internal {
namespace {

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

void EvaluateRegularizedHamiltonianWithJets(const TrackingProblem& problem, const Instant& instant,
                                            const Eigen::VectorXd& z, const Eigen::VectorXd& rho,
                                            HamiltonianOrder order, HamiltonianEval& out) {
  AssembleRegularizedHamiltonian(problem, instant, z, rho, order, out, [&](auto d) {
    AddSprings<decltype(d)::value>(problem, instant, z, rho, order, out);
  });
}

}  // namespace moreau::control::internal
