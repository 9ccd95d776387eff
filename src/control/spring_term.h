// Closed-form value, gradient and Hessian of one spring's part of the regularised Hamiltonian
// (internal header). With the local variables Δx, Δv, e (d each; hamiltonian.h) and
//   q = Δx·Δx, l = √q, a = e·Δx, b = Δx·Δv, P = κ a / l,
//   φ(Δx, Δv, e) = S^γ(P) − κ a − ξ a b / q,
// the derivatives follow from those of P and of f = a b / q by the chain rule:
//   ∇φ  = S' ∇P − κ ∇a − ξ ∇f,     ∇²φ = S' ∇²P + S'' ∇P ∇Pᵀ − κ ∇²a − ξ ∇²f.
// φ is linear in Δv and in e apart from S^γ, so the (Δv, Δv) block is zero and the (e, e) block
// is S'' ∇_e P ∇_e Pᵀ. tests/control/hamiltonian_test.cpp checks every block against finite
// differences and against the forward-mode jets of hamiltonian_jets.cpp.
#pragma once

#include <Eigen/Core>
#include <cmath>

#include "moreau/control/hamiltonian.h"
#include "moreau/control/spring_network.h"

namespace moreau::control::internal {

template <int D>
struct SpringTerm {
  using Vec = Eigen::Matrix<double, D, 1>;
  using Mat = Eigen::Matrix<double, D, D>;
  double value = 0.0;
  Vec gx, gv, ge;  // ∂φ/∂Δx, ∂φ/∂Δv, ∂φ/∂e
  // Hessian blocks, (row variable, column variable): xx, xv = ∂²φ/∂Δx∂Δv, xe, ve, ee (vv = 0).
  Mat xx, xv, xe, ve, ee;
};

// φ and its derivatives; the Hessian blocks only when `hessian` is true.
template <int D>
void EvaluateSpringTerm(const Eigen::Matrix<double, D, 1>& dx,
                        const Eigen::Matrix<double, D, 1>& dv, const Eigen::Matrix<double, D, 1>& e,
                        const NetworkSpring& sp, double gamma, bool hessian, SpringTerm<D>& t) {
  using Vec = Eigen::Matrix<double, D, 1>;
  using Mat = Eigen::Matrix<double, D, D>;
  const double kappa = sp.stiffness, xi = sp.damping;
  const double q = dx.squaredNorm();
  const double inv_q = 1.0 / q;
  const double inv_l = std::sqrt(inv_q);
  const double a = e.dot(dx), b = dx.dot(dv);
  const double p = kappa * a * inv_l;
  const SmoothMin s = RegularizedSpringMin(p, sp.rest_min, sp.rest_max, gamma);
  t.value = s.value - kappa * a - xi * a * b * inv_q;
  // ∇P: x-block κ (e − (a/q) Δx) / l, e-block κ Δx / l.
  const Vec px = kappa * inv_l * (e - a * inv_q * dx);
  const Vec pe = kappa * inv_l * dx;
  // ∇f = (b/q) ∇a + (a/q) ∇b − (a b / q²) ∇q with ∇a = (e, 0, Δx), ∇b = (Δv, Δx, 0), ∇q = (2Δx, 0,
  // 0).
  const double bq = b * inv_q, aq = a * inv_q, abq2 = a * b * inv_q * inv_q;
  t.gx = s.slope * px - kappa * e - xi * (bq * e + aq * dv - 2.0 * abq2 * dx);
  t.gv = -xi * aq * dx;
  t.ge = s.slope * pe - kappa * dx - xi * bq * dx;
  if (!hessian) return;
  const Mat id = Mat::Identity();
  const Mat xxt = dx * dx.transpose();
  const double inv_l3 = inv_l * inv_q;
  // ∇²P: xx = κ [−(e Δxᵀ + Δx eᵀ)/l³ − (a/l³) I + 3 a Δx Δxᵀ / l⁵], xe = κ (I/l − Δx Δxᵀ/l³).
  const Mat ext = e * dx.transpose();
  const Mat pxx = kappa * inv_l3 * (-(ext + ext.transpose()) - a * id + 3.0 * aq * xxt);
  const Mat pxe = kappa * (inv_l * id - inv_l3 * xxt);
  // ∇²f blocks.
  const Mat evt = e * dv.transpose();
  const Mat vxt = dv * dx.transpose();
  const Mat fxx = inv_q * (evt + evt.transpose()) - 2.0 * bq * inv_q * (ext + ext.transpose()) -
                  2.0 * aq * inv_q * (vxt + vxt.transpose()) + 8.0 * abq2 * inv_q * xxt -
                  2.0 * abq2 * id;
  const Mat fxv = inv_q * ext - 2.0 * aq * inv_q * xxt + aq * id;
  const Mat fxe = inv_q * vxt - 2.0 * bq * inv_q * xxt + bq * id;
  t.xx = s.slope * pxx + s.curvature * px * px.transpose() - xi * fxx;
  t.xv = -xi * fxv;
  t.xe = s.slope * pxe + s.curvature * px * pe.transpose() - kappa * id - xi * fxe;
  t.ve = -xi * inv_q * xxt;
  t.ee = s.curvature * pe * pe.transpose();
}

}  // namespace moreau::control::internal
