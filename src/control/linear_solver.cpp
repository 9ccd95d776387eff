#include "moreau/control/linear_solver.h"

#include <fmt/format.h>

#include "moreau/common/error.h"

namespace moreau::control {

const char* ToString(LinearSolverType type) {
  switch (type) {
    case LinearSolverType::kRiccati:
      return "riccati";
    case LinearSolverType::kSparseLU:
      return "sparse_lu";
  }
  return "unknown";
}

LinearSolverType ParseLinearSolverType(const std::string& text) {
  if (text == "riccati") return LinearSolverType::kRiccati;
  if (text == "sparse_lu") return LinearSolverType::kSparseLU;
  throw InputError(
      fmt::format("unknown linear solver '{}' (expected riccati or sparse_lu)", text));
}

bool RiccatiSolver::Factorize(const PontryaginDiscretization& disc,
                              const PontryaginJacobian& jacobian) {
  jacobian_ = &jacobian;
  steps_ = disc.steps();
  n_ = disc.state_size();
  const auto N = static_cast<std::size_t>(steps_);
  p_.resize(N + 1);
  k_.resize(N);
  lu_.resize(N);
  q_.resize(N + 1);
  v_.resize(N);
  p_[N] = jacobian.G.asDiagonal();
  Eigen::MatrixXd m(n_, n_), ptk(n_, n_);
  for (std::size_t k = N; k-- > 0;) {
    const Eigen::MatrixXd& A = jacobian.A[k];
    const Eigen::MatrixXd& B = jacobian.B[k];
    const Eigen::MatrixXd& C = jacobian.C[k];
    m.noalias() = -B * p_[k + 1];
    m.diagonal().array() += 1.0;
    lu_[k].compute(m);
    if (!(lu_[k].rcond() > 1e-14)) return false;
    k_[k] = lu_[k].solve(A);
    ptk.noalias() = p_[k + 1] * k_[k];
    p_[k] = C;
    p_[k].noalias() += A.transpose() * ptk;
    if (!p_[k].allFinite()) return false;
  }
  return true;
}

void RiccatiSolver::Solve(const Eigen::VectorXd& rhs, Eigen::VectorXd& x) {
  const PontryaginJacobian& J = *jacobian_;
  const auto N = static_cast<std::size_t>(steps_);
  const Eigen::Index n = n_;
  x.resize(rhs.size());
  q_[N].setZero(n);
  for (std::size_t k = N; k-- > 0;) {
    const Eigen::Index off = 2 * n * static_cast<Eigen::Index>(k);
    tmp_ = rhs.segment(off, n);
    tmp_.noalias() += J.B[k] * q_[k + 1];
    v_[k] = lu_[k].solve(tmp_);
    tmp2_ = q_[k + 1];
    tmp2_.noalias() += p_[k + 1] * v_[k];
    q_[k] = rhs.segment(off + n, n);
    q_[k].noalias() += J.A[k].transpose() * tmp2_;
  }
  // Forward: δz^0 = 0.
  tmp_.setZero(n);  // δz^k
  for (std::size_t k = 0; k < N; ++k) {
    const Eigen::Index off = 2 * n * static_cast<Eigen::Index>(k);
    x.segment(off + n, n) = q_[k];
    x.segment(off + n, n).noalias() += p_[k] * tmp_;
    tmp2_ = v_[k];
    tmp2_.noalias() += k_[k] * tmp_;
    x.segment(off, n) = tmp2_;
    tmp_ = tmp2_;
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
