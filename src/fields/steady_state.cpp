// SolveSteadyState: conjugate gradients (Jacobi-preconditioned, matrix-free) on
//   M c = f,  M = −D ∇²_h + λ + S + U,  f = S c* + R + the fixed faces' 2 D c_b / h²,
// the discrete operator of Step with its ghost values, symmetric positive definite when the
// substrate decays, is taken up, secreted or held on a fixed face. Sums go row by row of x and
// then over the rows in order, so the bits do not depend on the thread count.
#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "fields/team.h"
#include "moreau/common/error.h"
#include "moreau/common/stopwatch.h"
#include "moreau/common/summary_json.h"
#include "moreau/fields/field_set.h"

namespace moreau::fields {
namespace {

// The operator of one substrate on the grid, and the vectors of one solve.
class SteadyOperator {
 public:
  SteadyOperator(const Grid& grid, const Substrate& sub, int threads, std::span<const double> s,
                 std::span<const double> target, std::span<const double> u,
                 std::span<const double> r)
      : n_(grid.cells()),
        k_(grid.dimension),
        threads_(internal::TeamSize(threads, grid.voxel_count())),
        sub_(sub),
        coefficient_(sub.diffusion / (grid.spacing * grid.spacing)) {
    const std::int64_t count = grid.voxel_count();
    rows_ = count / n_[0];
    absorption_.resize(static_cast<std::size_t>(count));
    rhs_.resize(static_cast<std::size_t>(count));
    diagonal_.resize(static_cast<std::size_t>(count));
    for (std::int64_t v = 0; v < count; ++v) {
      absorption_[v] = sub.decay + s[v] + u[v];
      rhs_[v] = target[v] + r[v];
    }
    ForRows([&](std::int64_t row) { FaceTermsAndDiagonal(row); });
  }

  // y = M x.
  void Apply(const std::vector<double>& x, std::vector<double>& y) const {
    ForRows([&](std::int64_t row) {
      const std::int64_t begin = row * n_[0];
      for (std::int64_t v = begin; v < begin + n_[0]; ++v) y[v] = Row(x, v);
    });
  }

  // Σ_v a_v b_v, row by row.
  double Dot(const std::vector<double>& a, const std::vector<double>& b) const {
    std::vector<double> partial(static_cast<std::size_t>(rows_));
    ForRows([&](std::int64_t row) {
      double sum = 0.0;
      for (std::int64_t v = row * n_[0]; v < (row + 1) * n_[0]; ++v) sum += a[v] * b[v];
      partial[row] = sum;
    });
    double sum = 0.0;
    for (double p : partial) sum += p;
    return sum;
  }

  template <typename F>
  void ForRows(F&& f) const {
#pragma omp parallel for num_threads(threads_) schedule(static) if (threads_ > 1)
    for (std::int64_t row = 0; row < rows_; ++row) f(row);
  }

  const std::vector<double>& rhs() const { return rhs_; }
  const std::vector<double>& diagonal() const { return diagonal_; }
  std::int64_t row_length() const { return n_[0]; }

 private:
  // (M x)_v: the decay and sources, and per axis D/h² (2 x_v − the two neighbours or ghosts).
  double Row(const std::vector<double>& x, std::int64_t v) const {
    const double xv = x[v];
    double sum = 0.0;
    std::int64_t stride = 1;
    std::int64_t rest = v;
    for (int a = 0; a < k_; ++a) {
      const std::int64_t n = n_[a];
      const std::int64_t i = rest % n;
      rest /= n;
      sum += 2.0 * xv - Neighbour(x, v, i, n, stride, 2 * a, -1) -
             Neighbour(x, v, i, n, stride, 2 * a + 1, 1);
      stride *= n;
    }
    return absorption_[v] * xv + coefficient_ * sum;
  }

