// Theorem 5.1 of the thesis (seed 001, after Definition 6): a priori bounds on the error of the
// discrete value function ū (31) of the Symplectic Pontryagin scheme with N = T / Δt steps,
//
//   −(C1 C2 T / 2) ((e^{C2 T} − 1) Δt + Δt²) − (C1 C3 / 2) (e^{C2 T} − 1) Δt − T δ
//       ≤ u(x_s, 0) − ū(x_s, 0) ≤
//   ½ C1 C2 (C3 + 1) e^{C2 T} T Δt + T δ,
//
// where C1 bounds the Lipschitz constant of the Hamiltonian in λ, C2 its Lipschitz constant in
// x (per 1 + |λ|), C3 bounds |Dg|, and δ bounds ‖H − H^δ‖_∞. The constants come from the problem
// (section 9.1 works them out for the oscillator); the library does not estimate them.
#pragma once

#include <nlohmann/json.hpp>

namespace moreau::control {

struct ValueErrorConstants {
  double c1 = 0.0;     // C1 ≥ 0: |H(x, λ1) − H(x, λ2)| ≤ C1 |λ1 − λ2|
  double c2 = 0.0;     // C2 ≥ 0: |H(x, λ) − H(y, λ)| ≤ C2 (1 + |λ|) |x − y|
  double c3 = 0.0;     // C3 ≥ 0: |Dg| ≤ C3 (0 without a terminal cost)
  double delta = 0.0;  // δ ≥ 0: ‖H − H^δ‖_∞ ≤ δ
  // Throws InputError("study.theorem.<field>: must be a finite number ≥ 0 (got …)").
  void Validate() const;
  nlohmann::json ToJson() const;  // {"c1", "c2", "c3", "delta"}
};

// lower ≤ u − ū ≤ upper.
struct ValueErrorBounds {
  double lower = 0.0;
  double upper = 0.0;
};

// The bounds of Theorem 5.1 for horizon T > 0 and time step Δt > 0 (both in the problem's time
// unit). Validates the constants (throws InputError).
ValueErrorBounds Theorem51Bounds(const ValueErrorConstants& constants, double horizon, double dt);

}  // namespace moreau::control
