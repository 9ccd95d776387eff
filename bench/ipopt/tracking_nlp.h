// The primal counterpart of moreau's Symplectic Pontryagin system, as an Ipopt::TNLP
// (benchmark only; docs/benchmarks.md, "moreau against IPOPT").
//
//   minimise over z^1 … z^N (n_z each) and L^0 … L^{N−1} (one rest length per spring)
//     J = Σ_{n=0}^{N−1} Δt [ h(z^n, t_n) + γ Σ_s ψ_s(L^n_s) ] + g(z^N)
//   subject to  c_n = z^{n+1} − z^n − Δt f(z^n, L^n, t_n) = 0,   n = 0 … N−1,   z^0 = z(0),
//               L−_s <= L^n_s <= L+_s,
// with ψ_s the entropy penalty of spring_terms.h. Its KKT conditions are moreau's discrete
// system (pontryagin.h) with ρ^{n+1} = −λ_n (λ: IPOPT's constraint multipliers), L^n the
// effective rest lengths L^γ(z^n, ρ^{n+1}) and J the discrete value ū of (31).
//
// Variables are stored step by step: block n = (L^n, z^{n+1}), n = 0 … N−1.
#pragma once

#include <IpTNLP.hpp>

#include <Eigen/Core>
#include <vector>

#include "moreau/control/pontryagin.h"

namespace moreau::bench {

class TrackingNlp : public Ipopt::TNLP {
 public:
  // `states`: n_z × (N+1) start trajectory (column 0 ignored); `controls`: springs × N start
  // rest lengths, moved inside the bounds by at most 1e−6 of their range if on or outside them.
  TrackingNlp(const control::PontryaginDiscretization& disc, Eigen::MatrixXd states,
              Eigen::MatrixXd controls);

  // The solution after IPOPT returns: states n_z × (N+1), controls springs × N, dual ρ as
  // −λ (n_z × N, column n is ρ^{n+1}), objective J and IPOPT's status.
  const Eigen::MatrixXd& states() const { return states_; }
  const Eigen::MatrixXd& controls() const { return controls_; }
  const Eigen::MatrixXd& duals() const { return duals_; }
  double objective() const { return objective_; }
  Ipopt::SolverReturn status() const { return status_; }

  bool get_nlp_info(Ipopt::Index& n, Ipopt::Index& m, Ipopt::Index& nnz_jac_g,
                    Ipopt::Index& nnz_h_lag, IndexStyleEnum& index_style) override;
  bool get_bounds_info(Ipopt::Index n, Ipopt::Number* x_l, Ipopt::Number* x_u, Ipopt::Index m,
                       Ipopt::Number* g_l, Ipopt::Number* g_u) override;
  bool get_starting_point(Ipopt::Index n, bool init_x, Ipopt::Number* x, bool init_z,
                          Ipopt::Number* z_l, Ipopt::Number* z_u, Ipopt::Index m, bool init_lambda,
                          Ipopt::Number* lambda) override;
  bool eval_f(Ipopt::Index n, const Ipopt::Number* x, bool new_x,
              Ipopt::Number& obj_value) override;
  bool eval_grad_f(Ipopt::Index n, const Ipopt::Number* x, bool new_x,
                   Ipopt::Number* grad_f) override;
  bool eval_g(Ipopt::Index n, const Ipopt::Number* x, bool new_x, Ipopt::Index m,
              Ipopt::Number* g) override;
  bool eval_jac_g(Ipopt::Index n, const Ipopt::Number* x, bool new_x, Ipopt::Index m,
                  Ipopt::Index nele_jac, Ipopt::Index* i_row, Ipopt::Index* j_col,
                  Ipopt::Number* values) override;
  bool eval_h(Ipopt::Index n, const Ipopt::Number* x, bool new_x, Ipopt::Number obj_factor,
              Ipopt::Index m, const Ipopt::Number* lambda, bool new_lambda, Ipopt::Index nele_hess,
              Ipopt::Index* i_row, Ipopt::Index* j_col, Ipopt::Number* values) override;
  void finalize_solution(Ipopt::SolverReturn status, Ipopt::Index n, const Ipopt::Number* x,
                         const Ipopt::Number* z_l, const Ipopt::Number* z_u, Ipopt::Index m,
                         const Ipopt::Number* g, const Ipopt::Number* lambda,
                         Ipopt::Number obj_value, const Ipopt::IpoptData* ip_data,
                         Ipopt::IpoptCalculatedQuantities* ip_cq) override;

 private:
  // Local sparsity of one step, in the local variables (z^n, L^n): (row, column) pairs, and a
  // dense table from a pair to its slot (−1: structurally zero).
  struct Pattern {
    std::vector<int> rows, cols;
    std::vector<int> slot;  // rows_count × cols_count
    int Add(int row, int col, int cols_count);
  };
  void BuildPatterns();
  // Global index of z^k (k = 1 … N) and of L^n (n = 0 … N−1).
  int ZIndex(int k) const { return (k - 1) * block_ + m_; }
  int LIndex(int n) const { return n * block_; }
  // z^n (z^0 for n = 0) and L^n from x.
  void Gather(const Ipopt::Number* x, int n, Eigen::VectorXd& z, Eigen::VectorXd& rest) const;
  // ∂f/∂z and ∂f/∂L at step n into the slots of jac_z_/jac_l_ (values accumulated).
  void DynamicsJacobian(int n, const Eigen::VectorXd& z, const Eigen::VectorXd& rest, double* vz,
                        double* vl) const;
  // ∇²(λ·f) at step n into the slots of hess_zz_/hess_lz_ (scaled by `scale`).
  void DynamicsHessian(int n, const Eigen::VectorXd& z, const Eigen::VectorXd& rest,
                       const Ipopt::Number* lambda, double scale, double* vzz, double* vlz) const;

  const control::PontryaginDiscretization& disc_;
  int nz_ = 0, m_ = 0, steps_ = 0, block_ = 0;
  Pattern jac_z_, jac_l_, hess_zz_, hess_lz_;
  Eigen::MatrixXd start_states_, start_controls_;
  Eigen::MatrixXd states_, controls_, duals_;
  double objective_ = 0.0;
  Ipopt::SolverReturn status_ = Ipopt::INTERNAL_ERROR;
};

}  // namespace moreau::bench
