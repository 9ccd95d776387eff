// The feasible set S = S_1 ∩ … ∩ S_m as the time steppers see it: whole sweeps of projections in
// a fixed order, linearisations for PGS, penalty directions, violations.
//
// Two implementations: ConstraintSetList (any ConstraintSet objects; the general path) and
// ParticleConstraints (particle_constraints.h; particle systems through the particle core).
// A Constraints object may keep per-run workspace (a neighbour list), so its methods are not const
// and one object serves one simulation at a time.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "moreau/pbd/constraint_set.h"

namespace moreau::pbd {

// Half-spaces {z : ⟨a_j, z⟩ ≥ b_j} with sparse normals a_j, the linearisation of each S_j at a
// point y: g_j(y) + ⟨∇g_j(y), z − y⟩ ≥ 0.
class LinearizedConstraints {
 public:
  void Clear();
  // Adds the row ⟨a, z⟩ ≥ b with a given by (index[k], coeff[k]); rows with a = 0 are skipped.
  void AddRow(const int* index, const double* coeff, int count, double b);
  std::int64_t rows() const { return static_cast<std::int64_t>(rhs_.size()); }
  // One sweep of orthogonal projections onto the half-spaces, in row order.
  void Sweep(VectorRef z) const;

 private:
  std::vector<std::int64_t> row_start_{0};
  std::vector<int> index_;
  std::vector<double> coeff_;
  std::vector<double> rhs_;
  std::vector<double> inv_norm2_;
};

class Constraints {
 public:
  virtual ~Constraints() = default;

  // Size d of the state x ∈ R^d (k·N for N particles in R^k).
  virtual int state_size() const = 0;
  // Number m of sets S_j; a sweep counts as m constraint evaluations.
  virtual std::int64_t num_sets() const = 0;

  // x ← P_{S_m} ∘ … ∘ P_{S_1}(x): one sweep in the fixed order of the sets.
  virtual void Sweep(VectorRef x) = 0;

  // The half-spaces linearising every S_j at y (for PGS), into *out (cleared first).
  virtual void Linearize(ConstVectorRef y, LinearizedConstraints* out) = 0;

  // out += Σ_j (x − P_{S_j}(x)) = Σ_j d_{S_j}(x) ∇d_{S_j}(x), the penalty direction.
  virtual void AddPenaltyDirection(ConstVectorRef x, VectorRef out) = 0;

  // max_j max(0, −g_j(x)): the largest violation in the units of the constraint functions
  // (penetration depth for balls and walls, overlap length for particle pairs).
  virtual double MaxViolation(ConstVectorRef x) = 0;
};

// S given as a list of ConstraintSet objects, visited in list order.
class ConstraintSetList final : public Constraints {
 public:
  explicit ConstraintSetList(int state_size);
  // Throws InputError if the set's dimension differs.
  void Add(std::unique_ptr<const ConstraintSet> set);
  const ConstraintSet& set(std::int64_t j) const { return *sets_[static_cast<std::size_t>(j)]; }

  int state_size() const override { return state_size_; }
  std::int64_t num_sets() const override { return static_cast<std::int64_t>(sets_.size()); }
  void Sweep(VectorRef x) override;
  void Linearize(ConstVectorRef y, LinearizedConstraints* out) override;
  void AddPenaltyDirection(ConstVectorRef x, VectorRef out) override;
  double MaxViolation(ConstVectorRef x) override;

 private:
  int state_size_;
  std::vector<std::unique_ptr<const ConstraintSet>> sets_;
  Vector scratch_;
  std::vector<int> all_indices_;
};

}  // namespace moreau::pbd
