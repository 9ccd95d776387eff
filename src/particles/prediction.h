// The engine's prediction Y_i = X_i + h u_i(X) + √(2 D h) ξ_i (forces.h): the drift from the
// trap, the constant force, the pair attraction (over the neighbour list) and self-propulsion
// (with a crowd's desired speeds and density factor), and the counter-based noise
// ξ_i(seed, id, step). Per slot; the noise and the desired speeds depend only on the ids.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <vector>

#include "moreau/particles/forces.h"
#include "moreau/particles/routing.h"
#include "particles/colouring.h"
#include "particles/neighbour_list.h"
#include "particles/noise.h"

namespace moreau::particles::internal {

// The drift's constants, taken from Forces once (k = dimension components).
struct DriftParameters {
  bool trap = false;
  double gamma = 0.0;
  double center[3] = {0, 0, 0};
  bool any_constant = false;
  double f0[3] = {0, 0, 0};
  bool propulsion = false;  // speed > 0
  double v0 = 0.0;
  double target[3] = {0, 0, 0};
  bool segment = false;  // the target is [target, target_end]
  double target_end[3] = {0, 0, 0};
  bool exit = false;  // past the target the direction is exit_direction (normalised)
  double exit_direction[3] = {0, 0, 0};
  bool fixed = false;  // one desired direction everywhere (normalised)
  double direction[3] = {0, 0, 0};
  std::shared_ptr<const DistanceField> route_owner;  // the exits' distance field (2D)
  const DistanceField* route = nullptr;              // route_owner.get()
  double speed_sd = 0.0;  // σ_v of the desired speeds; 0: v0 for all
  bool density = false;   // Weidmann's factor on the walking speed
  DensitySpeed density_law;
  bool collision_free = false;  // the collision-free speed model (forces.h)
  CollisionFreeSpeed walk;
  double attraction_stiffness = 0.0;
  double attraction_range = 0.0;        // > 0 when the attraction is on
  std::vector<double> class_stiffness;  // C × C (PairAttraction); empty: the one stiffness
  int classes = 0;                      // C
  double sigma = 0.0;                   // √(2 D h); 0 without noise

  DriftParameters(const Forces& forces, int k, double h);
};

struct StepContext;         // step_context.h
class CollisionFreeWalls;  // collision_free.cpp

// The desired direction e0 (unit, or zero when already at the target) of a particle at xw
// (wrapped) into e: −∇d of the distance field to the exits; the fixed direction; past the
// target along the exit direction; else toward the target point or the nearest point of the
// target segment. Inlined: a call in the prediction
// loop would keep its running maximum in memory.
template <int K>
[[gnu::always_inline]] inline void DesiredDirection(const DriftParameters& d, const double* xw,
                                                    double* e) {
  if constexpr (K == 2) {
    if (d.route != nullptr) {
      d.route->Direction(xw, e);
      return;
    }
  }
  if (d.fixed) {
    for (int a = 0; a < K; ++a) e[a] = d.direction[a];
    return;
  }
  double beyond = 0.0;
  if (d.exit) {
    for (int a = 0; a < K; ++a) beyond += (xw[a] - d.target[a]) * d.exit_direction[a];
  }
  if (beyond > 0.0) {
    for (int a = 0; a < K; ++a) e[a] = d.exit_direction[a];
    return;
  }
  double target[K];
  if (d.segment) {
    double e2 = 0.0, dot = 0.0;
    for (int a = 0; a < K; ++a) {
      e2 += (d.target_end[a] - d.target[a]) * (d.target_end[a] - d.target[a]);
      dot += (xw[a] - d.target[a]) * (d.target_end[a] - d.target[a]);
    }
    const double t = e2 > 0.0 ? std::clamp(dot / e2, 0.0, 1.0) : 0.0;
    for (int a = 0; a < K; ++a) target[a] = d.target[a] + t * (d.target_end[a] - d.target[a]);
  } else {
    for (int a = 0; a < K; ++a) target[a] = d.target[a];
  }
  double dx[K];
  double dist2 = 0.0;
  for (int a = 0; a < K; ++a) {
    dx[a] = target[a] - xw[a];
    dist2 += dx[a] * dx[a];
  }
  const double dist = std::sqrt(dist2);
  for (int a = 0; a < K; ++a) e[a] = dist > 1e-12 ? dx[a] / dist : 0.0;
}

// What a prediction reports besides the positions.
struct PredictionOutcome {
  double max_move = 0.0;        // the largest ‖Y_i − X_i‖ over finite rows
  std::int64_t bad_id = -1;     // the smallest id with a non-finite Y_i, or −1
  double max_coordinate = 0.0;  // the largest |Y_i,a| over finite rows
};

class Prediction {
 public:
  // n slots; uniform_mobility: every μ_i = 1 (the mobility loads are skipped). Throws
  // InputError for a density-dependent speed in a dimension other than 2.
  Prediction(const Forces& forces, const PeriodicBox& box, int n, double h, std::uint64_t seed,
             bool uniform_mobility);

