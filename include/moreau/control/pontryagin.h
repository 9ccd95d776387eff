// The Symplectic Pontryagin discretisation (thesis (29)) and its Newton system ((41)–(43)).
//
// With Δt = T / N, t_n = n Δt and H = H^δ evaluated at (z^n, ρ^{n+1}, t_n):
//   F^z_n = z^{n+1} − z^n − Δt H_ρ(z^n, ρ^{n+1}, t_n) = 0,   n = 0 … N−1,   z^0 = z(0),
//   F^ρ_n = ρ^n − ρ^{n+1} − Δt H_z(z^n, ρ^{n+1}, t_n) = 0,   n = 0 … N−1,   ρ^N = Dg(z^N).
// The unknowns y are z^1 … z^N and ρ^0 … ρ^{N−1} (ρ^N is eliminated as in the remark after
// (43)). Unlike (42), which orders y component by component, y is stored time-block by
// time-block: block n = (z^{n+1}, ρ^n), n = 0 … N−1, each of size 2n_z; F is stored alike,
// block n = (F^z_n, F^ρ_n). The orderings differ by a permutation only. In this ordering the
// Jacobian is block tridiagonal.
//
// The discrete value (31) is  ū = Σ_{n=0}^{N−1} h^δ(z^n, ρ^{n+1}, t_n) Δt + g(z^N), with
// h^δ = H^δ − ρ·H^δ_ρ (30); the thesis writes h^δ(x_n, λ_n), but the scheme couples x_n with
// λ_{n+1}, and with that pairing ū equals the cost of the discrete trajectory (docs/control.md).
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <vector>

#include "moreau/control/hamiltonian.h"
#include "moreau/control/tracking_problem.h"

namespace moreau::control {

// The discretised problem for a given number of steps N: per-step instants are precomputed.
class PontryaginDiscretization {
 public:
  // Throws InputError("discretization.steps: ...") if steps < 1.
  PontryaginDiscretization(const TrackingProblem& problem, int steps);

  const TrackingProblem& problem() const { return problem_; }
  int steps() const { return steps_; }
  double dt() const { return dt_; }
  int state_size() const { return n_; }
  int block_size() const { return 2 * n_; }
  // Size of y: 2 n_z N.
  Eigen::Index unknowns() const { return static_cast<Eigen::Index>(2) * n_ * steps_; }
  const Instant& instant(int n) const { return instants_[static_cast<std::size_t>(n)]; }
  const Eigen::VectorXd& initial_state() const { return z0_; }

  // Views into y: z^k for k = 1 … N and ρ^k for k = 0 … N−1.
  Eigen::Map<const Eigen::VectorXd> Z(const Eigen::VectorXd& y, int k) const;
  Eigen::Map<const Eigen::VectorXd> Rho(const Eigen::VectorXd& y, int k) const;
  Eigen::Map<Eigen::VectorXd> Z(Eigen::VectorXd& y, int k) const;
  Eigen::Map<Eigen::VectorXd> Rho(Eigen::VectorXd& y, int k) const;

  // Packs full trajectories (z: N+1 columns of n_z, ρ: N+1 columns) into y, and back
  // (Unpack also fills z^0 and ρ^N = Dg(z^N)).
  Eigen::VectorXd Pack(const Eigen::MatrixXd& z, const Eigen::MatrixXd& rho) const;
  void Unpack(const Eigen::VectorXd& y, Eigen::MatrixXd& z, Eigen::MatrixXd& rho) const;

 private:
  TrackingProblem problem_;
  int steps_;
  int n_;
  double dt_;
  Eigen::VectorXd z0_;
  std::vector<Instant> instants_;  // t_0 … t_N
};

// The Newton Jacobian in block-tridiagonal form, kept as the Hamiltonian Hessians per step:
// A_n = I + Δt H_ρz, B_n = Δt H_ρρ, C_n = Δt H_zz (all n_z × n_z) and G = D²g (diagonal).
// In block form (block n rows (F^z_n, F^ρ_n), columns (z^{n+1}, ρ^n)):
//   ∂/∂(z^n, ρ^{n−1})   = [[−A_n, 0], [−C_n, 0]]           (lower, n >= 1)
//   ∂/∂(z^{n+1}, ρ^n)   = [[I, 0], [0, I]]                 (diagonal; for n = N−1 the column
//                          z^N also gets [−B_n G; −A_nᵀ G] through ρ^N = Dg(z^N))
//   ∂/∂(z^{n+2}, ρ^{n+1}) = [[0, −B_n], [0, −A_nᵀ]]         (upper, n <= N−2)
struct PontryaginJacobian {
  std::vector<Eigen::MatrixXd> A, B, C;  // N each
  Eigen::VectorXd G;                     // D²g diagonal (n_z)
};

// Scratch of one thread of the residual/Jacobian evaluation: H^δ at (z^n, ρ^{n+1}).
struct PontryaginStepScratch {
  HamiltonianEval eval;
  Eigen::VectorXd zn, rho_next;
};

// Workspace of the residual/Jacobian evaluation (preallocated, reused across Newton steps).
struct PontryaginWorkspace {
  int threads = 0;  // OpenMP threads over time steps; 0: omp_get_max_threads() (1 when N < 64)
  std::vector<PontryaginStepScratch> scratch;  // one per thread
  Eigen::VectorXd dg;                          // ρ^N = Dg(z^N)
  PontryaginJacobian jacobian;
};

// F(y) (same block layout as y). Returns ‖F‖_∞, or +inf if a non-finite value appears (two
// connected nodes met, overflow); never throws for such numerical failures. The time steps are
// evaluated in parallel (ws.threads); each writes only its own blocks, so F and the Jacobian are
// bit-identical for every thread count.
double EvaluateResidual(const PontryaginDiscretization& disc, const Eigen::VectorXd& y,
                        PontryaginWorkspace& ws, Eigen::VectorXd& residual);

// F(y) and the Jacobian blocks (ws.jacobian).
double EvaluateResidualAndJacobian(const PontryaginDiscretization& disc, const Eigen::VectorXd& y,
                                   PontryaginWorkspace& ws, Eigen::VectorXd& residual);

// Assembles the Jacobian held in ws.jacobian as a sparse matrix (for Eigen SparseLU and tests).
Eigen::SparseMatrix<double> AssembleSparseJacobian(const PontryaginDiscretization& disc,
                                                   const PontryaginJacobian& jacobian);

// The discrete value ū of (31) at y.
double DiscreteValue(const PontryaginDiscretization& disc, const Eigen::VectorXd& y,
                     PontryaginWorkspace& ws);

// Effective rest lengths L^γ(z^n, ρ^{n+1}) for n = 0 … N−1 (num_springs × N).
Eigen::MatrixXd EffectiveControls(const PontryaginDiscretization& disc, const Eigen::VectorXd& y);

// The largest number of steps N a solve accepts (the key discretization.steps of the tool).
inline constexpr std::int64_t kMaxSteps = 100000000;

// Checked before a solve on `steps` steps allocates: throws InputError "N steps need about …,
// more than the … available (…)" (moreau::CheckMemory) when its memory — per step the Jacobian
// blocks and Riccati factors (about eight nz × nz matrices, nz = network.state_size()), the
// unknowns, residual, Newton direction, trial point and the controls — cannot be allocated, and
// "N must be between 1 and kMaxSteps" outside that range.
void CheckSolveMemory(const SpringNetwork& network, std::int64_t steps);

}  // namespace moreau::control
