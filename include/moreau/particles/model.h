// The particle model at scale: what the problem is (immutable once validated).
//
// N particles in R^k, k ∈ {1, 2, 3} (the engine runs k ∈ {2, 3}), with per-particle radius r_i > 0
// and mobility μ_i > 0, subject to (the sets S_j of x' ∈ f(x) − N(S, x), all with exact orthogonal
// projections):
//   - pair non-overlap        ‖X_i − X_j‖ ≥ r_i + r_j (minimum image on periodic axes);
//   - walls (half-spaces)     ⟨n, X_i⟩ ≥ offset + r_i;
//   - sphere obstacles        ‖X_i − c‖ ≥ R + r_i (disks in 2D, spheres in 3D);
//   - segment obstacles (2D)  dist(X_i, [a, b]) ≥ r_i (the particle stays off a line segment);
//   - periodic axes           X_i is identified with X_i + L e_a on a periodic axis a, L = hi − lo;
//                             positions reported are wrapped into [lo, hi).
// Lengths are in the scenario's length unit; nothing here assumes a unit.
// Walls and obstacles are not replicated across periodic boundaries: in a periodic domain keep
// them farther than r_max + skin from the boundary planes of the periodic axes (the engine keeps
// positions unwrapped by at most the skin between neighbour-list builds).
//
// Positions are flat arrays in particle-id order: X_i occupies entries k·i … k·i + k − 1.
// Vectors with three components (normal, centre, domain) use only the first k.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

namespace moreau::particles {

using Vec3 = std::array<double, 3>;

// Half-space {⟨normal, X⟩ ≥ offset + r_i} for particle centres. The normal need not be unit
// length: Validate() rejects a zero normal, the engine normalises (normal, offset) together.
struct Wall {
  Vec3 normal{0.0, 1.0, 0.0};
  double offset = 0.0;
};

// A disk (2D) or sphere (3D) the particles stay out of: ‖X_i − center‖ ≥ radius + r_i.
struct SphereObstacle {
  Vec3 center{0.0, 0.0, 0.0};
  double radius = 0.0;  // > 0
};

// A line segment [a, b] in 2D (dimension 2 only): dist(X_i, [a, b]) ≥ r_i. a ≠ b.
// Rooms with doors are built from segments.
struct SegmentObstacle {
  std::array<double, 2> a{0.0, 0.0};
  std::array<double, 2> b{1.0, 0.0};
};

struct ParticleModel {
  int dimension = 2;             // k ∈ {1, 2, 3}; the engine needs 2 or 3
  std::vector<double> radius;    // r_i > 0, one per particle (the particle count N = radius.size())
  std::vector<double> mobility;  // μ_i > 0, one per particle; empty means μ_i = 1 for all
  // Stable ids of a changing population (population.h), one per particle, each in [0, 2^62):
  // they key the noise ξ(seed, stable id, step) in place of the index i, so a particle keeps its
  // noise stream when others are added or removed. Empty: the index i (a fixed population).
  std::vector<std::int64_t> stable_ids;
  // The adhesion class c_i ≥ 0 of each particle: it picks the pair attraction's stiffness
  // k_{c_i c_j} from forces.h PairAttraction::class_stiffness (a population's agent type). Empty:
  // class 0 for all.
  std::vector<int> adhesion_class;
  std::vector<Wall> walls;
  std::vector<SphereObstacle> spheres;
  std::vector<SegmentObstacle> segments;  // dimension 2 only
  // Periodic axes: periodic[a] makes axis a periodic with domain [domain_lo[a], domain_hi[a]).
  // domain_lo/hi are ignored on non-periodic axes.
  std::array<bool, 3> periodic{false, false, false};
  Vec3 domain_lo{0.0, 0.0, 0.0};
  Vec3 domain_hi{1.0, 1.0, 1.0};

  int count() const { return static_cast<int>(radius.size()); }
  double mobility_of(int i) const {
    return mobility.empty() ? 1.0 : mobility[static_cast<std::size_t>(i)];
  }
  double max_radius() const;

  // Adds the walls of the box [lo, hi] on every axis that is not (yet) periodic (particle
  // centres then stay in [lo + r_i, hi − r_i] there). Order: for each such axis a, the wall at
  // lo[a], then hi[a].
  void AddBoxWalls(const Vec3& lo, const Vec3& hi);

  // Throws InputError naming the offending field and value:
  //   "dimension must be 1, 2 or 3 (got 4)", "a particle model needs at least one particle",
  //   "radius of particle 12 must be > 0 (got -1)", "mobility of particle 3 must be > 0 (got 0)",
  //   "mobility has 5 entries for 6 particles", "stable_ids has 5 entries for 6 particles",
  //   "stable id of particle 2 must be in [0, 2^62) (got -1)",
  //   "adhesion_class has 5 entries for 6 particles",
  //   "adhesion class of particle 4 must be ≥ 0 (got -1)", "walls[2].normal must be non-zero",
  //   "spheres[1].radius must be > 0", "segments[0] needs a ≠ b",
  //   "segments need dimension 2 (segments[0] given in 3D)",
  //   "domain of periodic axis 1 needs lo < hi (got [0, 0))",
  //   "radius of particle 7 (0.6) is too large for periodic axis 0 of length 2: need 4 r < L"
  //   (the minimum image of a pair in contact must be unique).
  void Validate() const;
};

// The feasibility check of initial positions (CheckInitialState) is in initial_state.h.

}  // namespace moreau::particles
