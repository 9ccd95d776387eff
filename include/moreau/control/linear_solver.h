// Direct solvers for the Newton system J δy = r of the Symplectic Pontryagin scheme.
//
// RiccatiSolver exploits the block-tridiagonal (in time) structure of J (pontryagin.h): a
// backward sweep eliminates the dual through  δρ^{n+1} = P_{n+1} δz^{n+1} + q_{n+1}  with
//   P_N = D²g,  M_n = I − B_n P_{n+1},  K_n = M_n^{-1} A_n,  P_n = C_n + A_nᵀ P_{n+1} K_n,
// and a forward sweep recovers δz^{n+1} = K_n δz^n + v_n, δρ^n = P_n δz^n + q_n. This is block
// Gaussian elimination of the block-tridiagonal matrix in the order (ρ^N, z^N), …, i.e. the
// discrete Riccati recursion; each step costs O(n_z³) (one LU of M_n), so a solve costs
// O(N n_z³) time and O(N n_z²) memory. M_n = I + |B_n| P_{n+1} is invertible whenever P_{n+1}
// is positive semidefinite (H^δ is concave in ρ, so B_n is negative semidefinite). State sizes
// 8, 12, 16 and 24 use fixed-size (unrolled) blocks, others dynamic ones; the results agree to
// rounding.
//
// SparseLuSolver assembles J as an Eigen sparse matrix and factorises it with SparseLU (COLAMD
// ordering): the general path, used to cross-check RiccatiSolver.
#pragma once

#include <Eigen/Core>
#include <Eigen/LU>
#include <Eigen/SparseCore>
#include <Eigen/SparseLU>
#include <string>
#include <vector>

#include "moreau/common/enum_names.h"
#include "moreau/control/pontryagin.h"

namespace moreau::control {

enum class LinearSolverType { kRiccati, kSparseLU };
inline constexpr EnumNames<LinearSolverType, 2> kLinearSolverNames{
    {{LinearSolverType::kRiccati, "riccati"}, {LinearSolverType::kSparseLU, "sparse_lu"}}};
// "riccati" / "sparse_lu". ParseLinearSolverType throws InputError for any other name.
const char* ToString(LinearSolverType type);
LinearSolverType ParseLinearSolverType(const std::string& text);

class NewtonLinearSolver {
 public:
  virtual ~NewtonLinearSolver() = default;
  // Factorises the Jacobian held in `jacobian` (which must outlive the following Solve calls).
  // Returns false if a pivot block is singular or non-finite.
  virtual bool Factorize(const PontryaginDiscretization& disc,
                         const PontryaginJacobian& jacobian) = 0;
  // Solves J x = rhs (block layout of pontryagin.h). Requires a successful Factorize.
  virtual void Solve(const Eigen::VectorXd& rhs, Eigen::VectorXd& x) = 0;
};

class RiccatiSolver final : public NewtonLinearSolver {
 public:
  bool Factorize(const PontryaginDiscretization& disc, const PontryaginJacobian& jacobian) override;
  void Solve(const Eigen::VectorXd& rhs, Eigen::VectorXd& x) override;

 private:
  const PontryaginJacobian* jacobian_ = nullptr;
  int steps_ = 0;
  int n_ = 0;
  std::vector<Eigen::MatrixXd> p_;      // P_0 … P_N
  std::vector<Eigen::MatrixXd> k_;      // K_0 … K_{N−1}
  std::vector<Eigen::MatrixXd> m_inv_;  // M_n⁻¹ (from the LU with partial pivoting)
  std::vector<Eigen::VectorXd> q_, v_;  // right-hand-side sweeps
};

class SparseLuSolver final : public NewtonLinearSolver {
 public:
  bool Factorize(const PontryaginDiscretization& disc, const PontryaginJacobian& jacobian) override;
  void Solve(const Eigen::VectorXd& rhs, Eigen::VectorXd& x) override;

 private:
  Eigen::SparseMatrix<double> matrix_;
  Eigen::SparseLU<Eigen::SparseMatrix<double>, Eigen::COLAMDOrdering<int>> lu_;
};

}  // namespace moreau::control
