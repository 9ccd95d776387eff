// The two examples of the thesis, as problem builders (section 9; docs/control.md explains the
// choices the thesis leaves open). Every parameter is a field, settable from a scenario file.
#pragma once

#include <array>

#include "moreau/control/tracking_problem.h"

namespace moreau::control {

// Example 5.1 / 9.1: one free mass on a spring–damper to a wall at x = 0, d = 1.
// Reference: x_r(t) = x0 + p Δ σ(min(t / T_m, 1)), σ(τ) = τ − sin(2πτ) / (2π), so the reference
// velocity v_r = p Δ (1 − cos(2π t/T_m)) / T_m is a smooth bump that starts and ends at rest; the
// reference stays at x0 + pΔ for t >= T_m. Δ = target − start.
struct OscillatorExample {
  double mass = 100.0;           // m
  double stiffness = 10.0;       // κ
  double damping = 20.0;         // ξ
  double rest_min = 0.5;         // L−
  double rest_max = 1.515;       // L+
  double gamma = 1e-4;           // γ (δ = ½ ln2 (L+ − L−) γ = 3.51772e−5)
  double horizon = 2.0;          // T
  double start = 1.0;            // x(0) (at rest)
  double target = 1.01;          // final reference position
  double move_time = 1.5;        // T_m: the reference moves during [0, T_m], then stands still
  double position_weight = 1.0;  // μ_x
  double velocity_weight = 1.0;  // μ_v
};
TrackingProblem MakeOscillatorProblem(const OscillatorExample& example, double path_fraction);

// The arm model of section 9.2 / preSymbolic.m / computeRef2DVer1.m (d = 2). Nodes (0-based):
// 0 = thesis node 1 (upper hand marker), 1 = node 2 (lower hand marker), 2 = node 3 (upper elbow
// marker), 3 = node 4 (lower elbow marker), 4 = node 5 fixed at (0, 0), 5 = node 6 fixed at (0, 1).
// Springs (thesis numbering) 3–1, 4–1, 2–1, 4–2, 5–3, 6–3, 4–3, 6–4.
// Reference (computeRef2DVer1): shoulder A = anchor; elbow B = A + L1 (cos θ1, sin θ1);
// wrist C = B + L2 (cos θ2, sin θ2); elbow markers B ± l1 (cos(θ1 + φ1 ± π/2), …) and hand
// markers C ± l2 (cos(θ2 + φ2 ± π/2), …); each angle α(t) = p α_max (1 − cos(2π k t / T)) / 2
// (getSineVelocity: from 0 to α_max at T/2 and back, k periods). Velocities are the exact time
// derivatives. Rest-length bounds: (1 ± spring_limit) × the spring length in the full (p = 1)
// reference at t = bounds_time.
struct ArmExample {
  double mass = 3.0;                          // mass of the four free nodes
  double stiffness = 20.0;                    // κ of every spring
  double damping = 40.0;                      // ξ of every spring
  double spring_limit = 0.5;                  // SpringLimit of preSymbolic.m
  double horizon = 30.0;                      // T
  double gamma = 1e-4;                        // γ
  double position_weight = 100.0;             // mu1 of preSymbolic.m
  double velocity_weight = 0.0;               // no velocity term in preSymbolic.m
  double upper_bone = 3.0;                    // L1 = |A B|
  double lower_bone = 3.0;                    // L2 = |B C|
  double elbow_half_width = 0.5;              // l1: markers 3, 4 at distance l1 from B
  double hand_half_width = 0.5;               // l2: markers 1, 2 at distance l2 from C
  std::array<double, 2> anchor = {0.0, 0.5};  // A (mid-point of the fixed nodes)
  double angle_ab_deg = 15.0;                 // θ1 max (bone A–B)
  double angle_bc_deg = 45.0;  // θ2 max (bone B–C, absolute angle as in computeRef2DVer1)
  double angle_34_deg = 15.0;  // φ1 max (elbow bar 3–4, relative to A–B)
  double angle_12_deg = 20.0;  // φ2 max (hand bar 1–2, relative to B–C)
  double periods = 1.0;        // k
  double bounds_time = 15.0;   // time of the reference configuration for the bounds (T/2)
};
TrackingProblem MakeArmProblem(const ArmExample& example, double path_fraction);

// Reference positions (4 free nodes × 2) and velocities of the arm at time t for fraction p.
void ArmReference(const ArmExample& example, double path_fraction, double t, double* positions,
                  double* velocities);

// An example whose reference cannot be followed within the bounds (docs/control_bang_bang.md):
// one free mass on a spring–damper to a wall at x = 0, d = 1, with a reference oscillating
// faster than the natural frequency √(κ/m) and wider than the rest-length range, so the optimal
// rest length saturates at L− or L+ except near switching points (bang-bang as γ → 0).
// Reference: x_r(t) = centre + amplitude sin(2π t / period), v_r its derivative; x(0) = centre,
// at rest. The 1D and arm examples above are tracked by interior controls; this one is not.
struct SaturatingExample {
  double mass = 1.0;             // m
  double stiffness = 4.0;        // κ (natural frequency 2 rad/s)
  double damping = 0.5;          // ξ
  double rest_min = 0.8;         // L−
  double rest_max = 1.2;         // L+
  double centre = 1.0;           // centre of the reference and x(0)
  double amplitude = 0.3;        // reference amplitude (> (L+ − L−) / 2: unreachable)
  double period = 1.0;           // reference period (2π rad/s, above the natural frequency)
  double horizon = 2.0;          // T
  double gamma = 1e-3;           // γ
  double position_weight = 1.0;  // μ_x
  double velocity_weight = 0.0;  // μ_v
};
// path_fraction scales the reference amplitude (continuation).
TrackingProblem MakeSaturatingProblem(const SaturatingExample& example, double path_fraction);

}  // namespace moreau::control