  bool attracts() const { return parameters_.attraction_range > 0.0; }
  bool measures_density() const { return parameters_.density; }
  bool walks_collision_free() const { return parameters_.collision_free; }
  // Each slot's velocity V_i(s_i) e_i of the collision-free speed model (forces.h) at the store's
  // current positions: the repulsions over the list's pairs closer than R (the blocks in the
  // colouring's dependency order in parallel, or lexicographic on one thread), the walls', the
  // directions, then the headways (a minimum, so no order matters), in one team
  // (collision_free.cpp).
  void CollisionFreeWalk(const StepContext& context);
  // Each slot's Weidmann factor φ(ρ_i) at the store's current positions, ρ_i counted over the
  // list's pairs closer than R (forces.h DensitySpeed): by colour in parallel, or
  // (lexicographic) on one thread. Integer counts, so the factors do not depend on the thread
  // count.
  void LocalDensity(const StepContext& context);
  // The attraction at the store's current positions over the list's pairs into the force
  // buffer: by colour in parallel, or (lexicographic) on one thread in row order.
  void Attraction(const StepContext& context);
  // The store's predicted positions from its current ones for the step from t_step to
  // t_{step+1}, per slot with its id (or noise key), mobility and active velocity; the noise is
  // drawn in batches of kNoiseBatch slots (noise.h). bound (optional): also
  // max_i ‖Y_i − reference_i‖² and the count of slots beyond √quarter2 (the neighbour list's
  // exact skin bound, NeighbourList::ExactBound) in the same pass.
  PredictionOutcome Predict(StepContext& context, std::int64_t step,
                            ExactBound* bound = nullptr) const;
  // The force buffer follows a reordering of the slots (new slot s holds old slot perm[s]).
  void Reorder(const std::vector<int>& perm, int threads);

 private:
  // Matrix: the stiffness of slots (s, t) is K[C cls[id[s]] + cls[id[t]]] (cls: the model's
  // adhesion classes in id order), else `uniform`.
  template <int K, bool P, bool Matrix>
  void AttractionImpl(const double* x, const double* radius, const int* id, const int* cls,
                      double uniform, const NeighbourList& list, const Colouring& colouring,
                      const CellList& cells, bool lexicographic, int threads);
  template <int K, bool P>
  void LocalDensityImpl(const double* x, const NeighbourList& list, const Colouring& colouring,
                        const CellList& cells, bool lexicographic, int threads);
  template <int K, bool P>
  void CollisionFreeWalkImpl(const StepContext& context);
  template <int K, bool P, bool Noise>
  void PredictImpl(const double* x, double* y, const int* id, const std::int64_t* key,
                   const double* active, const double* mobility, std::int64_t step, int threads,
                   double* max_move, std::int64_t* bad_id, double* max_coordinate,
                   ExactBound* bound) const;
  // The drift is at most the trap and active velocities (every μ_i = 1, no attraction,
  // propulsion or wrap): the same arithmetic as PredictImpl in a loop without branches
  // (prediction_plain.cpp); a batch with a non-finite row is looked at again row by row.
  bool Plain() const;
  void PredictPlainDispatch(const double* x, double* y, const int* id, const std::int64_t* key,
                            const double* active, std::int64_t step, int threads, double* max_move,
                            std::int64_t* bad_id, double* max_coordinate, ExactBound* bound) const;
  template <int K, bool Noise, bool Trap, bool Active, bool Bound>
  void PredictPlain(const double* x, double* y, const int* id, const std::int64_t* key,
                    const double* active, std::int64_t step, int threads, double* max_move,
                    std::int64_t* bad_id, double* max_coordinate, ExactBound* bound) const;

  DriftParameters parameters_;
  PeriodicBox box_;
  int n_ = 0;
  double h_ = 0.0;
  std::uint64_t seed_ = 0;
  bool uniform_mobility_ = true;
  std::vector<double> force_;         // k per slot, attraction only
  std::vector<int> neighbours_;       // per slot, #{j : ‖X_i − X_j‖ < R}; density only
  std::vector<double> speed_factor_;  // per slot, φ(ρ_i); density only
  std::vector<double> walk_;          // k per slot: V_i e_i, then the velocity; collision-free only
  std::vector<double> headway_;       // per slot, s_i; collision-free only
  // The walls and segments binned for the collision-free repulsion, built again when they change.
  std::shared_ptr<const CollisionFreeWalls> walls_;
  BlockProgress repulsion_progress_;  // the collision-free pair passes' block schedules
  BlockProgress headway_progress_;
  std::vector<double> scratch_;
};

// Reorders rows of `width` (1, 2 or 3) values: new row s is old row perm[s]; *scratch keeps its
// capacity.
// A prediction's totals into Predict's outputs: the largest move, the largest coordinate (if
// asked), the non-finite row's id (−1: none) and the exact skin bound (if asked).
void ReportPrediction(const PredictionTotals& totals, double* max_move, std::int64_t* bad_id,
                      double* max_coordinate, ExactBound* bound);

void GatherRows(const std::vector<int>& perm, int width, int threads, std::vector<double>* v,
                std::vector<double>* scratch);

}  // namespace moreau::particles::internal
