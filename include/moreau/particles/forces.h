// The drift of the particle engine (overdamped: velocity = mobility × force) and its noise.
//
// The drift velocity of particle i at positions X is
//   u_i(X) = μ_i (F_trap + F_const + F_attr,i) + v_prop,i
// with
//   F_trap   = −γ (X_i − c)                       harmonic trap (the paper's disks: c = 0);
//   F_const  = f                                  a constant force (gravity, a drift);
//   F_attr,i = Σ_j k_ij g_ij (1 − g_ij / ℓ) e_ij  short-range pair attraction between surfaces,
//              over pairs with gap g_ij = ‖X_i − X_j‖ − (r_i + r_j) in (0, ℓ), e_ij the unit vector
//              from X_i to X_j (minimum image). The force rises linearly (stiffness k_ij) from
//              contact, peaks at g = ℓ/2 and is continuous, zero at and beyond ℓ. k_ij = k for
//              every pair, or, with a class matrix (PairAttraction::class_stiffness), the entry
//              K[c_i, c_j] for the particles' adhesion classes c_i, c_j (model.h; a population's
//              agent types: differential adhesion). The work to pull a pair apart from contact is
//              ∫_0^ℓ k_ij g (1 − g/ℓ) dg = k_ij ℓ² / 6.
//   v_prop,i = v0 (T_i − X_i) / ‖T_i − X_i‖      self-propulsion at the desired speed v0 toward a
//              target T_i: a point, or the nearest point of a target segment (a door); zero when
//              ‖T_i − X_i‖ ≤ 1e−12 (already there). A velocity, not scaled by μ_i. With an exit
//              direction e, a particle with ⟨X_i − target, e⟩ > 0 gets v0 e/‖e‖ instead.
//              A pedestrian crowd (docs/abm.md) replaces v0 by the person's own walking speed
//                v_i = v0,i · φ(ρ_i)
//              with v0,i the desired speed of person i (WalkingSpeeds::speed_sd: a truncated
//              normal drawn from (seed, id)) and φ the density factor of Weidmann's fundamental
//              diagram at the local density ρ_i (DensitySpeed); v0 and 1 when not set.
// On periodic axes the trap and the target use the wrapped position.
//
// Brownian noise (Euler–Maruyama): after the drift, X_i += √(2 D h) ξ_i with ξ_i ~ N(0, I_k)
// drawn from a counter-based generator keyed by (seed, particle id, step): Philox4x32-10
// (Salmon et al., SC'11) with key = seed and counter = (id low, block + 4 · (id high), step low,
// step high) (id low/high: its 32-bit halves; ids below 2^32 have id high = 0), where
// step k = 0, 1, … is the step from t_k to t_{k+1} and block 0 gives ξ_0, ξ_1, block 1 gives ξ_2:
// its first three 32-bit words make two normals by BoxMullerNormals (common/random.h: a uniform of
// 52 bits for the radius, 32 bits for the angle, a few ulp from the exact transform; the fourth
// word is unused). The noise of a particle depends only on (seed, id, step), never on threads,
// storage order, batch or other particles.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "moreau/common/field_list.h"
#include "moreau/particles/model.h"

