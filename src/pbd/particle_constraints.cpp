#include "moreau/pbd/particle_constraints.h"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>

#include "moreau/common/error.h"

namespace moreau::pbd {

void ParticleModel::Validate() const {
  if (spatial_dimension < 1 || spatial_dimension > 3) {
    throw InputError(fmt::format("spatial dimension must be 1, 2 or 3 (got {})", spatial_dimension));
  }
  if (radius.empty()) throw InputError("a particle model needs at least one particle");
  for (std::size_t i = 0; i < radius.size(); ++i) {
    if (!(radius[i] > 0.0) || !std::isfinite(radius[i])) {
      throw InputError(fmt::format("radius of particle {} must be > 0 (got {})", i, radius[i]));
    }
  }
  for (std::size_t w = 0; w < walls.size(); ++w) {
    if (walls[w].normal.size() != spatial_dimension || !(walls[w].normal.norm() > 0.0)) {
      throw InputError(fmt::format("wall {} needs a non-zero normal of size {}", w, spatial_dimension));
    }
  }
}

ParticleConstraints::ParticleConstraints(ParticleModel model, ParticleConstraintsOptions options)
    : model_(std::move(model)), options_(options) {
  model_.Validate();
  for (Wall& w : model_.walls) {
    const double n = w.normal.norm();
    w.normal /= n;
    w.offset /= n;
  }
  if (!(options_.skin_factor > 0.0)) throw InputError("skin_factor must be > 0");
  skin_ = options_.skin_factor * *std::max_element(model_.radius.begin(), model_.radius.end());
  if (options_.search == PairSearch::kAllPairs) {
    const int n = model_.count();
    for (int i = 0; i < n; ++i) {
      for (int j = i + 1; j < n; ++j) {
        pairs_.emplace_back(i, j);
        contact_.push_back(model_.radius[static_cast<std::size_t>(i)] +
                           model_.radius[static_cast<std::size_t>(j)]);
      }
    }
    stats_.candidate_pairs = static_cast<std::int64_t>(pairs_.size());
  }
}

std::int64_t ParticleConstraints::num_sets() const {
  const std::int64_t n = model_.count();
  return n * (n - 1) / 2 + n * static_cast<std::int64_t>(model_.walls.size());
}

void ParticleConstraints::UpdatePairs(ConstVectorRef x) {
  if (options_.search == PairSearch::kAllPairs) return;
  const int k = model_.spatial_dimension;
  const int n = model_.count();
  if (built_) {
    // Rebuild when some particle moved more than skin/4: two particles then approach by less than
    // skin/2 before the check, leaving skin/2 for motion within one sweep.
    const double limit2 = 0.0625 * skin_ * skin_;
    bool stale = false;
    for (int i = 0; i < n && !stale; ++i) {
      stale = (x.segment(i * k, k) - reference_.segment(i * k, k)).squaredNorm() > limit2;
    }
    if (!stale) return;
  }
  pairs_.clear();
  contact_.clear();
  for (int i = 0; i < n; ++i) {
    for (int j = i + 1; j < n; ++j) {
      const double c = model_.radius[static_cast<std::size_t>(i)] +
                       model_.radius[static_cast<std::size_t>(j)];
      const double reach = c + skin_;
      if ((x.segment(i * k, k) - x.segment(j * k, k)).squaredNorm() < reach * reach) {
        pairs_.emplace_back(i, j);
        contact_.push_back(c);
      }
    }
  }
  reference_ = x;
  built_ = true;
  ++stats_.builds;
  stats_.candidate_pairs = static_cast<std::int64_t>(pairs_.size());
}

template <int K>
void ParticleConstraints::SweepImpl(double* x) const {
  const std::size_t np = pairs_.size();
  for (std::size_t p = 0; p < np; ++p) {
    double* xi = x + K * pairs_[p].first;
    double* xj = x + K * pairs_[p].second;
    double u[K];
    double r2 = 0.0;
    for (int c = 0; c < K; ++c) {
      u[c] = xi[c] - xj[c];
      r2 += u[c] * u[c];
    }
    const double contact = contact_[p];
    if (r2 >= contact * contact) continue;
    const double r = std::sqrt(r2);
    if (r > 0.0) {
      const double s = 0.5 * (contact - r) / r;
      for (int c = 0; c < K; ++c) {
        xi[c] += s * u[c];
        xj[c] -= s * u[c];
      }
    } else {
      xi[0] += 0.5 * contact;
      xj[0] -= 0.5 * contact;
    }
  }
  const int n = model_.count();
  for (int i = 0; i < n; ++i) {
    double* xi = x + K * i;
    for (const Wall& w : model_.walls) {
      double g = -w.offset - model_.radius[static_cast<std::size_t>(i)];
      for (int c = 0; c < K; ++c) g += w.normal[c] * xi[c];
      if (g < 0.0) {
        for (int c = 0; c < K; ++c) xi[c] -= g * w.normal[c];
      }
    }
  }
}

void ParticleConstraints::Sweep(VectorRef x) {
  UpdatePairs(x);
  switch (model_.spatial_dimension) {
    case 1: SweepImpl<1>(x.data()); break;
    case 2: SweepImpl<2>(x.data()); break;
    default: SweepImpl<3>(x.data()); break;
  }
}

void ParticleConstraints::Linearize(ConstVectorRef y, LinearizedConstraints* out) {
  UpdatePairs(y);
  out->Clear();
  const int k = model_.spatial_dimension;
  int index[6];
  double coeff[6];
  for (std::size_t p = 0; p < pairs_.size(); ++p) {
    const int i = pairs_[p].first;
    const int j = pairs_[p].second;
    Vector u = y.segment(i * k, k) - y.segment(j * k, k);
    const double r = u.norm();
    if (r > 0.0) {
      u /= r;
    } else {
      u.setZero();
      u[0] = 1.0;
    }
    // g = ‖X_i − X_j‖ − c; ∇g = (u, −u); b = ⟨∇g, y⟩ − g(y) = r − (r − c) = c.
    for (int c = 0; c < k; ++c) {
      index[c] = i * k + c;
      coeff[c] = u[c];
      index[k + c] = j * k + c;
      coeff[k + c] = -u[c];
    }
    out->AddRow(index, coeff, 2 * k, contact_[p]);
  }
  for (int i = 0; i < model_.count(); ++i) {
    for (const Wall& w : model_.walls) {
      for (int c = 0; c < k; ++c) {
        index[c] = i * k + c;
        coeff[c] = w.normal[c];
      }
      out->AddRow(index, coeff, k, w.offset + model_.radius[static_cast<std::size_t>(i)]);
    }
  }
}

void ParticleConstraints::AddPenaltyDirection(ConstVectorRef x, VectorRef out) {
  UpdatePairs(x);
  const int k = model_.spatial_dimension;
  for (std::size_t p = 0; p < pairs_.size(); ++p) {
    const int i = pairs_[p].first;
    const int j = pairs_[p].second;
    Vector u = x.segment(i * k, k) - x.segment(j * k, k);
    const double r = u.norm();
    if (r >= contact_[p]) continue;
    if (r > 0.0) {
      u /= r;
    } else {
      u.setZero();
      u[0] = 1.0;
    }
    const double half = 0.5 * (contact_[p] - r);
    out.segment(i * k, k) -= half * u;
    out.segment(j * k, k) += half * u;
  }
  for (int i = 0; i < model_.count(); ++i) {
    for (const Wall& w : model_.walls) {
      const double g = w.normal.dot(x.segment(i * k, k)) - w.offset -
                       model_.radius[static_cast<std::size_t>(i)];
      if (g < 0.0) out.segment(i * k, k) += g * w.normal;
    }
  }
}

double ParticleConstraints::MaxViolation(ConstVectorRef x) {
  UpdatePairs(x);
  const int k = model_.spatial_dimension;
  double worst = 0.0;
  for (std::size_t p = 0; p < pairs_.size(); ++p) {
    const double r = (x.segment(pairs_[p].first * k, k) - x.segment(pairs_[p].second * k, k)).norm();
    worst = std::max(worst, contact_[p] - r);
  }
  for (int i = 0; i < model_.count(); ++i) {
    for (const Wall& w : model_.walls) {
      const double g = w.normal.dot(x.segment(i * k, k)) - w.offset -
                       model_.radius[static_cast<std::size_t>(i)];
      worst = std::max(worst, -g);
    }
  }
  return worst;
}

double ParticleConstraints::MaxPairOverlapAllPairs(ConstVectorRef x) const {
  const int k = model_.spatial_dimension;
  const int n = model_.count();
  double worst = 0.0;
  for (int i = 0; i < n; ++i) {
    for (int j = i + 1; j < n; ++j) {
      const double c = model_.radius[static_cast<std::size_t>(i)] +
                       model_.radius[static_cast<std::size_t>(j)];
      worst = std::max(worst, c - (x.segment(i * k, k) - x.segment(j * k, k)).norm());
    }
  }
  return worst;
}

}  // namespace moreau::pbd
