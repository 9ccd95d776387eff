// The two test problems of paper 000, section 4, as models with everything a run needs.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>

#include "moreau/pbd/constraints.h"
#include "moreau/pbd/drift.h"
#include "moreau/particles/model.h"
#include "moreau/pbd/particle_constraints.h"

namespace moreau::pbd {

// Sliding case (section 4.2): x' ∈ −e_2 − N(S, x), x(0) = sin α e_1 + cos α e_2 in R^d, d ≥ 3.
//
// The paper prints S_j = B_R(·) (balls) and a '+' on the last centre. Its explicit solution only
// solves the inclusion for the EXTERIORS S_j = {x : ‖x − c_j‖ ≥ R}, R = √(1 + C²), with centres
// c_j = C e_{j+2} (j = 1 … d−2) and c_{d−1} = −C (d−2)^{−1/2} Σ_{j≥3} e_j: on the plane x_3 = … =
// x_d = 0 each distance is √(x_1² + x_2² + C²), so S there is the exterior of the unit disk, and
// the centres sum to zero with weights (1, …, 1, √(d−2)), so the normal cone of S on the unit
// circle contains the inward radial direction. The particle slides along the unit circle in that
// groove until t* = −c_1, then moves straight down: x_1 = 1, x_2 = −(t − t*) (the paper's
// "x_2 = C_1 − t" has the sign of C_1 flipped). docs/pbd.md has the derivation.
struct SlidingCase {
  int dimension = 3;      // d ≥ 3
  double C = 10.0;        // distance of the ball centres from the plane, C > 0
  double alpha = 0.19634954084936207;  // initial angle from e_2, in (0, π); π/16 by default
  double T = 4.0;         // final time

  void Validate() const;  // throws InputError naming the field
  double radius() const;  // R = √(1 + C²)
  double c1() const;      // c_1 = ½ ln((1 − cos α)/(1 + cos α))
  double sliding_end_time() const;  // t* = max(0, −c_1)

  std::unique_ptr<ConstraintSetList> MakeConstraints() const;
  std::unique_ptr<Drift> MakeDrift() const;
  Vector InitialState() const;
  Vector ExactSolution(double t) const;
  Vector ExactVelocity(double t) const;
};

// Disks case (section 4.3): N disks of radius R in the plane, x' ∈ −γ x − N(S, x), S the
// non-overlap set, optionally above a horizontal wall y ≥ wall + R.
struct DisksCase {
  // The most disks: the random start and its feasibility check test all N²/2 pairs (the
  // particle core's Engine has cell lists for more).
  static constexpr int kMaxCount = 20000;

  int count = 40;  // N, 1 … kMaxCount
  double radius = 0.1;
  double gamma = 1.0;
  double T = 4.0;
  std::uint64_t seed = 1;
  std::optional<double> wall;  // the line y = wall; disk centres stay at y ≥ wall + R
  // Half-width L of the square [−L, L]² of the random initial state; 0 picks L = R √(π N),
  // a packing fraction of 1/4.
  double box = 0.0;

  void Validate() const;
  double box_half_width() const;
  particles::ParticleModel MakeModel() const;  // the particle core's model (k = 2)
  std::unique_ptr<Drift> MakeDrift() const;
  // Random sequential addition of non-overlapping disks, reproducible from the seed on every
  // platform (SplitMix64). Throws InputError when the disks do not fit.
  Vector InitialState() const;
};

}  // namespace moreau::pbd
