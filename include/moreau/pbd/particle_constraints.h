// Particles with volume exclusion: the model (radii, walls) and its constraint sweeps.
//
// The state is x = (X_0, …, X_{N−1}) ∈ R^{kN}, X_i ∈ R^k, k ∈ {1, 2, 3}. The sets are, in sweep
// order: every pair S_ij = {‖X_i − X_j‖ ≥ r_i + r_j} for i < j in lexicographic order, then for
// each particle i and each wall w the half-space {⟨n_w, X_i⟩ ≥ b_w + r_i}.
//
// With PairSearch::kVerletList only pairs closer than r_i + r_j + skin when the list was built
// are visited; the list is rebuilt when a particle has moved more than skin/4 since. Pairs left
// out are farther apart than contact, their projections are the identity, so the sweep gives the
// same bits as the all-pairs sweep, and the constraint evaluations still count all m sets.
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include "moreau/pbd/constraints.h"

namespace moreau::pbd {

// A flat wall: particle centres satisfy ⟨n, X⟩ ≥ offset + r_i (n is normalised on validation).
struct Wall {
  Vector normal;
  double offset = 0.0;
};

struct ParticleModel {
  int spatial_dimension = 2;      // k
  std::vector<double> radius;     // r_i > 0, one per particle
  std::vector<Wall> walls;

  int count() const { return static_cast<int>(radius.size()); }
  // Throws InputError naming the offending entry.
  void Validate() const;
};

enum class PairSearch { kAllPairs, kVerletList };

struct ParticleConstraintsOptions {
  PairSearch search = PairSearch::kVerletList;
  // Verlet skin as a multiple of the largest radius: candidate pairs are those with
  // ‖X_i − X_j‖ < r_i + r_j + skin_factor · max r.
  double skin_factor = 1.0;
};

struct NeighbourListStats {
  std::int64_t builds = 0;
  std::int64_t candidate_pairs = 0;  // at the last build
};

class ParticleConstraints final : public Constraints {
 public:
  ParticleConstraints(ParticleModel model, ParticleConstraintsOptions options = {});

  const ParticleModel& model() const { return model_; }
  const NeighbourListStats& neighbour_stats() const { return stats_; }

  int dimension() const override { return model_.spatial_dimension * model_.count(); }
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

  ParticleModel model_;
  ParticleConstraintsOptions options_;
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
  Vector reference_;                // positions at the last build
  bool built_ = false;
  NeighbourListStats stats_;
};

}  // namespace moreau::pbd
