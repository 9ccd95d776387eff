#include "moreau/pbd/constraints.h"

#include <algorithm>
#include <fmt/format.h>
#include <numeric>

#include "moreau/common/error.h"

namespace moreau::pbd {

void LinearizedConstraints::Clear() {
  row_start_.assign(1, 0);
  index_.clear();
  coeff_.clear();
  rhs_.clear();
  inv_norm2_.clear();
}

void LinearizedConstraints::AddRow(const int* index, const double* coeff, int count, double b) {
  double n2 = 0.0;
  for (int k = 0; k < count; ++k) n2 += coeff[k] * coeff[k];
  if (!(n2 > 0.0)) return;
  index_.insert(index_.end(), index, index + count);
  coeff_.insert(coeff_.end(), coeff, coeff + count);
  row_start_.push_back(static_cast<std::int64_t>(index_.size()));
  rhs_.push_back(b);
  inv_norm2_.push_back(1.0 / n2);
}

void LinearizedConstraints::Sweep(VectorRef z) const {
  for (std::size_t r = 0; r < rhs_.size(); ++r) {
    const std::int64_t begin = row_start_[r];
    const std::int64_t end = row_start_[r + 1];
    double az = 0.0;
    for (std::int64_t k = begin; k < end; ++k) az += coeff_[k] * z[index_[k]];
    const double deficit = rhs_[r] - az;
    if (deficit <= 0.0) continue;
    const double step = deficit * inv_norm2_[r];
    for (std::int64_t k = begin; k < end; ++k) z[index_[k]] += step * coeff_[k];
  }
}

ConstraintSetList::ConstraintSetList(int state_size)
    : state_size_(state_size),
      scratch_(state_size),
      all_indices_(static_cast<std::size_t>(std::max(state_size, 0))) {
  if (state_size <= 0) {
    throw InputError(fmt::format("state size must be > 0 (got {})", state_size));
  }
  std::iota(all_indices_.begin(), all_indices_.end(), 0);
}

void ConstraintSetList::Add(std::unique_ptr<const ConstraintSet> set) {
  if (set->dimension() != state_size_) {
    throw InputError(fmt::format("constraint set of dimension {} added to a problem of state size {}",
                                 set->dimension(), state_size_));
  }
  sets_.push_back(std::move(set));
}

void ConstraintSetList::Sweep(VectorRef x) {
  for (const auto& set : sets_) set->Project(x);
}

void ConstraintSetList::Linearize(ConstVectorRef y, LinearizedConstraints* out) {
  out->Clear();
  for (const auto& set : sets_) {
    set->Gradient(y, scratch_);
    const double b = scratch_.dot(y) - set->Value(y);
    out->AddRow(all_indices_.data(), scratch_.data(), state_size_, b);
  }
}

void ConstraintSetList::AddPenaltyDirection(ConstVectorRef x, VectorRef out) {
  for (const auto& set : sets_) {
    scratch_ = x;
    if (set->Project(scratch_)) out += x - scratch_;
  }
}

double ConstraintSetList::MaxViolation(ConstVectorRef x) {
  double worst = 0.0;
  for (const auto& set : sets_) worst = std::max(worst, -set->Value(x));
  return worst;
}

}  // namespace moreau::pbd
