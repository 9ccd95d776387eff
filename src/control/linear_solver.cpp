#include "moreau/control/linear_solver.h"

#include <fmt/format.h>

#include "moreau/common/error.h"

namespace moreau::control {

const char* ToString(LinearSolverType type) { return EnumName(kLinearSolverNames, type).data(); }

LinearSolverType ParseLinearSolverType(const std::string& text) {
  return ParseEnumName(kLinearSolverNames, text, "linear solver");
}

namespace {

// The Riccati sweeps on n × n blocks, with S = n known at compile time for the common state sizes
// (fixed-size Eigen products and LU are unrolled and vectorised) or S = Eigen::Dynamic. The
// blocks stay in dynamic storage and are viewed through maps.
template <int S>
struct RiccatiKernel {
  using Mat = Eigen::Matrix<double, S, S>;
  using Vec = Eigen::Matrix<double, S, 1>;
  using MatMap = Eigen::Map<Mat>;
  using ConstMatMap = Eigen::Map<const Mat>;
  using VecMap = Eigen::Map<Vec>;
  using ConstVecMap = Eigen::Map<const Vec>;

  // P_n, K_n and M_n⁻¹ for n = N−1 … 0 (p[N] given). False on a singular or non-finite block:
  // M_n = I − B_n P_{n+1} counts as singular when its reciprocal 1-norm condition number
  // 1 / (‖M‖₁ ‖M⁻¹‖₁), computed from the inverse the solve needs anyway, is below 1e−14.
  // The products are coefficient-based (lazyProduct): for blocks this small, the fixed-size
  // unrolled loops are several times faster than Eigen's blocked matrix-matrix kernel.
  static bool Factorize(const PontryaginJacobian& J, int n, std::vector<Eigen::MatrixXd>& p,
                        std::vector<Eigen::MatrixXd>& k, std::vector<Eigen::MatrixXd>& m_inv) {
    Mat m(n, n), ptk(n, n);
    for (std::size_t s = k.size(); s-- > 0;) {
      const ConstMatMap A(J.A[s].data(), n, n), B(J.B[s].data(), n, n), C(J.C[s].data(), n, n);
      const ConstMatMap p_next(p[s + 1].data(), n, n);
      m = -B.lazyProduct(p_next);
      m.diagonal().array() += 1.0;
      const Eigen::PartialPivLU<Mat> lu(m);
      m_inv[s].resize(n, n);
      k[s].resize(n, n);
      p[s].resize(n, n);
      MatMap M_inv(m_inv[s].data(), n, n);
      M_inv = lu.inverse();
      const double norm = m.cwiseAbs().colwise().sum().maxCoeff();
      const double inv_norm = M_inv.cwiseAbs().colwise().sum().maxCoeff();
      if (!(1.0 / (norm * inv_norm) > 1e-14)) return false;
      MatMap K(k[s].data(), n, n);
      K = M_inv.lazyProduct(A);
      ptk = p_next.lazyProduct(K);
      MatMap P(p[s].data(), n, n);
      P = C + A.transpose().lazyProduct(ptk);
      if (!P.allFinite()) return false;
    }
    return true;
  }

