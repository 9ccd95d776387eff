#include "moreau/pbd/constraint_set.h"

#include <cmath>
#include <fmt/format.h>

#include "moreau/common/error.h"
#include "unit_vector.h"

namespace moreau::pbd {

double ConstraintSet::Distance(ConstVectorRef x) const {
  Vector p = x;
  Project(p);
  return (p - x).norm();
}

BallSet::BallSet(Vector center, double radius) : center_(std::move(center)), radius_(radius) {
  if (!(radius > 0.0)) throw InputError(fmt::format("ball radius must be > 0 (got {})", radius));
}

double BallInterior::Value(ConstVectorRef x) const { return radius_ - (x - center_).norm(); }

void BallInterior::Gradient(ConstVectorRef x, VectorRef grad) const {
  const double r = (x - center_).norm();
  if (r > 0.0) {
    grad = -(x - center_) / r;
  } else {
    grad.setZero();
  }
}

bool BallInterior::Project(VectorRef x) const {
  const double r = (x - center_).norm();
  if (r <= radius_) return false;
  x = center_ + (radius_ / r) * (x - center_);
  return true;
}

double BallExterior::Value(ConstVectorRef x) const { return (x - center_).norm() - radius_; }

void BallExterior::Gradient(ConstVectorRef x, VectorRef grad) const {
  const double r = (x - center_).norm();
  if (r > 0.0) {
    grad = (x - center_) / r;
  } else {
    grad.setZero();
    grad[0] = 1.0;
  }
}

bool BallExterior::Project(VectorRef x) const {
  const double r = (x - center_).norm();
  if (r >= radius_) return false;
  if (r > 0.0) {
    x = center_ + (radius_ / r) * (x - center_);
  } else {
    x = center_;
    x[0] += radius_;
  }
  return true;
}

HalfSpace::HalfSpace(Vector normal, double offset) : normal_(std::move(normal)), offset_(offset) {
  const double n = normal_.norm();
  if (!(n > 0.0) || !std::isfinite(n)) throw InputError("half-space normal must be non-zero");
  normal_ /= n;
  offset_ /= n;
}

double HalfSpace::Value(ConstVectorRef x) const { return normal_.dot(x) - offset_; }

void HalfSpace::Gradient(ConstVectorRef /*x*/, VectorRef grad) const { grad = normal_; }

bool HalfSpace::Project(VectorRef x) const {
  const double g = normal_.dot(x) - offset_;
  if (g >= 0.0) return false;
  x -= g * normal_;
  return true;
}

PairNonOverlap::PairNonOverlap(int dimension, int spatial_dimension, int i, int j,
                               double contact_distance)
    : dimension_(dimension), k_(spatial_dimension), i_(i), j_(j), contact_(contact_distance) {
  if (i == j || i < 0 || j < 0 || (std::max(i, j) + 1) * k_ > dimension_) {
    throw InputError(fmt::format("pair ({}, {}) is not a pair of distinct particles", i, j));
  }
  if (!(contact_distance > 0.0)) {
    throw InputError(fmt::format("contact distance must be > 0 (got {})", contact_distance));
  }
}

double PairNonOverlap::Value(ConstVectorRef x) const {
  return (x.segment(i_ * k_, k_) - x.segment(j_ * k_, k_)).norm() - contact_;
}

void PairNonOverlap::Gradient(ConstVectorRef x, VectorRef grad) const {
  grad.setZero();
  Vector u = x.segment(i_ * k_, k_) - x.segment(j_ * k_, k_);
  internal::NormalizeOrFirstAxis(u);
  grad.segment(i_ * k_, k_) = u;
  grad.segment(j_ * k_, k_) = -u;
}

bool PairNonOverlap::Project(VectorRef x) const {
  Vector u = x.segment(i_ * k_, k_) - x.segment(j_ * k_, k_);
  const double r = u.norm();
  if (r >= contact_) return false;
  if (r > 0.0) {
    u /= r;
  } else {
    u.setZero();
    u[0] = 1.0;
  }
  const double half = 0.5 * (contact_ - r);
  x.segment(i_ * k_, k_) += half * u;
  x.segment(j_ * k_, k_) -= half * u;
  return true;
}

double PairNonOverlap::Distance(ConstVectorRef x) const {
  const double gap = Value(x);
  return gap >= 0.0 ? 0.0 : -gap / std::sqrt(2.0);
}

FunctionSet::FunctionSet(int dimension, Function g, GradientFunction grad)
    : dimension_(dimension), g_(std::move(g)), grad_(std::move(grad)) {
  if (dimension <= 0) throw InputError("function set dimension must be > 0");
  if (!g_ || !grad_) throw InputError("function set needs g and its gradient");
}

bool FunctionSet::Project(VectorRef x) const {
  const double g = g_(x);
  if (g >= 0.0) return false;
  Vector grad(dimension_);
  grad_(x, grad);
  const double n2 = grad.squaredNorm();
  if (!(n2 > 0.0)) return false;  // No descent direction: leave x as it is.
  x -= (g / n2) * grad;
  return true;
}

}  // namespace moreau::pbd