  // The neighbour of voxel v (index i of n along the axis) on side `step`, or its ghost's part
  // that depends on x (zero flux: x_v; fixed: −x_v, the 2 c_b going to the right-hand side).
  double Neighbour(const std::vector<double>& x, std::int64_t v, std::int64_t i, std::int64_t n,
                   std::int64_t stride, int face, int step) const {
    const std::int64_t j = i + step;
    if (j >= 0 && j < n) return x[v + step * stride];
    switch (sub_.boundary[face].kind) {
      case BoundaryKind::kPeriodic:
        return x[v + (j < 0 ? n - 1 : 1 - n) * stride];
      case BoundaryKind::kFixed:
        return -x[v];
      case BoundaryKind::kZeroFlux:
        break;
    }
    return x[v];
  }

  // The fixed faces' terms of the right-hand side and the diagonal of M on row `row`.
  void FaceTermsAndDiagonal(std::int64_t row) {
    for (std::int64_t v = row * n_[0]; v < (row + 1) * n_[0]; ++v) {
      double diag = 0.0;
      std::int64_t rest = v;
      for (int a = 0; a < k_; ++a) {
        const std::int64_t n = n_[a];
        const std::int64_t i = rest % n;
        rest /= n;
        for (int side = 0; side < 2; ++side) {
          const FaceBoundary& face = sub_.boundary[2 * a + side];
          const bool at_face = side == 0 ? i == 0 : i == n - 1;
          if (!at_face || face.kind == BoundaryKind::kPeriodic) {
            diag += at_face && n == 1 ? 0.0 : 1.0;  // a periodic axis of one voxel: itself
          } else if (face.kind == BoundaryKind::kFixed) {
            diag += 2.0;
            rhs_[v] += 2.0 * coefficient_ * face.value;
          }
        }
      }
      diagonal_[v] = absorption_[v] + coefficient_ * diag;
    }
  }

