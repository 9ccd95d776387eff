// Particle systems with volume exclusion as a constraint set for the paper's steppers: a thin
// adapter over the particle core (moreau::particles: the model, its pair and wall projections and
// its neighbour search).
//
// The state is x = (X_0, …, X_{N−1}) ∈ R^{kN}, X_i ∈ R^k, k = model.dimension ∈ {1, 2, 3}. The sets
// are, in sweep order: every pair S_ij = {‖X_i − X_j‖ ≥ r_i + r_j} for i < j in lexicographic
// order, then for each particle i and each wall w the half-space {⟨n_w, X_i⟩ ≥ b_w + r_i} (walls
// normalised as the particle core does). Spheres, segments and periodic axes are the engine's
// (particles/engine.h); this adapter rejects them.
//
// Model and workspace: the model is shared and immutable (one per study); a ParticleConstraints
// object is the per-run workspace (the neighbour list), so make one per simulation.
//
// With PairSearch::kVerletList only pairs closer than r_i + r_j + skin when the list was built
// are visited (found by the particle core's neighbour search, in lexicographic order); the list
// is rebuilt when a particle has moved more than skin/4 since. Pairs left out are farther apart than contact, their projections
// are the identity, so the sweep gives the same bits as the all-pairs sweep (kAllPairs, kept for
// cross-checks), and the constraint evaluations still count all m sets.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "moreau/particles/model.h"
#include "moreau/pbd/constraints.h"

namespace moreau::particles::internal {
struct UnitWall;
class LexicographicPairList;
}  // namespace moreau::particles::internal

namespace moreau::pbd {

enum class PairSearch { kAllPairs, kVerletList };

struct ParticleConstraintsOptions {
  PairSearch search = PairSearch::kVerletList;
  // Verlet skin as a multiple of the largest radius: candidate pairs are those with
  // ‖X_i − X_j‖ < r_i + r_j + skin_factor · max r. > 0.
  double skin_factor = 1.0;
};

struct NeighbourListStats {
  std::int64_t neighbour_list_builds = 0;
  std::int64_t candidate_pairs = 0;  // at the last build
};

class ParticleConstraints final : public Constraints {
 public:
  // Validates the model (InputError naming the field; also for spheres, segments or periodic
  // axes, which this adapter does not handle) and the options.
  explicit ParticleConstraints(std::shared_ptr<const particles::ParticleModel> model,
                               ParticleConstraintsOptions options = {});
  // The same with a model of its own.
  explicit ParticleConstraints(particles::ParticleModel model,
                               ParticleConstraintsOptions options = {});
  ~ParticleConstraints() override;

  const particles::ParticleModel& model() const { return *model_; }
  const NeighbourListStats& neighbour_stats() const { return stats_; }

  int state_size() const override { return model_->dimension * model_->count(); }
  std::int64_t num_sets() const override;
  void Sweep(VectorRef x) override;
  void Linearize(ConstVectorRef y, LinearizedConstraints* out) override;
  void AddPenaltyDirection(ConstVectorRef x, VectorRef out) override;
  double MaxViolation(ConstVectorRef x) override;

  // Largest pair overlap max(0, r_i + r_j − ‖X_i − X_j‖) over all pairs (brute force, O(N²)).
  double MaxPairOverlapAllPairs(ConstVectorRef x) const;

 private:
  void UpdatePairs(ConstVectorRef x);
  void AddCandidate(int i, int j, double contact);  // appends the pair to the candidate arrays
  template <int K>
  bool NeedsRebuild(const double* x) const;
  template <int K>
  void BuildPairs(const double* x);
  template <int K>
  void SweepImpl(double* x) const;
  template <int K>
  double MaxPairViolation(const double* x) const;

  std::shared_ptr<const particles::ParticleModel> model_;
  ParticleConstraintsOptions options_;
  std::vector<particles::internal::UnitWall> walls_;  // normalised by the particle core
  double skin_ = 0.0;
  bool uniform_contact_ = false;  // all radii equal: every pair has the same contact distance
  // Visited pairs in lexicographic order, stored by rows: the pairs (i, j) of particle i are
  // p = row_start_[i] … row_start_[i + 1] − 1 with j = neighbour_[p] (increasing j > i).
  std::vector<int> row_start_;
  std::vector<int> first_;        // i per visited pair
  std::vector<int> neighbour_;    // j per visited pair
  std::vector<double> contact_;   // r_i + r_j per visited pair
  std::vector<double> contact2_;  // contact_² (rounded), the sweep's no-overlap test
  std::vector<double> separated2_;  // the double above contact_²: r2 ≥ it ⇒ fl(√r2) ≥ contact_
  std::unique_ptr<particles::internal::LexicographicPairList> search_;  // kVerletList only
  Vector reference_;                // positions at the last build
  bool built_ = false;
  NeighbourListStats stats_;
};

}  // namespace moreau::pbd
