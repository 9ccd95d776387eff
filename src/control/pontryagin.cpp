#include "moreau/control/pontryagin.h"

#include <fmt/format.h>

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "moreau/common/error.h"
#include "moreau/common/memory.h"

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

// Loads z^n and ρ^{n+1} (with ρ^N = dg = Dg(z^N)) into the scratch.
void LoadStep(const PontryaginDiscretization& disc, const Eigen::VectorXd& y, int n,
              const Eigen::VectorXd& dg, PontryaginStepScratch& s) {
  if (n == 0) {
    s.zn = disc.initial_state();
  } else {
    s.zn = disc.Z(y, n);
  }
  if (n + 1 == disc.steps()) {
    s.rho_next = dg;
  } else {
    s.rho_next = disc.Rho(y, n + 1);
  }
}

// Threads for a sweep over N steps: one below 64 steps (not worth a parallel region).
int SweepThreads(int requested, int steps) {
  if (steps < 64) return 1;
  return requested > 0 ? requested : std::max(1, omp_get_max_threads());
}

// Residual block n (and its Jacobian blocks): touches only block n of the outputs.
void EvaluateStep(const PontryaginDiscretization& disc, const Eigen::VectorXd& y, int n,
                  HamiltonianOrder order, PontryaginWorkspace& ws, PontryaginStepScratch& s,
                  Eigen::VectorXd& residual) {
  const int nz = disc.state_size();
  const double dt = disc.dt();
  LoadStep(disc, y, n, ws.dg, s);
  EvaluateRegularizedHamiltonian(disc.problem(), disc.instant(n), s.zn, s.rho_next, order, s.eval);
  const Eigen::Index off = static_cast<Eigen::Index>(2 * nz) * n;
  residual.segment(off, nz) = disc.Z(y, n + 1) - s.zn - dt * s.eval.drho;
  residual.segment(off + nz, nz) = disc.Rho(y, n) - s.rho_next - dt * s.eval.dz;
  if (order == HamiltonianOrder::kHessian) {
    PontryaginJacobian& J = ws.jacobian;
    const auto k = static_cast<std::size_t>(n);
    J.A[k] = dt * s.eval.rho_z;
    J.A[k].diagonal().array() += 1.0;
    J.B[k] = dt * s.eval.rho_rho;
    J.C[k] = dt * s.eval.zz;
  }
}

double ResidualImpl(const PontryaginDiscretization& disc, const Eigen::VectorXd& y,
                    PontryaginWorkspace& ws, Eigen::VectorXd& residual, bool jacobian) {
  const int N = disc.steps();
  residual.resize(disc.unknowns());
  PontryaginJacobian& J = ws.jacobian;
  const Eigen::VectorXd zN = disc.Z(y, N);
  TerminalCost(disc.problem(), disc.instant(N), zN, &ws.dg, jacobian ? &J.G : nullptr);
  if (jacobian) {
    J.A.resize(static_cast<std::size_t>(N));
    J.B.resize(static_cast<std::size_t>(N));
    J.C.resize(static_cast<std::size_t>(N));
  }
  const HamiltonianOrder order =
      jacobian ? HamiltonianOrder::kHessian : HamiltonianOrder::kGradient;
  const int threads = SweepThreads(ws.threads, N);
  if (ws.scratch.size() < static_cast<std::size_t>(threads)) {
    ws.scratch.resize(static_cast<std::size_t>(threads));
  }
  // Each step writes only its own blocks, so the result does not depend on the thread count.
#pragma omp parallel for num_threads(threads) schedule(static) if (threads > 1)
  for (int n = 0; n < N; ++n) {
    PontryaginStepScratch& s = ws.scratch[static_cast<std::size_t>(omp_get_thread_num())];
    EvaluateStep(disc, y, n, order, ws, s, residual);
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
  const Eigen::VectorXd zN = disc.Z(y, N);
  const double terminal = TerminalCost(disc.problem(), disc.instant(N), zN, &ws.dg, nullptr);
  if (ws.scratch.empty()) ws.scratch.resize(1);
  PontryaginStepScratch& s = ws.scratch.front();
  double value = 0.0;
  for (int n = 0; n < N; ++n) {
    LoadStep(disc, y, n, ws.dg, s);
    EvaluateRegularizedHamiltonian(disc.problem(), disc.instant(n), s.zn, s.rho_next,
                                   HamiltonianOrder::kGradient, s.eval);
    value += s.eval.running_cost * disc.dt();
  }
  return value + terminal;
}

Eigen::MatrixXd EffectiveControls(const PontryaginDiscretization& disc, const Eigen::VectorXd& y) {
  const int N = disc.steps();
  PontryaginStepScratch s;
  Eigen::VectorXd dg;
  const Eigen::VectorXd zN = disc.Z(y, N);
  TerminalCost(disc.problem(), disc.instant(N), zN, &dg, nullptr);
  Eigen::MatrixXd controls(disc.problem().network().num_springs(), N);
  Eigen::VectorXd rest;
  for (int n = 0; n < N; ++n) {
    LoadStep(disc, y, n, dg, s);
    EffectiveRestLengths(disc.problem(), disc.instant(n), s.zn, s.rho_next, rest);
    controls.col(n) = rest;
  }
  return controls;
}

void CheckSolveMemory(const SpringNetwork& network, std::int64_t steps) {
  if (steps < 1 || steps > kMaxSteps) {
    throw InputError(fmt::format("N must be between 1 and {} (got {})", kMaxSteps, steps));
  }
  const double nz = network.state_size();
  const double per_step = 8.0 * (8.0 * nz * nz + 24.0 * nz + network.num_springs()) +
                          25.0 * (3.0 * nz + network.num_springs()) + 512.0;
  CheckMemory(fmt::format("{} steps", steps), per_step * (static_cast<double>(steps) + 1.0));
}

}  // namespace moreau::control
