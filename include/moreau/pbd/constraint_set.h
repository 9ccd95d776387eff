// Constraint sets S_j ⊂ R^d of the inclusion x' ∈ f(x) − N(S, x), S = S_1 ∩ … ∩ S_m.
//
// Each set is {x : g(x) ≥ 0} for a constraint function g that is a signed distance where one
// exists, and knows its orthogonal projection P_{S_j}. The built-in projections are exact; a
// user-defined set is projected by one Gauss–Newton step (paper 000, section 1), which is exact
// when g is itself a signed distance.
#pragma once

#include <Eigen/Core>
#include <functional>

namespace moreau::pbd {

using Vector = Eigen::VectorXd;
using VectorRef = Eigen::Ref<Eigen::VectorXd>;
using ConstVectorRef = Eigen::Ref<const Eigen::VectorXd>;

class ConstraintSet {
 public:
  virtual ~ConstraintSet() = default;

  // Dimension d of the ambient space R^d.
  virtual int dimension() const = 0;

  // The constraint function g (S = {g ≥ 0}); a signed distance for the built-in sets except the
  // pair set, whose g is the gap ‖X_i − X_j‖ − (r_i + r_j). x has size dimension().
  virtual double Value(ConstVectorRef x) const = 0;

  // ∇g(x) into grad (size dimension()). Where g is not differentiable (a centre), a fixed
  // element of the generalised gradient is returned so results stay deterministic.
  virtual void Gradient(ConstVectorRef x, VectorRef grad) const = 0;

  // x ← P_{S_j}(x), in place. Returns true when x moved (x was outside the set).
  virtual bool Project(VectorRef x) const = 0;

  // Euclidean distance d_{S_j}(x) = ‖x − P_{S_j}(x)‖ (0 inside).
  virtual double Distance(ConstVectorRef x) const;
};

// The centre c and radius R > 0 shared by the two ball sets below.
class BallSet : public ConstraintSet {
 public:
  BallSet(Vector center, double radius);  // Throws InputError if radius ≤ 0.
  int dimension() const override { return static_cast<int>(center_.size()); }

 protected:
  Vector center_;
  double radius_;
};

// {x : ‖x − c‖ ≤ R}.
class BallInterior final : public BallSet {
 public:
  using BallSet::BallSet;
  double Value(ConstVectorRef x) const override;
  void Gradient(ConstVectorRef x, VectorRef grad) const override;
  bool Project(VectorRef x) const override;
};

// {x : ‖x − c‖ ≥ R}. At x = c the projection picks c + R e_1.
class BallExterior final : public BallSet {
 public:
  using BallSet::BallSet;
  double Value(ConstVectorRef x) const override;
  void Gradient(ConstVectorRef x, VectorRef grad) const override;
  bool Project(VectorRef x) const override;
};

// {x : ⟨n, x⟩ ≥ b}; n is normalised on construction (throws InputError if n = 0).
class HalfSpace final : public ConstraintSet {
 public:
  HalfSpace(Vector normal, double offset);
  int dimension() const override { return static_cast<int>(normal_.size()); }
  double Value(ConstVectorRef x) const override;
  void Gradient(ConstVectorRef x, VectorRef grad) const override;
  bool Project(VectorRef x) const override;

 private:
  Vector normal_;
  double offset_;
};

// Non-overlap of particles i and j in a state x = (X_0, …, X_{N−1}), X_k ∈ R^k:
// {x : ‖X_i − X_j‖ ≥ r_i + r_j}. The orthogonal projection moves each particle by half of the
// overlap along the line of centres; coincident centres are separated along e_1.
class PairNonOverlap final : public ConstraintSet {
 public:
  PairNonOverlap(int dimension, int spatial_dimension, int i, int j, double contact_distance);
  int dimension() const override { return dimension_; }
  double Value(ConstVectorRef x) const override;
  void Gradient(ConstVectorRef x, VectorRef grad) const override;
  bool Project(VectorRef x) const override;
  double Distance(ConstVectorRef x) const override;

 private:
  int dimension_;
  int k_;
  int i_;
  int j_;
  double contact_;
};

// A user-defined set {x : g(x) ≥ 0} given g and ∇g; projected by one Gauss–Newton step
// x ← x − g(x) ∇g(x) / ‖∇g(x)‖² when g(x) < 0.
class FunctionSet final : public ConstraintSet {
 public:
  using Function = std::function<double(ConstVectorRef)>;
  using GradientFunction = std::function<void(ConstVectorRef, VectorRef)>;
  FunctionSet(int dimension, Function g, GradientFunction grad);
  int dimension() const override { return dimension_; }
  double Value(ConstVectorRef x) const override { return g_(x); }
  void Gradient(ConstVectorRef x, VectorRef grad) const override { grad_(x, grad); }
  bool Project(VectorRef x) const override;

 private:
  int dimension_;
  Function g_;
  GradientFunction grad_;
};

}  // namespace moreau::pbd
