#include "moreau/pbd/drift.h"

namespace moreau::pbd {

void ConstantDrift::Evaluate(ConstVectorRef /*x*/, VectorRef out) const { out = c_; }

bool ConstantDrift::Jacobian(ConstVectorRef x, Eigen::MatrixXd* jacobian) const {
  jacobian->setZero(x.size(), x.size());
  return true;
}

void HarmonicDrift::Evaluate(ConstVectorRef x, VectorRef out) const {
  if (center_.size() == 0) {
    out = -gamma_ * x;
  } else {
    out = -gamma_ * (x - center_);
  }
}

bool HarmonicDrift::Jacobian(ConstVectorRef x, Eigen::MatrixXd* jacobian) const {
  jacobian->setZero(x.size(), x.size());
  jacobian->diagonal().setConstant(-gamma_);
  return true;
}

bool FunctionDrift::Jacobian(ConstVectorRef x, Eigen::MatrixXd* jacobian) const {
  if (!df_) return false;
  df_(x, jacobian);
  return true;
}

}  // namespace moreau::pbd