namespace moreau::particles {

class DistanceField;  // routing.h

struct HarmonicTrap {
  double gamma = 1.0;  // γ ≥ 0, in 1/(time · mobility)
  Vec3 center{0.0, 0.0, 0.0};
};

// Weidmann's fundamental diagram (Weidmann 1993, the speed–density relation of pedestrians):
// the walking speed falls with the local density ρ as
//   φ(ρ) = 1 − exp(−γ (1/ρ − 1/ρ_max))   for 0 < ρ < ρ_max,   φ = 0 for ρ ≥ ρ_max,
// v_i = v0,i φ(ρ_i). Weidmann's fit: γ = 1.913 persons/m², ρ_max = 5.4 persons/m² (with a free
// speed of 1.34 m/s). The local density of person i is the count of people (i included) whose
// centres lie within the measuring radius R of X_i, over the circle's area:
//   ρ_i = (1 + #{j ≠ i : ‖X_i − X_j‖ < R}) / (π R²)
// (2D only; lengths in metres when γ and ρ_max are Weidmann's). Walls are not discounted: near a
// wall or in a doorway the circle reaches outside the room and ρ_i is lower than the crowd's.
struct DensitySpeed {
  double gamma = 1.913;      // γ > 0, persons/length²
  double max_density = 5.4;  // ρ_max > 0, persons/length²
  double radius = 1.0;       // R > 0, the measuring circle (length); widens the neighbour lists
};

struct SelfPropulsion {
  double speed = 1.0;  // v0 ≥ 0, length/time: the mean desired speed
  Vec3 target{0.0, 0.0, 0.0};
  // When set, the target is the segment [target, *target_end] and each particle heads for its
  // nearest point on it (a door).
  std::optional<Vec3> target_end;
  // When set (non-zero), a particle past the target, ⟨X_i − target, e⟩ > 0, walks at v0 along
  // e instead (a pedestrian who went through the door keeps walking away from the room).
  std::optional<Vec3> exit_direction;
  // When set (non-zero), every particle's desired direction is direction / ‖direction‖ wherever
  // it is, and target, target_end and exit_direction are not used (a corridor, a ring).
  std::optional<Vec3> direction;
  // When set (dimension 2), the desired direction is the distance field's −∇d toward the
  // nearest exit (routing.h DistanceField::Direction), and target, target_end, exit_direction
  // and direction are not used. Shared, never changed after construction.
  std::shared_ptr<const DistanceField> route;
};

// The collision-free speed model of Tordeux, Chraibi & Seyfried (2016, "Collision-free speed
// model for pedestrian dynamics", Traffic and Granular Flow '15, 225–232; arXiv:1512.05597),
// dimension 2. Person i walks at
//   ẋ_i = V_i(s_i) e_i,   V_i(s) = min(v0,i, max(0, (s − ℓ) / T)),
// with v0,i the desired speed (WalkingSpeeds::speed_sd) and
//   e_i = ê(e0,i + Σ_j a exp((ℓ − d_ij) / D) n_ij + Σ_w a_w exp((ℓ/2 − d_iw) / D_w) n_iw),
// ê(u) = u / ‖u‖ (e_i = 0 when u = 0), e0,i the desired direction of SelfPropulsion, d_ij =
// ‖x_i − x_j‖ (minimum image), n_ij = (x_i − x_j) / d_ij, d_iw the distance from x_i to wall or
// segment w and n_iw the unit vector from its nearest point to x_i. The headway s_i is the
// distance to the nearest neighbour in the walking direction and within the body's path:
//   s_i = min { d_ij : ⟨e_i, x_j − x_i⟩ > 0, |⟨e_i^⊥, x_j − x_i⟩| < ℓ },   +∞ if there is none.
// Only neighbours with d_ij < R count, R = ℓ + max(T max_i v0,i, 10 D) (CollisionFreeRange):
// V_i(s) = v0,i for s ≥ R, and a repulsion weight at R is at most a e^{−10}. In single file at
// density ρ (equal spacing 1/ρ) every person walks at V(1/ρ) (docs/crowds.md). The model
// itself keeps people at least ℓ apart along their path; the engine's projection still enforces
// ‖x_i − x_j‖ ≥ r_i + r_j (the radii are the model's, not ℓ).
struct CollisionFreeSpeed {
  double time_gap = 1.0;         // T > 0 (time)
  double length = 0.3;           // ℓ > 0 (length): the body diameter
  double repulsion = 5.0;        // a ≥ 0: the neighbours' repulsion strength
  double repulsion_range = 0.1;  // D > 0 (length)
  // The wall term is not in the paper; a_w and D_w are those of its authors' codes, jpscore's
  // model "Tordeux2015" and JuPedSim's CollisionFreeSpeedModel (≥ 1.0), which both use 5, 0.02 m.
  double wall_repulsion = 5.0;         // a_w ≥ 0: the walls' and segments' repulsion strength
  double wall_repulsion_range = 0.02;  // D_w > 0 (length)

