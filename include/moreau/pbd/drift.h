// The drift f : R^d → R^d of x' ∈ f(x) − N(S, x) (Lipschitz, as the convergence proof assumes).
#pragma once

#include <Eigen/Core>
#include <functional>

#include "moreau/pbd/constraint_set.h"

namespace moreau::pbd {

class Drift {
 public:
  virtual ~Drift() = default;
  // f(x) into out; x and out have size d.
  virtual void Evaluate(ConstVectorRef x, VectorRef out) const = 0;
  // The Jacobian Df(x) (d × d) into *jacobian when the drift provides one; false otherwise.
  virtual bool Jacobian(ConstVectorRef /*x*/, Eigen::MatrixXd* /*jacobian*/) const { return false; }
};

// f(x) = c.
class ConstantDrift final : public Drift {
 public:
  explicit ConstantDrift(Vector c) : c_(std::move(c)) {}
  void Evaluate(ConstVectorRef x, VectorRef out) const override;
  bool Jacobian(ConstVectorRef x, Eigen::MatrixXd* jacobian) const override;

 private:
  Vector c_;
};

// f(x) = −γ (x − x*), a harmonic trap around x* (x* = 0 when not given).
class HarmonicDrift final : public Drift {
 public:
  explicit HarmonicDrift(double gamma, Vector center = Vector()) : gamma_(gamma), center_(std::move(center)) {}
  void Evaluate(ConstVectorRef x, VectorRef out) const override;
  bool Jacobian(ConstVectorRef x, Eigen::MatrixXd* jacobian) const override;

 private:
  double gamma_;
  Vector center_;
};

// A user-supplied f, with an optional Jacobian.
class FunctionDrift final : public Drift {
 public:
  using Function = std::function<void(ConstVectorRef, VectorRef)>;
  using JacobianFunction = std::function<void(ConstVectorRef, Eigen::MatrixXd*)>;
  explicit FunctionDrift(Function f, JacobianFunction df = {}) : f_(std::move(f)), df_(std::move(df)) {}
  void Evaluate(ConstVectorRef x, VectorRef out) const override { f_(x, out); }
  bool Jacobian(ConstVectorRef x, Eigen::MatrixXd* jacobian) const override;

 private:
  Function f_;
  JacobianFunction df_;
};

}  // namespace moreau::pbd