  std::array<int, 3> n_;
  int k_;
  int threads_;
  const Substrate& sub_;
  double coefficient_;  // D / h²
  std::int64_t rows_ = 0;
  std::vector<double> absorption_, rhs_, diagonal_;
};

double MaxAbs(const std::vector<double>& v) {
  double m = 0.0;
  bool nan = false;
  for (double x : v) {
    m = std::max(m, std::abs(x));
    nan = nan || std::isnan(x);
  }
  return nan ? std::numeric_limits<double>::quiet_NaN() : m;
}

struct CgResult {
  int iterations = 0;
  double residual = 0.0;  // relative, ∞-norm
  bool converged = false;
  bool finite = true;
};

// Preconditioned conjugate gradients on M c = f from c; restarts from the true residual when the
// recurred one meets the tolerance but the true one does not.
CgResult ConjugateGradients(const SteadyOperator& op, const SteadyStateOptions& options,
                            std::vector<double>& c) {
  const std::vector<double>& f = op.rhs();
  const std::vector<double>& d = op.diagonal();
  const std::size_t n = c.size();
  std::vector<double> r(n), z(n), p(n), q(n);
  CgResult out;
  const double reference = MaxAbs(f);
  if (!(reference > 0.0)) {  // f = 0: the solution is 0
    std::fill(c.begin(), c.end(), 0.0);
    out.converged = std::isfinite(reference);
    out.finite = out.converged;
    return out;
  }
  const auto restart = [&] {
    op.Apply(c, q);
    op.ForRows([&](std::int64_t row) {
      for (std::int64_t v = row * op.row_length(); v < (row + 1) * op.row_length(); ++v) {
        r[v] = f[v] - q[v];
        z[v] = r[v] / d[v];
        p[v] = z[v];
      }
    });
    return op.Dot(r, z);
  };
  double rz = restart();
  bool recurred = false;  // r is a recurred residual (not recomputed since the last step)
  while (true) {
    out.residual = MaxAbs(r) / reference;
    if (!std::isfinite(out.residual)) {
      out.finite = false;
      return out;
    }
    if (out.residual <= options.tolerance) {
      if (!recurred) break;
      rz = restart();
      recurred = false;
      continue;
    }
    if (out.iterations >= options.max_iterations) return out;
    op.Apply(p, q);
    const double alpha = rz / op.Dot(p, q);
    op.ForRows([&](std::int64_t row) {
      for (std::int64_t v = row * op.row_length(); v < (row + 1) * op.row_length(); ++v) {
        c[v] += alpha * p[v];
        r[v] -= alpha * q[v];
        z[v] = r[v] / d[v];
      }
    });
    const double rz_next = op.Dot(r, z);
    const double beta = rz_next / rz;
    rz = rz_next;
    op.ForRows([&](std::int64_t row) {
      for (std::int64_t v = row * op.row_length(); v < (row + 1) * op.row_length(); ++v) {
        p[v] = z[v] + beta * p[v];
      }
    });
    ++out.iterations;
    recurred = true;
  }
  out.converged = true;
  return out;
}

// True when the substrate has a unique steady state: decay, a fixed face, or somewhere S + U > 0.
bool HasUniqueSteadyState(const Substrate& sub, int dimension, std::span<const double> s,
                          std::span<const double> u) {
  if (sub.decay > 0.0) return true;
  for (int f = 0; f < 2 * dimension; ++f) {
    if (sub.boundary[f].kind == BoundaryKind::kFixed) return true;
  }
  for (std::size_t v = 0; v < s.size(); ++v) {
    if (s[v] + u[v] > 0.0) return true;
  }
  return false;
}

}  // namespace

const FieldList<SteadyStateOptions>& SteadyStateOptions::Fields() {
  using O = SteadyStateOptions;
  static const FieldList<O> list = [] {
    FieldList<O> t;
    t.Number("tolerance", &O::tolerance, Range::Open(0.0, 1.0), "",
             "stop at ‖residual‖_∞ ≤ tolerance · ‖residual at c = 0‖_∞")
        .Integer("max_iterations", &O::max_iterations, Range::AtLeast(1), "",
                 "conjugate-gradient iterations at most, per substrate");
    return t;
  }();
  return list;
}

nlohmann::json SteadyStateSummary::ToJson() const {
  nlohmann::json j = SummaryJson(termination, message, seconds);
  j["iterations"] = iterations;
  j["residual"] = FiniteOrNull(residual);
  return j;
}

SteadyStateSummary FieldSet::SolveSteadyState(const SteadyStateOptions& options) {
  SteadyStateOptions::Fields().Validate(options);
  for (std::size_t s = 0; s < substrates_.size(); ++s) {
    if (!HasUniqueSteadyState(substrates_[s], grid_.dimension, secretion_[s], uptake_[s])) {
      throw InputError("substrates." + substrates_[s].name,
                       "has no unique steady state (no decay, uptake, secretion or fixed face)");
    }
  }
  const Stopwatch watch;
  SteadyStateSummary summary;
  for (std::size_t s = 0; s < substrates_.size(); ++s) {
    const SteadyOperator op(grid_, substrates_[s], threads_, secretion_[s], secretion_target_[s],
                            uptake_[s], source_[s]);
    const std::vector<double> start = values_[s];
    const CgResult result = ConjugateGradients(op, options, values_[s]);
    summary.iterations += result.iterations;
    summary.residual = std::max(summary.residual, result.residual);
    if (!result.finite) {
      values_[s] = start;
      summary.termination = Termination::kDiverged;
      summary.message = fmt::format("substrate '{}': the residual is not finite at iteration {}",
                                    substrates_[s].name, result.iterations);
      break;
    }
    if (!result.converged && summary.ok()) {
      summary.termination = Termination::kMaxIterations;
      summary.message = fmt::format("substrate '{}': relative residual {:.3g} after {} iterations",
                                    substrates_[s].name, result.residual, result.iterations);
    }
  }
  summary.seconds = watch.Seconds();
  return summary;
}

}  // namespace moreau::fields
