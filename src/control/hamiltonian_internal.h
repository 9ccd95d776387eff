// Pieces of the regularised Hamiltonian shared by its two implementations (internal header).
#pragma once

#include <Eigen/Core>

#include <type_traits>

#include "moreau/control/hamiltonian.h"

namespace moreau::control::internal {

// Resets `out` (sizes n, Hessian blocks only for kHessian) and adds the spring-free part of H^δ:
// the transport term λ·v and the running cost h, with their derivatives.
void AddTransportAndCost(const TrackingProblem& problem, const Instant& instant,
                         const Eigen::VectorXd& z, const Eigen::VectorXd& rho,
                         HamiltonianOrder order, HamiltonianEval& out);

// H^δ assembled in the order both implementations share: the spring-free part, then the springs
// by add_springs(std::integral_constant<int, d>{}) for the network's dimension d, then h = H −
// ρ·∂H/∂ρ.
template <typename AddSprings>
void AssembleRegularizedHamiltonian(const TrackingProblem& problem, const Instant& instant,
                                    const Eigen::VectorXd& z, const Eigen::VectorXd& rho,
                                    HamiltonianOrder order, HamiltonianEval& out,
                                    AddSprings&& add_springs) {
  AddTransportAndCost(problem, instant, z, rho, order, out);
  switch (problem.network().dimension()) {
    case 1:
      add_springs(std::integral_constant<int, 1>{});
      break;
    case 2:
      add_springs(std::integral_constant<int, 2>{});
      break;
    default:
      add_springs(std::integral_constant<int, 3>{});
      break;
  }
  out.running_cost = out.value - rho.dot(out.drho);
}

// The same as EvaluateRegularizedHamiltonian, with the spring terms differentiated by
// second-order forward-mode jets (jet.h): the original path, slower; kept for cross-checks.
void EvaluateRegularizedHamiltonianWithJets(const TrackingProblem& problem, const Instant& instant,
                                            const Eigen::VectorXd& z, const Eigen::VectorXd& rho,
                                            HamiltonianOrder order, HamiltonianEval& out);

}  // namespace moreau::control::internal
