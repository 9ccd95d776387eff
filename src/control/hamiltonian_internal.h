// Pieces of the regularised Hamiltonian shared by its two implementations (internal header).
#pragma once

#include <Eigen/Core>

#include "moreau/control/hamiltonian.h"

namespace moreau::control::internal {

// Resets `out` (sizes n, Hessian blocks only for kHessian) and adds the spring-free part of H^δ:
// the transport term λ·v and the running cost h, with their derivatives.
void AddTransportAndCost(const TrackingProblem& problem, const Instant& instant,
                         const Eigen::VectorXd& z, const Eigen::VectorXd& rho,
                         HamiltonianOrder order, HamiltonianEval& out);

// The same as EvaluateRegularizedHamiltonian, with the spring terms differentiated by
// second-order forward-mode jets (jet.h): the original path, slower; kept for cross-checks.
void EvaluateRegularizedHamiltonianWithJets(const TrackingProblem& problem, const Instant& instant,
                                            const Eigen::VectorXd& z, const Eigen::VectorXd& rho,
                                            HamiltonianOrder order, HamiltonianEval& out);

}  // namespace moreau::control::internal