  // Backward sweep for q_n, v_n, then forward for δz, δρ (x in the layout of pontryagin.h).
  static void Solve(const PontryaginJacobian& J, int n, const std::vector<Eigen::MatrixXd>& p,
                    const std::vector<Eigen::MatrixXd>& k,
                    const std::vector<Eigen::MatrixXd>& m_inv, const Eigen::VectorXd& rhs,
                    std::vector<Eigen::VectorXd>& q, std::vector<Eigen::VectorXd>& v,
                    Eigen::VectorXd& x) {
    const std::size_t N = k.size();
    Vec tmp(n), tmp2(n);
    q[N].setZero(n);
    for (std::size_t s = N; s-- > 0;) {
      const Eigen::Index off = 2 * n * static_cast<Eigen::Index>(s);
      const ConstVecMap q_next(q[s + 1].data(), n);
      tmp = rhs.segment(off, n);
      tmp += ConstMatMap(J.B[s].data(), n, n).lazyProduct(q_next);
      v[s].resize(n);
      VecMap(v[s].data(), n) = ConstMatMap(m_inv[s].data(), n, n).lazyProduct(tmp);
      tmp2 = q_next;
      tmp2 += ConstMatMap(p[s + 1].data(), n, n).lazyProduct(ConstVecMap(v[s].data(), n));
      q[s].resize(n);
      VecMap qs(q[s].data(), n);
      qs = rhs.segment(off + n, n);
      qs += ConstMatMap(J.A[s].data(), n, n).transpose().lazyProduct(tmp2);
    }
    tmp.setZero(n);  // δz^s, from δz^0 = 0
    for (std::size_t s = 0; s < N; ++s) {
      const Eigen::Index off = 2 * n * static_cast<Eigen::Index>(s);
      x.segment(off + n, n) = ConstVecMap(q[s].data(), n);
      x.segment(off + n, n) += ConstMatMap(p[s].data(), n, n).lazyProduct(tmp);
      tmp2 = ConstVecMap(v[s].data(), n);
      tmp2 += ConstMatMap(k[s].data(), n, n).lazyProduct(tmp);
      x.segment(off, n) = tmp2;
      tmp = tmp2;
    }
  }
};

// Calls f(RiccatiKernel<S>{}) with S = n for the sizes compiled fixed, else S = Eigen::Dynamic.
template <typename F>
auto DispatchStateSize(int n, F&& f) {
  switch (n) {
    case 8:
      return f(RiccatiKernel<8>{});
    case 12:
      return f(RiccatiKernel<12>{});
    case 16:
      return f(RiccatiKernel<16>{});
    case 24:
      return f(RiccatiKernel<24>{});
    default:
      return f(RiccatiKernel<Eigen::Dynamic>{});
  }
}

}  // namespace

namespace {

// The split order of the state (linear_solver.h): positions of every free node, then velocities.
std::vector<int> SplitOrder(const PontryaginDiscretization& disc) {
  const int d = disc.problem().network().dimension();
  const int m = disc.problem().network().num_free();
  std::vector<int> order(static_cast<std::size_t>(2 * d * m));
  for (int k = 0; k < m; ++k) {
    for (int i = 0; i < d; ++i) {
      order[static_cast<std::size_t>(d * k + i)] = 2 * d * k + i;
      order[static_cast<std::size_t>(d * m + d * k + i)] = 2 * d * k + d + i;
    }
  }
  return order;
}

// Whether every B_n vanishes outside the velocity block and every A_n has position rows
// [I, α I] (in the split order): the structure the split path needs.
bool HasSplitStructure(const PontryaginJacobian& J, const std::vector<int>& order, double alpha) {
  const auto n = static_cast<Eigen::Index>(order.size());
  const Eigen::Index h = n / 2;
  for (std::size_t s = 0; s < J.A.size(); ++s) {
    const Eigen::MatrixXd& A = J.A[s];
    const Eigen::MatrixXd& B = J.B[s];
    for (Eigen::Index i = 0; i < h; ++i) {
      const int x = order[static_cast<std::size_t>(i)];
      const int v = order[static_cast<std::size_t>(h + i)];
      for (Eigen::Index j = 0; j < n; ++j) {
        if (B(x, j) != 0.0 || B(j, x) != 0.0) return false;
        const double a = A(x, j);
        const double expected = j == x ? 1.0 : (j == v ? alpha : 0.0);
        if (a != expected) return false;
      }
    }
  }
  return true;
}

}  // namespace

bool RiccatiSolver::Factorize(const PontryaginDiscretization& disc,
                              const PontryaginJacobian& jacobian) {
  jacobian_ = &jacobian;
  steps_ = disc.steps();
  n_ = disc.state_size();
  const auto N = static_cast<std::size_t>(steps_);
  p_.resize(N + 1);
  k_.resize(N);
  m_inv_.resize(N);
  q_.resize(N + 1);
  v_.resize(N);
  order_ = SplitOrder(disc);
  alpha_ = disc.dt();
  split_ = n_ >= kSplitMinStateSize && n_ % 2 == 0 && static_cast<int>(order_.size()) == n_ &&
           HasSplitStructure(jacobian, order_, alpha_);
  if (split_) return FactorizeSplit();
  p_[N] = jacobian.G.asDiagonal();
  return DispatchStateSize(
      n_, [&](auto kernel) { return decltype(kernel)::Factorize(jacobian, n_, p_, k_, m_inv_); });
}

void RiccatiSolver::Solve(const Eigen::VectorXd& rhs, Eigen::VectorXd& x) {
  x.resize(rhs.size());
  if (split_) {
    SolveSplit(rhs, x);
    return;
  }
  DispatchStateSize(n_, [&](auto kernel) {
    decltype(kernel)::Solve(*jacobian_, n_, p_, k_, m_inv_, rhs, q_, v_, x);
  });
}

// The recursion of linear_solver.h in the split order, X = positions, V = velocities (h = n/2):
//   M_VX = −B_VV P_VX,  M_VV = I − B_VV P_VV,  W = M_VV⁻¹ M_VX,
//   K = [A_X; K_V],  A_X = [I, α I],  K_V = M_VV⁻¹ A_V − W A_X,
//   P_n = C_n + A_nᵀ (P_{n+1} K)  with  A_nᵀ Y = [Y_X; α Y_X] + A_Vᵀ Y_V.
bool RiccatiSolver::FactorizeSplit() {
  const PontryaginJacobian& J = *jacobian_;
  const Eigen::Index n = n_, h = n / 2;
  const double alpha = alpha_;
  const auto N = static_cast<std::size_t>(steps_);
  a_v_.resize(N);
  b_vv_.resize(N);
  w_.resize(N);
  const std::vector<int> xs(order_.begin(), order_.begin() + h),
      vs(order_.begin() + h, order_.end());
  p_[N] = Eigen::VectorXd(J.G(order_)).asDiagonal();
  for (std::size_t s = N; s-- > 0;) {
    const Eigen::MatrixXd& p_next = p_[s + 1];
    a_v_[s] = J.A[s](vs, order_);
    b_vv_[s] = J.B[s](vs, vs);
    const Eigen::MatrixXd& b = b_vv_[s];
    m_vx_.noalias() = -b * p_next.bottomLeftCorner(h, h);
    m_vv_.noalias() = -b * p_next.bottomRightCorner(h, h);
    m_vv_.diagonal().array() += 1.0;
    const Eigen::PartialPivLU<Eigen::MatrixXd> lu(m_vv_);
    m_inv_[s] = lu.inverse();
    const Eigen::MatrixXd& m_inv = m_inv_[s];
    const double norm = m_vv_.cwiseAbs().colwise().sum().maxCoeff();
    const double inv_norm = m_inv.cwiseAbs().colwise().sum().maxCoeff();
    if (!(1.0 / (norm * inv_norm) > 1e-14)) return false;
    w_[s].noalias() = m_inv * m_vx_;
    Eigen::MatrixXd& k = k_[s];
    k.noalias() = m_inv * a_v_[s];
    k.leftCols(h) -= w_[s];
    k.rightCols(h) -= alpha * w_[s];
    // P_{n+1} K = [P_X, α P_X] + P_V K_V (P_X, P_V: column blocks of P_{n+1}).
    pk_.resize(n, n);
    pk_.leftCols(h) = p_next.leftCols(h);
    pk_.rightCols(h) = alpha * p_next.leftCols(h);
    pk_.noalias() += p_next.rightCols(h) * k;
    Eigen::MatrixXd& p = p_[s];
    p = J.C[s](order_, order_);
    p.topRows(h) += pk_.topRows(h);
    p.bottomRows(h) += alpha * pk_.topRows(h);
    p.noalias() += a_v_[s].transpose() * pk_.bottomRows(h);
    if (!p.allFinite()) return false;
  }
  return true;
}

void RiccatiSolver::SolveSplit(const Eigen::VectorXd& rhs, Eigen::VectorXd& x) {
  const Eigen::Index n = n_, h = n / 2;
  const double alpha = alpha_;
  const auto N = static_cast<std::size_t>(steps_);
  Eigen::VectorXd r(n), tmp(n), tmp2(n), dz = Eigen::VectorXd::Zero(n);
  q_[N].setZero(n);
  for (std::size_t s = N; s-- > 0;) {
    const Eigen::Index off = 2 * n * static_cast<Eigen::Index>(s);
    const Eigen::VectorXd& q_next = q_[s + 1];
    r = rhs.segment(off, n)(order_);
    tmp = r;  // B q_{n+1}: velocity rows only
    tmp.tail(h).noalias() += b_vv_[s] * q_next.tail(h);
    Eigen::VectorXd& v = v_[s];
    v.resize(n);
    v.head(h) = tmp.head(h);
    v.tail(h).noalias() = m_inv_[s] * tmp.tail(h);
    v.tail(h).noalias() -= w_[s] * tmp.head(h);
    tmp2 = q_next;
    tmp2.noalias() += p_[s + 1] * v;
    Eigen::VectorXd& q = q_[s];
    q = rhs.segment(off + n, n)(order_);
    q.head(h) += tmp2.head(h);
    q.tail(h) += alpha * tmp2.head(h);
    q.noalias() += a_v_[s].transpose() * tmp2.tail(h);
  }
  for (std::size_t s = 0; s < N; ++s) {
    const Eigen::Index off = 2 * n * static_cast<Eigen::Index>(s);
    tmp = q_[s];
    tmp.noalias() += p_[s] * dz;
    x.segment(off + n, n)(order_) = tmp;
    tmp2 = v_[s];
    tmp2.head(h) += dz.head(h) + alpha * dz.tail(h);
    tmp2.tail(h).noalias() += k_[s] * dz;
    x.segment(off, n)(order_) = tmp2;
    dz = tmp2;
  }
}

bool SparseLuSolver::Factorize(const PontryaginDiscretization& disc,
                               const PontryaginJacobian& jacobian) {
  matrix_ = AssembleSparseJacobian(disc, jacobian);
  matrix_.makeCompressed();
  lu_.analyzePattern(matrix_);
  lu_.factorize(matrix_);
  return lu_.info() == Eigen::Success;
}

void SparseLuSolver::Solve(const Eigen::VectorXd& rhs, Eigen::VectorXd& x) { x = lu_.solve(rhs); }

}  // namespace moreau::control
