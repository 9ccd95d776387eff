// The Hamiltonian of the tracking problem and its regularisation (thesis (10), section 6.3).
//
//   H(z, ρ, t)   = min_{L ∈ Π[L−_s, L+_s]} ρ · f(z, L) + h(z, t)
//                = Σ_j λ_j·v_j + Σ_s [ S_s(P_s) − κ_s e_s·Δx_s − ξ_s (e_s·u_s)(u_s·Δv_s) ] + h,
//   P_s(z, ρ)    = κ_s e_s · u_s,   e_s = ζ_b/m_b − ζ_a/m_a  (a fixed node contributes 0),
//   S_s(P)       = min(P L−_s, P L+_s)            (bang-bang: L = L+ if P < 0, L− if P > 0),
//   S^γ_s(P)     = ((L− − L+)/2) γ ln cosh(P/γ) + ((L− + L+)/2) P    (regularised),
//   H^δ          = H with S replaced by S^γ;  |S_s − S^γ_s| <= ½ ln2 (L+_s − L−_s) γ, hence
//                  |H − H^δ| <= δ = ½ ln2 · n · (L_max − L_min) · γ (section 6.3).
//
// P_s is the coefficient of the rest length L_s in ρ · f; the thesis prints it with the factor
// (x_i − x_j), a sign misprint (see docs/control.md). ln cosh is evaluated as
// |y| + log1p(exp(−2|y|)) − ln 2, which never overflows.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "moreau/control/tracking_problem.h"

namespace moreau::control {

// Everything the Hamiltonian needs to know about one instant t: fixed-node states and the
// reference. Built once per time step (MakeInstant allocates; hot loops reuse instants).
struct Instant {
  double t = 0.0;
  Eigen::VectorXd fixed_position;  // d × num_nodes (entries of free nodes unused)
  Eigen::VectorXd fixed_velocity;  // d × num_nodes
  Eigen::VectorXd ref_position;    // d M
  Eigen::VectorXd ref_velocity;    // d M
  Eigen::VectorXd ref_weight;      // M
};

// Evaluates fixed-node states and the reference at time t.
Instant MakeInstant(const TrackingProblem& problem, double t);

// Value and first two derivatives of the regularised minimum S^γ(P) of one spring.
struct SmoothMin {
  double value = 0.0;      // S^γ(P)
  double slope = 0.0;      // dS^γ/dP = effective rest length, in [L−, L+]
  double curvature = 0.0;  // d²S^γ/dP² <= 0
};
SmoothMin RegularizedSpringMin(double p, double rest_min, double rest_max, double gamma);

// How much of the derivative information to compute.
enum class HamiltonianOrder { kValue, kGradient, kHessian };

// H^δ and its derivatives at (z, ρ) (both of size n = state_size()). Resized on first use;
// reuse one object to avoid allocation.
struct HamiltonianEval {
  double value = 0.0;         // H^δ(z, ρ, t)
  double running_cost = 0.0;  // h^δ = H^δ − ρ · H^δ_ρ, equation (30)
  Eigen::VectorXd dz;         // H^δ_z      (n)
  Eigen::VectorXd drho;       // H^δ_ρ      (n) = f(z, L^γ(z, ρ))
  Eigen::MatrixXd zz;         // H^δ_zz     (n × n), symmetric
  Eigen::MatrixXd rho_z;      // H^δ_ρz     (n × n), row: ρ index, column: z index
  Eigen::MatrixXd rho_rho;    // H^δ_ρρ     (n × n), symmetric, negative semidefinite
};

void EvaluateRegularizedHamiltonian(const TrackingProblem& problem, const Instant& instant,
                                    const Eigen::VectorXd& z, const Eigen::VectorXd& rho,
                                    HamiltonianOrder order, HamiltonianEval& out);

// The exact (non-smooth) Hamiltonian H(z, ρ, t). If `minimiser` is non-null it receives the
// bang-bang rest lengths (size num_springs) attaining the minimum.
double EvaluateHamiltonian(const TrackingProblem& problem, const Instant& instant,
                           const Eigen::VectorXd& z, const Eigen::VectorXd& rho,
                           Eigen::VectorXd* minimiser = nullptr);

// Switching functions P_s(z, ρ) (size num_springs).
void SwitchingFunctions(const TrackingProblem& problem, const Instant& instant,
                        const Eigen::VectorXd& z, const Eigen::VectorXd& rho, Eigen::VectorXd& p);

// Effective (relaxed) rest lengths L^γ_s = dS^γ_s/dP (P_s(z, ρ)) ∈ [L−_s, L+_s], the control
// realised by the regularised Hamiltonian: H^δ_ρ = f(z, L^γ).
void EffectiveRestLengths(const TrackingProblem& problem, const Instant& instant,
                          const Eigen::VectorXd& z, const Eigen::VectorXd& rho,
                          Eigen::VectorXd& rest_lengths);

// Running cost h(z, t) and terminal cost g(z) with its gradient Dg and (constant, diagonal)
// Hessian D²g (returned as the diagonal, size n). `terminal` is the instant at t = T.
double RunningCost(const TrackingProblem& problem, const Instant& instant,
                   const Eigen::VectorXd& z);
double TerminalCost(const TrackingProblem& problem, const Instant& terminal,
                    const Eigen::VectorXd& z, Eigen::VectorXd* gradient = nullptr,
                    Eigen::VectorXd* hessian_diagonal = nullptr);

}  // namespace moreau::control
