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
  p_[N] = jacobian.G.asDiagonal();
  return DispatchStateSize(
      n_, [&](auto kernel) { return decltype(kernel)::Factorize(jacobian, n_, p_, k_, m_inv_); });
}

void RiccatiSolver::Solve(const Eigen::VectorXd& rhs, Eigen::VectorXd& x) {
  x.resize(rhs.size());
  DispatchStateSize(n_, [&](auto kernel) {
    decltype(kernel)::Solve(*jacobian_, n_, p_, k_, m_inv_, rhs, q_, v_, x);
  });
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
