// Direct solvers for the Newton system J δy = r of the Symplectic Pontryagin scheme.
//
// RiccatiSolver exploits the block-tridiagonal (in time) structure of J (pontryagin.h): a
// backward sweep eliminates the dual through  δρ^{n+1} = P_{n+1} δz^{n+1} + q_{n+1}  with
//   P_N = D²g,  M_n = I − B_n P_{n+1},  K_n = M_n^{-1} A_n,  P_n = C_n + A_nᵀ P_{n+1} K_n,
// and a forward sweep recovers δz^{n+1} = K_n δz^n + v_n, δρ^n = P_n δz^n + q_n. This is block
// Gaussian elimination of the block-tridiagonal matrix in the order (ρ^N, z^N), …, i.e. the
// discrete Riccati recursion; each step costs O(n_z³) (one LU of M_n), so a solve costs
// O(N n_z³) time and O(N n_z²) memory. M_n = I + |B_n| P_{n+1} is invertible whenever P_{n+1}
// is positive semidefinite (H^δ is concave in ρ, so B_n is negative semidefinite). From
// n_z = 18 on, the scheme's structure halves the blocks (the split path, below); smaller state
// sizes 8, 12 and 16 use fixed-size (unrolled) blocks, others (and n_z = 24 without the structure)
// dynamic ones; the results agree to rounding.
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
  // True when the last Factorize took the split path (below).
  bool split() const { return split_; }
  // The split path runs for state sizes from this on; smaller ones keep the fixed-size kernels.
  static constexpr int kSplitMinStateSize = 18;

 private:
  bool FactorizeSplit();
  void SolveSplit(const Eigen::VectorXd& rhs, Eigen::VectorXd& x);

  const PontryaginJacobian* jacobian_ = nullptr;
  int steps_ = 0;
  int n_ = 0;
  std::vector<Eigen::MatrixXd> p_;      // P_0 … P_N
  std::vector<Eigen::MatrixXd> k_;      // K_0 … K_{N−1} (split: the velocity rows of K_n)
  std::vector<Eigen::MatrixXd> m_inv_;  // M_n⁻¹ (split: M_VV⁻¹), from an LU with partial pivoting
  std::vector<Eigen::VectorXd> q_, v_;  // right-hand-side sweeps
  // The split path. The scheme's Jacobian has B_n = Δt H_ρρ zero outside the velocity block (ρ
  // enters H^δ only through the springs' ζ terms) and position rows [I, Δt I] of A_n (ẋ = v).
  // Then M_n = I − B_n P_{n+1} has identity position rows and only the velocity block M_VV (half
  // the size) is factorised, K_n's position rows are A_n's, and the products with A_n skip them:
  // about 2 n_z³ flops per step instead of about 7 n_z³. Blocks are stored in the order
  // (positions of every free node, then velocities) given by order_; the same numbers up to
  // rounding as the general path, which runs when the structure is absent or n_z < 18.
  bool split_ = false;
  double alpha_ = 0.0;                 // Δt: A_n's position rows are [I, α I]
  std::vector<int> order_;             // split index i → index in z (positions, then velocities)
  std::vector<Eigen::MatrixXd> a_v_;   // velocity rows of A_n (n_z/2 × n_z), split order
  std::vector<Eigen::MatrixXd> b_vv_;  // velocity block of B_n (n_z/2 × n_z/2)
  std::vector<Eigen::MatrixXd> w_;     // M_VV⁻¹ M_VX (n_z/2 × n_z/2)
  Eigen::MatrixXd pk_, m_vx_, m_vv_;   // scratch of the factorisation
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
