#include "moreau/pbd/particle_constraints.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fmt/format.h>
#include <limits>

#include "moreau/common/error.h"
#include "particles/neighbour_list.h"
#include "unit_vector.h"

namespace moreau::pbd {

namespace {

using particles::internal::SquaredNorm;

// Given cc = fl(c · c), a double t > c² (exact): cc is within half an ulp of c², so its successor
// lies above c². A squared distance r2 ≥ t has √r2 > c exactly, so fl(√r2) ≥ c.
double SeparatedSquare(double cc) {
  return std::nextafter(cc, std::numeric_limits<double>::infinity());
}

void CheckHandled(const particles::ParticleModel& model) {
  model.Validate();
  if (!model.spheres.empty() || !model.segments.empty()) {
    throw InputError(
        "spheres and segments: ParticleConstraints handles pairs and walls only (use the "
        "particle engine)");
  }
  for (int a = 0; a < 3; ++a) {
    if (model.periodic[static_cast<std::size_t>(a)]) {
      throw InputError(fmt::format(
          "periodic[{}]: ParticleConstraints has no periodic axes (use the particle engine)", a));
    }
  }
}

}  // namespace

void ParticleConstraints::AddCandidate(int i, int j, double contact) {
  first_.push_back(i);
  neighbour_.push_back(j);
  contact_.push_back(contact);
  contact2_.push_back(contact * contact);
  separated2_.push_back(SeparatedSquare(contact * contact));
}

ParticleConstraints::ParticleConstraints(particles::ParticleModel model,
                                         ParticleConstraintsOptions options)
    : ParticleConstraints(std::make_shared<const particles::ParticleModel>(std::move(model)),
                          options) {}

ParticleConstraints::ParticleConstraints(std::shared_ptr<const particles::ParticleModel> model,
                                         ParticleConstraintsOptions options)
    : model_(std::move(model)), options_(options) {
  if (!model_) throw InputError("model: ParticleConstraints needs a particle model");
  CheckHandled(*model_);
  if (!(options_.skin_factor > 0.0)) {
    throw InputError(fmt::format("skin_factor must be > 0 (got {})", options_.skin_factor));
  }
  walls_ = particles::internal::UnitWalls(*model_);
  const std::vector<double>& radius = model_->radius;
  skin_ = options_.skin_factor * model_->max_radius();
  uniform_contact_ =
      std::all_of(radius.begin(), radius.end(), [&](double r) { return r == radius.front(); });
  const int n = model_->count();
  row_start_.assign(static_cast<std::size_t>(n) + 1, 0);
  if (options_.search == PairSearch::kAllPairs) {
    for (int i = 0; i < n; ++i) {
      for (int j = i + 1; j < n; ++j) {
        AddCandidate(i, j, radius[static_cast<std::size_t>(i)] + radius[static_cast<std::size_t>(j)]);
      }
      row_start_[static_cast<std::size_t>(i) + 1] = static_cast<int>(neighbour_.size());
    }
    stats_.candidate_pairs = static_cast<std::int64_t>(neighbour_.size());
  } else {
    search_ = std::make_unique<particles::internal::LexicographicPairList>(
        particles::internal::PeriodicBox::Of(*model_), n, model_->max_radius(), skin_);
  }
}

std::int64_t ParticleConstraints::num_sets() const {
  const std::int64_t n = model_->count();
  return n * (n - 1) / 2 + n * static_cast<std::int64_t>(walls_.size());
}

ParticleConstraints::~ParticleConstraints() = default;

// Rebuild when some particle moved more than skin/4: two particles then approach by less than
// skin/2 before the check, leaving skin/2 for motion within one sweep. A NaN displacement does
// not count as a move. The check runs every sweep, so it is a branch-free pass; in the plane two
// particles are checked at once.
template <int K>
bool ParticleConstraints::NeedsRebuild(const double* x) const {
  const double limit2 = 0.0625 * skin_ * skin_;
  const double* ref = reference_.data();
  const int n = model_->count();
  double worst = 0.0;
  int i = 0;
#if defined(__GNUC__) && !defined(__clang__)  // GCC vector extensions
  if constexpr (K == 2) {
    using Double2 = double __attribute__((vector_size(16)));
    using Index2 = long long __attribute__((vector_size(16)));
    Double2 worst2 = {0.0, 0.0};
    for (; i + 1 < n; i += 2) {
      Double2 a;
      Double2 b;
      Double2 ra;
      Double2 rb;
      std::memcpy(&a, x + 2 * i, sizeof a);
      std::memcpy(&b, x + 2 * i + 2, sizeof b);
      std::memcpy(&ra, ref + 2 * i, sizeof ra);
      std::memcpy(&rb, ref + 2 * i + 2, sizeof rb);
      a -= ra;
      b -= rb;
      a *= a;
      b *= b;
      const Double2 d2 =
          __builtin_shuffle(a, b, Index2{0, 2}) + __builtin_shuffle(a, b, Index2{1, 3});
      worst2 = d2 > worst2 ? d2 : worst2;
    }
    worst = worst2[1] > worst2[0] ? worst2[1] : worst2[0];
  }
#endif
  for (; i < n; ++i) {
    double d[K];
    for (int c = 0; c < K; ++c) d[c] = x[K * i + c] - ref[K * i + c];
    const double d2 = SquaredNorm<K>(d);
    worst = d2 > worst ? d2 : worst;
  }
  return worst > limit2;
}


// The candidate pairs from the particle core's neighbour search (pairs closer than
// r_i + r_j + skin, in lexicographic order with each row sorted by j), so the list is the
// all-pairs list restricted to pairs within reach, in the same order.
template <int K>
void ParticleConstraints::BuildPairs(const double* x) {
  const int n = model_->count();
  const std::vector<double>& radius = model_->radius;
  first_.clear();
  neighbour_.clear();
  contact_.clear();
  contact2_.clear();
  separated2_.clear();
  search_->Build(x, radius.data());
  const particles::internal::NeighbourList& list = search_->list();
  const int* row_start = list.row_start();
  const int* nbr = list.neighbours();
  for (int i = 0; i < n; ++i) {
    const double ri = radius[static_cast<std::size_t>(i)];
    for (int p = row_start[i]; p < row_start[i + 1]; ++p) {
      AddCandidate(i, nbr[p], ri + radius[static_cast<std::size_t>(nbr[p])]);
    }
    row_start_[static_cast<std::size_t>(i) + 1] = static_cast<int>(neighbour_.size());
  }
  reference_ = Eigen::Map<const Vector>(x, K * n);
  built_ = true;
  ++stats_.neighbour_list_builds;
  stats_.candidate_pairs = static_cast<std::int64_t>(neighbour_.size());
}

void ParticleConstraints::UpdatePairs(ConstVectorRef x) {
  if (options_.search == PairSearch::kAllPairs) return;
  particles::internal::DispatchDimension(model_->dimension, [&](auto k) {
    if (!built_ || NeedsRebuild<k>(x.data())) BuildPairs<k>(x.data());
  });
}

// One sweep in the documented order. The pairs (i, ·) are consecutive and no other pair touches
// X_i between them, so X_i is kept in registers over its row: the same operations in the same
// order as visiting the pairs one by one, without a store and reload of X_i per pair.
template <int K>
void ParticleConstraints::SweepImpl(double* x) const {
  const int n = model_->count();
  const int* row_start = row_start_.data();
  const int* neighbour = neighbour_.data();
  const double* contact = contact_.data();
  const double* contact2 = contact2_.data();
  for (int i = 0; i < n; ++i) {
    int p = row_start[i];
    const int end = row_start[i + 1];
    if (p == end) continue;
    double* xi_mem = x + K * i;
    double xi[K];
    for (int c = 0; c < K; ++c) xi[c] = xi_mem[c];
    for (; p < end; ++p) {
      double* xj = x + K * neighbour[p];
      double u[K];
      for (int c = 0; c < K; ++c) u[c] = xi[c] - xj[c];
      const double r2 = SquaredNorm<K>(u);
      if (r2 >= contact2[p]) continue;
      particles::internal::ProjectOverlappingPair<K>(xi, xj, u, r2, contact[p]);
    }
    for (int c = 0; c < K; ++c) xi_mem[c] = xi[c];
  }
  if (walls_.empty()) return;
  const std::vector<double>& radius = model_->radius;
  for (int i = 0; i < n; ++i) {
    double* xi = x + K * i;
    for (const particles::internal::UnitWall& w : walls_) {
      particles::internal::ProjectWall<K>(xi, w.n, w.b + radius[static_cast<std::size_t>(i)]);
    }
  }
}

void ParticleConstraints::Sweep(VectorRef x) {
  UpdatePairs(x);
  particles::internal::DispatchDimension(model_->dimension,
                                         [&](auto k) { SweepImpl<k>(x.data()); });
}

void ParticleConstraints::Linearize(ConstVectorRef y, LinearizedConstraints* out) {
  UpdatePairs(y);
  out->Clear();
  const int k = model_->dimension;
  const int n = model_->count();
  int index[6];
  double coeff[6];
  for (int i = 0; i < n; ++i) {
    for (int p = row_start_[static_cast<std::size_t>(i)];
         p < row_start_[static_cast<std::size_t>(i) + 1]; ++p) {
      const int j = neighbour_[static_cast<std::size_t>(p)];
      Vector u = y.segment(i * k, k) - y.segment(j * k, k);
      internal::NormalizeOrFirstAxis(u);
      // g = ‖X_i − X_j‖ − c; ∇g = (u, −u); b = ⟨∇g, y⟩ − g(y) = r − (r − c) = c.
      for (int c = 0; c < k; ++c) {
        index[c] = i * k + c;
        coeff[c] = u[c];
        index[k + c] = j * k + c;
        coeff[k + c] = -u[c];
      }
      out->AddRow(index, coeff, 2 * k, contact_[static_cast<std::size_t>(p)]);
    }
  }
  for (int i = 0; i < n; ++i) {
    for (const particles::internal::UnitWall& w : walls_) {
      for (int c = 0; c < k; ++c) {
        index[c] = i * k + c;
        coeff[c] = w.n[c];
      }
      out->AddRow(index, coeff, k, w.b + model_->radius[static_cast<std::size_t>(i)]);
    }
  }
}

void ParticleConstraints::AddPenaltyDirection(ConstVectorRef x, VectorRef out) {
  UpdatePairs(x);
  const int k = model_->dimension;
  const int n = model_->count();
  for (int i = 0; i < n; ++i) {
    for (int p = row_start_[static_cast<std::size_t>(i)];
         p < row_start_[static_cast<std::size_t>(i) + 1]; ++p) {
      const int j = neighbour_[static_cast<std::size_t>(p)];
      const double contact = contact_[static_cast<std::size_t>(p)];
      Vector u = x.segment(i * k, k) - x.segment(j * k, k);
      const double r = u.norm();
      if (r >= contact) continue;
      if (r > 0.0) {
        u /= r;
      } else {
        u.setZero();
        u[0] = 1.0;
      }
      const double half = 0.5 * (contact - r);
      out.segment(i * k, k) -= half * u;
      out.segment(j * k, k) += half * u;
    }
  }
  for (int i = 0; i < n; ++i) {
    const double r = model_->radius[static_cast<std::size_t>(i)];
    for (const particles::internal::UnitWall& w : walls_) {
      const double g = particles::internal::WallGap(w, x.data() + i * k, k, r);
      if (g >= 0.0) continue;
      for (int c = 0; c < k; ++c) out[i * k + c] += g * w.n[c];
    }
  }
}

// max over the visited pairs of r_i + r_j − ‖X_i − X_j‖, floored at 0, the same value as
// evaluating every pair in turn (a NaN distance is skipped, as std::max(worst, NaN) does):
// - a pair with r2 ≥ separated2_ has a rounded distance ≥ its contact distance and cannot raise
//   the maximum, so its square root is skipped;
// - with equal radii every pair has the same contact distance c, and c − fl(√r2) is monotone in
//   r2, so the maximum is c − fl(√min r2): one square root per call.
template <int K>
double ParticleConstraints::MaxPairViolation(const double* x) const {
  const int n = model_->count();
  const int* row_start = row_start_.data();
  const int* neighbour = neighbour_.data();
  const double* contact = contact_.data();
  const double* separated2 = separated2_.data();
  if (uniform_contact_) {
    // The minimum is exact and does not depend on the order, so in the plane two pairs are
    // taken at once.
    const int np = static_cast<int>(neighbour_.size());
    const int* first = first_.data();
    double min_r2 = std::numeric_limits<double>::infinity();
    int p = 0;
#if defined(__GNUC__) && !defined(__clang__)  // GCC vector extensions
    if constexpr (K == 2) {
      using Double2 = double __attribute__((vector_size(16)));
      using Index2 = long long __attribute__((vector_size(16)));
      Double2 min2 = {min_r2, min_r2};
      for (; p + 1 < np; p += 2) {
        Double2 a;
        Double2 b;
        Double2 aj;
        Double2 bj;
        std::memcpy(&a, x + 2 * first[p], sizeof a);
        std::memcpy(&aj, x + 2 * neighbour[p], sizeof aj);
        std::memcpy(&b, x + 2 * first[p + 1], sizeof b);
        std::memcpy(&bj, x + 2 * neighbour[p + 1], sizeof bj);
        a -= aj;
        b -= bj;
        a *= a;
        b *= b;
        const Double2 r2 =
            __builtin_shuffle(a, b, Index2{0, 2}) + __builtin_shuffle(a, b, Index2{1, 3});
        min2 = r2 < min2 ? r2 : min2;
      }
      min_r2 = min2[1] < min2[0] ? min2[1] : min2[0];
    }
#endif
    for (; p < np; ++p) {
      const double* xi = x + K * first[p];
      const double* xj = x + K * neighbour[p];
      double u[K];
      for (int c = 0; c < K; ++c) u[c] = xi[c] - xj[c];
      const double r2 = SquaredNorm<K>(u);
      min_r2 = r2 < min_r2 ? r2 : min_r2;
    }
    if (np == 0 || !(min_r2 < separated2[0])) return 0.0;
    return std::max(0.0, contact[0] - std::sqrt(min_r2));
  }
  double worst = 0.0;
  for (int i = 0; i < n; ++i) {
    const double* xi = x + K * i;
    for (int p = row_start[i]; p < row_start[i + 1]; ++p) {
      const double* xj = x + K * neighbour[p];
      double u[K];
      for (int c = 0; c < K; ++c) u[c] = xi[c] - xj[c];
      const double r2 = SquaredNorm<K>(u);
      if (r2 >= separated2[p]) continue;
      worst = std::max(worst, contact[p] - std::sqrt(r2));
    }
  }
  return worst;
}

double ParticleConstraints::MaxViolation(ConstVectorRef x) {
  UpdatePairs(x);
  const int k = model_->dimension;
  const double worst = particles::internal::DispatchDimension(
      k, [&](auto kk) { return MaxPairViolation<kk>(x.data()); });
  if (walls_.empty()) return worst;
  double wall_worst = worst;
  for (int i = 0; i < model_->count(); ++i) {
    const double r = model_->radius[static_cast<std::size_t>(i)];
    for (const particles::internal::UnitWall& w : walls_) {
      wall_worst = std::max(wall_worst, -particles::internal::WallGap(w, x.data() + i * k, k, r));
    }
  }
  return wall_worst;
}

double ParticleConstraints::MaxPairOverlapAllPairs(ConstVectorRef x) const {
  const int k = model_->dimension;
  const int n = model_->count();
  const std::vector<double>& radius = model_->radius;
  double worst = 0.0;
  for (int i = 0; i < n; ++i) {
    for (int j = i + 1; j < n; ++j) {
      const double c = radius[static_cast<std::size_t>(i)] + radius[static_cast<std::size_t>(j)];
      worst = std::max(worst, c - (x.segment(i * k, k) - x.segment(j * k, k)).norm());
    }
  }
  return worst;
}

}  // namespace moreau::pbd