  // time_gap, length, repulsion, repulsion_range, wall_repulsion, wall_repulsion_range.
  static const FieldList<CollisionFreeSpeed>& Fields();
  // Throws InputError(key, reason): ("time_gap", "must be > 0 (got 0)").
  void Validate() const;
};

// A pedestrian crowd's walking speeds: they scale SelfPropulsion's v0 per person.
struct WalkingSpeeds {
  // σ_v ≥ 0: the desired speed of particle i is v0,i = v0 + σ_v z_i, z_i a standard normal
  // truncated to [−3, 3] (rejection), drawn from (seed, id) (DesiredSpeed); 0: v0,i = v0 for
  // all. Needs 3 σ_v ≤ v0 (no negative speeds). Helbing & Molnár (1995) use v0 = 1.34 m/s,
  // σ_v = 0.26 m/s.
  double speed_sd = 0.0;
  // When set, the speed falls with the local density (Weidmann's fundamental diagram).
  std::optional<DensitySpeed> density;
  // When set, the speed and the direction are those of the collision-free speed model (needs
  // dimension 2; does not go with density).
  std::optional<CollisionFreeSpeed> collision_free;
};

struct PairAttraction {
  double stiffness = 0.0;  // k ≥ 0 (force per length)
  double range = 0.0;  // ℓ > 0 when any stiffness is > 0 (length); widens the neighbour lists by ℓ
  // K: C × C stiffnesses (force per length) between adhesion classes, row-major, symmetric,
  // entries ≥ 0 and finite; a pair of classes (a, b) attracts with K[a C + b] in place of k.
  // Every particle's class (ParticleModel::adhesion_class) must be < C. Empty: k for every
  // pair. A matrix whose entries all equal k gives the same bits as k alone.
  std::vector<double> class_stiffness;

  // C, the number of classes of class_stiffness (0 when empty).
  int classes() const;
  // Whether any pair attracts: k > 0, or some entry of K > 0.
  bool attracts() const;
};

struct Forces {
  std::optional<HarmonicTrap> trap;
  Vec3 constant_force{0.0, 0.0, 0.0};  // f
  std::optional<SelfPropulsion> propulsion;
  WalkingSpeeds walking;  // per-person speeds of the propulsion (a crowd); default: v0 for all
  std::optional<PairAttraction> attraction;
  double diffusion = 0.0;  // D ≥ 0 (length²/time), the same for every particle; 0: no noise

  // Throws InputError naming the field ("forces.diffusion must be ≥ 0 (got -1)",
  // "forces.attraction.class_stiffness[0][1] (0.5) must equal [1][0] (0.2): the matrix must be
  // symmetric", …).
  void Validate() const;
};

// Throws InputError when a particle's adhesion class is outside the class matrix of `forces`
// ("adhesion class of particle 7 is 2, but forces.attraction.class_stiffness has 2 classes");
// nothing without a matrix.
void CheckAdhesionClasses(const ParticleModel& model, const Forces& forces);

// ξ ∈ R^k (k = 2 or 3 entries written to out) for (seed, id, step): the normals the engine adds.
void GaussianNoise(std::uint64_t seed, std::int64_t id, std::int64_t step, int k, double* out);

// The desired speed v0,i = mean + sd · z of particle id, z ~ N(0, 1) truncated to [−3, 3]: the
// first of the normals GaussianNoise(seed ⊕ c, id, m, 2) for m = 0, 1, … (two per m, in order)
// with |z| ≤ 3, c a constant that separates this stream from the Brownian noise. A pure function
// of (seed, id); mean when sd = 0. The truncated normal has mean `mean` and standard deviation
// sd · √(1 − 6 φ(3) / (2 Φ(3) − 1)) ≈ 0.9865 sd (φ, Φ: the standard normal density and
// distribution function).
double DesiredSpeed(std::uint64_t seed, std::int64_t id, double mean, double sd);

// Weidmann's factor φ(ρ) = 1 − exp(−γ (1/ρ − 1/ρ_max)) for 0 < ρ < ρ_max, 0 for ρ ≥ ρ_max
// (DensitySpeed); 1 for ρ ≤ 0.
double WeidmannSpeedFactor(const DensitySpeed& law, double density);

// V(s) = min(v0, max(0, (s − ℓ) / T)) of the collision-free speed model at headway s.
double CollisionFreeSpeedAt(const CollisionFreeSpeed& model, double v0, double headway);

// R = ℓ + max(T v_max, 10 D): the distance within which neighbours count in the collision-free
// speed model, v_max the largest desired speed.
double CollisionFreeRange(const CollisionFreeSpeed& model, double max_speed);

// How far the engine's neighbour lists reach beyond contact (r_i + r_j) for these forces: the
// attraction range ℓ, R − 2 r_min for the density circle and for the collision-free speed
// model's range (every pair closer than R is then a candidate pair); the largest, ≥ 0.
// min_radius: the smallest particle radius.
double PairListWidening(const Forces& forces, double min_radius);

}  // namespace moreau::particles
