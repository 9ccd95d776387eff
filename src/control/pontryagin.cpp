#include "moreau/control/pontryagin.h"

#include <fmt/format.h>

#include <cmath>
#include <limits>

#include "moreau/common/error.h"

namespace moreau::control {

PontryaginDiscretization::PontryaginDiscretization(const TrackingProblem& problem, int steps)
    : problem_(problem), steps_(steps), n_(problem.network().state_size()), dt_(0.0) {
  if (steps < 1) {
    throw InputError(fmt::format("discretization.steps: must be >= 1, got {}", steps));
  }
  dt_ = problem.horizon() / steps;
  if (!(dt_ > 0.0)) {
    throw InputError(fmt::format("discretization.steps: time step T/N = {} is not positive", dt_));
  }
  z0_ = problem.network().InitialState();
  instants_.reserve(static_cast<std::size_t>(steps) + 1);
  for (int k = 0; k <= steps; ++k) {
    // The last instant is exactly T (no rounding drift in k Δt).
    const double t = (k == steps) ? problem.horizon() : k * dt_;
    instants_.push_back(MakeInstant(problem_, t));
  }
}

Eigen::Map<const Eigen::VectorXd> PontryaginDiscretization::Z(const Eigen::VectorXd& y,
                                                              int k) const {
  return {y.data() + static_cast<Eigen::Index>(2 * n_) * (k - 1), n_};
}
Eigen::Map<const Eigen::VectorXd> PontryaginDiscretization::Rho(const Eigen::VectorXd& y,
                                                                int k) const {
  return {y.data() + static_cast<Eigen::Index>(2 * n_) * k + n_, n_};
}
Eigen::Map<Eigen::VectorXd> PontryaginDiscretization::Z(Eigen::VectorXd& y, int k) const {
  return {y.data() + static_cast<Eigen::Index>(2 * n_) * (k - 1), n_};
}
Eigen::Map<Eigen::VectorXd> PontryaginDiscretization::Rho(Eigen::VectorXd& y, int k) const {
  return {y.data() + static_cast<Eigen::Index>(2 * n_) * k + n_, n_};
}

Eigen::VectorXd PontryaginDiscretization::Pack(const Eigen::MatrixXd& z,
                                               const Eigen::MatrixXd& rho) const {
  Eigen::VectorXd y(unknowns());
  for (int k = 0; k < steps_; ++k) {
    Z(y, k + 1) = z.col(k + 1);
    Rho(y, k) = rho.col(k);
  }
  return y;
}

void PontryaginDiscretization::Unpack(const Eigen::VectorXd& y, Eigen::MatrixXd& z,
                                      Eigen::MatrixXd& rho) const {
  z.resize(n_, steps_ + 1);
  rho.resize(n_, steps_ + 1);
  z.col(0) = z0_;
  for (int k = 0; k < steps_; ++k) {
    z.col(k + 1) = Z(y, k + 1);
    rho.col(k) = Rho(y, k);
  }
  Eigen::VectorXd zn = z.col(steps_), dg;
  TerminalCost(problem_, instants_.back(), zn, &dg, nullptr);
  rho.col(steps_) = dg;
}

namespace {

// Loads z^n and ρ^{n+1} (with ρ^N = Dg(z^N)) into the workspace.
void LoadStep(const PontryaginDiscretization& disc, const Eigen::VectorXd& y, int n,
              PontryaginWorkspace& ws) {
  const int N = disc.steps();
  if (n == 0) {
    ws.zn = disc.initial_state();
  } else {
    ws.zn = disc.Z(y, n);
  }
  if (n + 1 == N) {
    Eigen::VectorXd zN = disc.Z(y, N);
    TerminalCost(disc.problem(), disc.instant(N), zN, &ws.dg, nullptr);
    ws.rho_next = ws.dg;
  } else {
    ws.rho_next = disc.Rho(y, n + 1);
  }
}

double ResidualImpl(const PontryaginDiscretization& disc, const Eigen::VectorXd& y,
                    PontryaginWorkspace& ws, Eigen::VectorXd& residual, bool jacobian) {
  const int N = disc.steps();
  const int nz = disc.state_size();
  const double dt = disc.dt();
  residual.resize(disc.unknowns());
  PontryaginJacobian& J = ws.jacobian;
  if (jacobian) {
    J.A.resize(static_cast<std::size_t>(N));
    J.B.resize(static_cast<std::size_t>(N));
    J.C.resize(static_cast<std::size_t>(N));
    Eigen::VectorXd zN = disc.Z(y, N), g;
    TerminalCost(disc.problem(), disc.instant(N), zN, &g, &J.G);
  }
  const HamiltonianOrder order =
      jacobian ? HamiltonianOrder::kHessian : HamiltonianOrder::kGradient;
  for (int n = 0; n < N; ++n) {
    LoadStep(disc, y, n, ws);
    EvaluateRegularizedHamiltonian(disc.problem(), disc.instant(n), ws.zn, ws.rho_next, order,
                                   ws.eval);
    const Eigen::Index off = static_cast<Eigen::Index>(2 * nz) * n;
    residual.segment(off, nz) = disc.Z(y, n + 1) - ws.zn - dt * ws.eval.drho;
    residual.segment(off + nz, nz) = disc.Rho(y, n) - ws.rho_next - dt * ws.eval.dz;
    if (jacobian) {
      const auto k = static_cast<std::size_t>(n);
      J.A[k] = dt * ws.eval.rho_z;
      J.A[k].diagonal().array() += 1.0;
      J.B[k] = dt * ws.eval.rho_rho;
      J.C[k] = dt * ws.eval.zz;
    }
  }
  if (!residual.allFinite()) return std::numeric_limits<double>::infinity();
  return residual.lpNorm<Eigen::Infinity>();
}

}  // namespace

double EvaluateResidual(const PontryaginDiscretization& disc, const Eigen::VectorXd& y,
                        PontryaginWorkspace& ws, Eigen::VectorXd& residual) {
  return ResidualImpl(disc, y, ws, residual, false);
}

double EvaluateResidualAndJacobian(const PontryaginDiscretization& disc, const Eigen::VectorXd& y,
                                   PontryaginWorkspace& ws, Eigen::VectorXd& residual) {
  return ResidualImpl(disc, y, ws, residual, true);
}

Eigen::SparseMatrix<double> AssembleSparseJacobian(const PontryaginDiscretization& disc,
                                                   const PontryaginJacobian& J) {
  const int N = disc.steps();
  const int nz = disc.state_size();
  const Eigen::Index b = 2 * nz;
  std::vector<Eigen::Triplet<double>> t;
  t.reserve(static_cast<std::size_t>(N) * static_cast<std::size_t>(4 * nz * nz + 2 * nz));
  auto add_block = [&](Eigen::Index r0, Eigen::Index c0, const Eigen::MatrixXd& m, double s) {
    for (Eigen::Index j = 0; j < m.cols(); ++j) {
      for (Eigen::Index i = 0; i < m.rows(); ++i) {
        if (m(i, j) != 0.0) t.emplace_back(r0 + i, c0 + j, s * m(i, j));
      }
    }
  };
  for (int n = 0; n < N; ++n) {
    const auto k = static_cast<std::size_t>(n);
    const Eigen::Index row = b * n;
    // Diagonal identity.
    for (Eigen::Index i = 0; i < b; ++i) t.emplace_back(row + i, row + i, 1.0);
    if (n >= 1) {
      const Eigen::Index col = b * (n - 1);  // z^n lives in block n−1
      add_block(row, col, J.A[k], -1.0);
      add_block(row + nz, col, J.C[k], -1.0);
    }
    if (n + 1 < N) {
      const Eigen::Index col = b * (n + 1) + nz;  // ρ^{n+1} in block n+1
      add_block(row, col, J.B[k], -1.0);
      add_block(row + nz, col, J.A[k].transpose(), -1.0);
    } else {
      // ρ^N = Dg(z^N): derivative through z^N (block N−1, z part).
      const Eigen::MatrixXd bg = J.B[k] * J.G.asDiagonal();
      const Eigen::MatrixXd ag = J.A[k].transpose() * J.G.asDiagonal();
      add_block(row, row, bg, -1.0);
      add_block(row + nz, row, ag, -1.0);
    }
  }
  Eigen::SparseMatrix<double> m(disc.unknowns(), disc.unknowns());
  m.setFromTriplets(t.begin(), t.end());
  return m;
}

double DiscreteValue(const PontryaginDiscretization& disc, const Eigen::VectorXd& y,
                     PontryaginWorkspace& ws) {
  const int N = disc.steps();
  double value = 0.0;
  for (int n = 0; n < N; ++n) {
    LoadStep(disc, y, n, ws);
    EvaluateRegularizedHamiltonian(disc.problem(), disc.instant(n), ws.zn, ws.rho_next,
                                   HamiltonianOrder::kGradient, ws.eval);
    value += ws.eval.running_cost * disc.dt();
  }
  Eigen::VectorXd zN = disc.Z(y, N);
  return value + TerminalCost(disc.problem(), disc.instant(N), zN);
}

Eigen::MatrixXd EffectiveControls(const PontryaginDiscretization& disc, const Eigen::VectorXd& y) {
  const int N = disc.steps();
  PontryaginWorkspace ws;
  Eigen::MatrixXd controls(disc.problem().network().num_springs(), N);
  Eigen::VectorXd rest;
  for (int n = 0; n < N; ++n) {
    LoadStep(disc, y, n, ws);
    EffectiveRestLengths(disc.problem(), disc.instant(n), ws.zn, ws.rho_next, rest);
    controls.col(n) = rest;
  }
  return controls;
}

}  // namespace moreau::control
