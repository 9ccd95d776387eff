// A first Newton iterate from a guessed trajectory of the free nodes (docs/mocap.md, "The first
// iterate"): states from the guess, controls fitted to the guess' spring lengths, costates that the
// scheme's equations give for those states and controls, without a backward march that an
// unstable mode of the dynamics would blow up.
#pragma once

#include <Eigen/Core>

#include "moreau/control/pontryagin.h"

namespace moreau::control {

// `positions`: d M × (N+1), x^n of every free node at t_n (column 0 is replaced by z(0)'s).
// Returns y (PontryaginDiscretization::Pack) with, for the scheme of pontryagin.h,
//   z^n = (x^n, v^n), v^n = (x^{n+1} − x^n) / Δt (n = 1 … N−1; v^N = v^{N−1}): the position rows
//       of F^z vanish for n >= 1;
//   L^n_s = clamp(|Δx_s(z^n, t_n)|, L−_s, L+_s), the controls at rest on the guess;
//   ζ^{n+1} (n = 0 … N−2) the least-squares solution of P_s(z^n, ρ^{n+1}) = γ artanh(c), c =
//       (L^n_s − (L−_s + L+_s)/2) / ((L−_s − L+_s)/2) clipped to ±(1 − 10⁻³): the costate whose
//       regularised minimiser realises L^n (hamiltonian.h); ρ^N = Dg(z^N);
//   λ^n = λ^{n+1} + Δt H_x(z^n, ρ^{n+1}) (n = N−1 … 0): the λ rows of F^ρ, a plain sum because
//       H_x does not depend on λ; ζ^0 = ζ^1 + Δt H_v(z^0, ρ^1), the ζ row of F^ρ at n = 0.
// The residual left is in the velocity rows of F^z and the ζ rows of F^ρ (n >= 1), both of the
// order of how far the guess is from a trajectory of the network.
Eigen::VectorXd FittedControlStart(const PontryaginDiscretization& disc,
                                   const Eigen::MatrixXd& positions);

}  // namespace moreau::control
