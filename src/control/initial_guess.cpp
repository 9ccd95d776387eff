#include "moreau/control/initial_guess.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>

#include "moreau/common/error.h"
#include "moreau/control/hamiltonian.h"

namespace moreau::control {
namespace {

// Position (d entries) of node j in state z at the instant.
Eigen::VectorXd NodePosition(const SpringNetwork& net, const Instant& instant,
                             const Eigen::VectorXd& z, int j) {
  const int d = net.dimension();
  const int k = net.free_index(j);
  return k < 0 ? Eigen::VectorXd(instant.fixed_position.segment(d * j, d))
               : Eigen::VectorXd(z.segment(2 * d * k, d));
}

// ζ (d M) for which P_s(z, ρ) = κ_s e_s · u_s matches the switching values that realise the
// controls at rest on z (clamped into the bounds), in the least-squares sense.
Eigen::VectorXd FittedVelocityCostate(const TrackingProblem& problem, const Instant& instant,
                                      const Eigen::VectorXd& z) {
  const SpringNetwork& net = problem.network();
  const int d = net.dimension();
  const int unknowns = d * net.num_free();
  Eigen::MatrixXd normal = Eigen::MatrixXd::Zero(unknowns, unknowns);
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(unknowns);
  Eigen::VectorXd row(unknowns);
  for (const NetworkSpring& sp : net.springs()) {
    const Eigen::VectorXd dx =
        NodePosition(net, instant, z, sp.b) - NodePosition(net, instant, z, sp.a);
    const double l = dx.norm();
    if (!(l > 0.0)) continue;
    const double half = 0.5 * (sp.rest_min - sp.rest_max);  // <= 0
    double target = 0.0;                                    // P_s that realises the control
    if (half < 0.0) {
      const double mid = 0.5 * (sp.rest_min + sp.rest_max);
      const double c = std::clamp((std::clamp(l, sp.rest_min, sp.rest_max) - mid) / half,
                                  -1.0 + 1e-3, 1.0 - 1e-3);
      target = problem.gamma() * std::atanh(c);
    }
    row.setZero();
    const int ends[2] = {sp.a, sp.b};
    for (int side = 0; side < 2; ++side) {
      const int k = net.free_index(ends[side]);
      if (k < 0) continue;
      const double sign = side == 0 ? -1.0 : 1.0;
      row.segment(d * k, d) = sign * sp.stiffness / net.node(ends[side]).mass * dx / l;
    }
    normal.noalias() += row * row.transpose();
    rhs += target * row;
  }
  // A node whose springs do not span every direction leaves ζ free there: the smallest ζ.
  const double ridge = 1e-12 * std::max(normal.diagonal().maxCoeff(), 1e-300);
  normal.diagonal().array() += ridge;
  return normal.ldlt().solve(rhs);
}

}  // namespace

Eigen::VectorXd FittedControlStart(const PontryaginDiscretization& disc,
                                   const Eigen::MatrixXd& positions) {
  const TrackingProblem& problem = disc.problem();
  const SpringNetwork& net = problem.network();
  const int d = net.dimension(), m = net.num_free(), N = disc.steps();
  const int nz = disc.state_size();
  const double dt = disc.dt();
  MOREAU_ASSERT(positions.rows() == d * m && positions.cols() == N + 1);
  Eigen::MatrixXd z(nz, N + 1), rho = Eigen::MatrixXd::Zero(nz, N + 1);
  z.col(0) = disc.initial_state();
  for (int n = 1; n <= N; ++n) {
    for (int k = 0; k < m; ++k) {
      z.col(n).segment(2 * d * k, d) = positions.col(n).segment(d * k, d);
    }
  }
  for (int n = 1; n <= N; ++n) {
    const int a = std::min(n, N - 1);
    for (int k = 0; k < m; ++k) {
      z.col(n).segment(2 * d * k + d, d) =
          (z.col(a + 1).segment(2 * d * k, d) - z.col(a).segment(2 * d * k, d)) / dt;
    }
  }
  Eigen::VectorXd dg;
  TerminalCost(problem, disc.instant(N), z.col(N), &dg, nullptr);
  rho.col(N) = dg;
  for (int n = 0; n + 1 < N; ++n) {
    const Eigen::VectorXd zeta = FittedVelocityCostate(problem, disc.instant(n), z.col(n));
    for (int k = 0; k < m; ++k) rho.col(n + 1).segment(2 * d * k + d, d) = zeta.segment(d * k, d);
  }
  HamiltonianEval eval;
  Eigen::VectorXd zn, rn;
  for (int n = N - 1; n >= 0; --n) {
    zn = z.col(n);
    rn = rho.col(n + 1);
    EvaluateRegularizedHamiltonian(problem, disc.instant(n), zn, rn, HamiltonianOrder::kGradient,
                                   eval);
    for (int k = 0; k < m; ++k) {
      const int x = 2 * d * k, v = x + d;
      rho.col(n).segment(x, d) = rn.segment(x, d) + dt * eval.dz.segment(x, d);
      if (n == 0) rho.col(0).segment(v, d) = rn.segment(v, d) + dt * eval.dz.segment(v, d);
    }
  }
  return disc.Pack(z, rho);
}

}  // namespace moreau::control
