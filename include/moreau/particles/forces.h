// The drift of the particle engine (overdamped: velocity = mobility × force) and its noise.
//
// The drift velocity of particle i at positions X is
//   u_i(X) = μ_i (F_trap + F_const + F_attr,i) + v_prop,i
// with
//   F_trap   = −γ (X_i − c)                       harmonic trap (the paper's disks: c = 0);
//   F_const  = f                                  a constant force (gravity, a drift);
//   F_attr,i = Σ_j k g_ij (1 − g_ij / ℓ) e_ij     short-range pair attraction between surfaces,
//              over pairs with gap g_ij = ‖X_i − X_j‖ − (r_i + r_j) in (0, ℓ), e_ij the unit vector
//              from X_i to X_j (minimum image). The force rises linearly (stiffness k) from
//              contact, peaks at g = ℓ/2 and is continuous, zero at and beyond ℓ.
//   v_prop,i = v0 (T_i − X_i) / ‖T_i − X_i‖      self-propulsion at the desired speed v0 toward a
//              target T_i: a point, or the nearest point of a target segment (a door); zero when
//              ‖T_i − X_i‖ ≤ 1e−12 (already there). A velocity, not scaled by μ_i. With an exit
//              direction e, a particle with ⟨X_i − target, e⟩ > 0 gets v0 e/‖e‖ instead.
// On periodic axes the trap and the target use the wrapped position.
//
// Brownian noise (Euler–Maruyama): after the drift, X_i += √(2 D h) ξ_i with ξ_i ~ N(0, I_k)
// drawn from a counter-based generator keyed by (seed, particle id, step): Philox4x32-10
// (Salmon et al., SC'11) with key = seed and counter = (id low, block + 4 · (id high), step low,
// step high) (id low/high: its 32-bit halves; ids below 2^32 have id high = 0), where
// step k = 0, 1, … is the step from t_k to t_{k+1} and block 0 gives ξ_0, ξ_1, block 1 gives ξ_2:
// its four 32-bit words make two uniforms in (0, 1), then two normals by Box–Muller. The noise of
// a particle depends only on (seed, id, step), never on threads, storage order or other particles.
#pragma once

#include <array>
#include <cstdint>
#include <optional>

#include "moreau/particles/model.h"

namespace moreau::particles {

struct HarmonicTrap {
  double gamma = 1.0;  // γ ≥ 0, in 1/(time · mobility)
  Vec3 center{0.0, 0.0, 0.0};
};

struct SelfPropulsion {
  double speed = 1.0;  // v0 ≥ 0, length/time
  Vec3 target{0.0, 0.0, 0.0};
  // When set, the target is the segment [target, *target_end] and each particle heads for its
  // nearest point on it (a door).
  std::optional<Vec3> target_end;
  // When set (non-zero), a particle past the target, ⟨X_i − target, e⟩ > 0, walks at v0 along
  // e instead (a pedestrian who went through the door keeps walking away from the room).
  std::optional<Vec3> exit_direction;
};

struct PairAttraction {
  double stiffness = 0.0;  // k ≥ 0 (force per length)
  double range = 0.0;      // ℓ > 0 when stiffness > 0 (length); widens the neighbour lists by ℓ
};

struct Forces {
  std::optional<HarmonicTrap> trap;
  Vec3 constant_force{0.0, 0.0, 0.0};  // f
  std::optional<SelfPropulsion> propulsion;
  std::optional<PairAttraction> attraction;
  double diffusion = 0.0;  // D ≥ 0 (length²/time), the same for every particle; 0: no noise

  // Throws InputError naming the field ("forces.diffusion must be ≥ 0 (got -1)", …).
  void Validate() const;
};

// ξ ∈ R^k (k = 2 or 3 entries written to out) for (seed, id, step): the normals the engine adds.
void GaussianNoise(std::uint64_t seed, std::int64_t id, std::int64_t step, int k, double* out);

}  // namespace moreau::particles
