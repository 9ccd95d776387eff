// Closed-form derivatives of one spring–damper of the control problem, for the IPOPT
// transcription (benchmark only; header-only and free of IPOPT, so that
// tests/control/ipopt_spring_terms_test.cpp checks it in every build). With Δx = x_b − x_a, l =
// |Δx|, u = Δx / l, P = I − u uᵀ and Δv = v_b − v_a, the force on node b is (spring_network.h)
//   F = κ L u − κ Δx − ξ u (u · Δv)          (−F on node a),
// and for a multiplier vector e (e = ζ_b / m_b − ζ_a / m_a) the scalar e · F has the Hessian
//   ∂²/∂Δx²  = κ L Q(e) − ξ [ (u·Δv) Q(e) + (e·u) Q(Δv) + (P e)(P Δv)ᵀ / l² + (P Δv)(P e)ᵀ / l² ],
//   ∂²/∂Δx∂Δv = −ξ [ (P e) uᵀ + (e·u) P ] / l,   ∂²/∂Δx∂L = κ P e / l,   ∂²/∂Δv² = 0,
// where Q(q) = −[ (q·u) P + (P q) uᵀ + u (P q)ᵀ ] / l² is the Hessian of q · u in Δx.
#pragma once

#include <Eigen/Core>
#include <cmath>

namespace moreau::bench {

template <int D>
struct SpringForceJacobian {
  Eigen::Matrix<double, D, D> dx;  // ∂F/∂Δx
  Eigen::Matrix<double, D, D> dv;  // ∂F/∂Δv
  Eigen::Matrix<double, D, 1> dl;  // ∂F/∂L
};

template <int D>
struct SpringForceHessian {
  Eigen::Matrix<double, D, D> xx;  // ∂²(e·F)/∂Δx²
  Eigen::Matrix<double, D, D> xv;  // ∂²(e·F)/∂Δx∂Δv (rows Δx, columns Δv)
  Eigen::Matrix<double, D, 1> xl;  // ∂²(e·F)/∂Δx∂L
};

template <int D>
SpringForceJacobian<D> ForceJacobian(const Eigen::Matrix<double, D, 1>& dx,
                                     const Eigen::Matrix<double, D, 1>& dv, double rest,
                                     double stiffness, double damping) {
  using Mat = Eigen::Matrix<double, D, D>;
  const double l = dx.norm();
  const Eigen::Matrix<double, D, 1> u = dx / l;
  const Mat p = Mat::Identity() - u * u.transpose();
  const double b = u.dot(dv);
  SpringForceJacobian<D> j;
  j.dx = (stiffness * rest - damping * b) / l * p - stiffness * Mat::Identity() -
         damping / l * u * (p * dv).transpose();
  j.dv = -damping * u * u.transpose();
  j.dl = stiffness * u;
  return j;
}

template <int D>
SpringForceHessian<D> ForceHessian(const Eigen::Matrix<double, D, 1>& dx,
                                   const Eigen::Matrix<double, D, 1>& dv,
                                   const Eigen::Matrix<double, D, 1>& e, double rest,
                                   double stiffness, double damping) {
  using Mat = Eigen::Matrix<double, D, D>;
  using Vec = Eigen::Matrix<double, D, 1>;
  const double l = dx.norm();
  const Vec u = dx / l;
  const Mat p = Mat::Identity() - u * u.transpose();
  const Vec pe = p * e;
  const Vec pdv = p * dv;
  auto q = [&](const Vec& w, const Vec& pw) -> Mat {
    return -(w.dot(u) * p + pw * u.transpose() + u * pw.transpose()) / (l * l);
  };
  const double a = e.dot(u);
  const double b = u.dot(dv);
  SpringForceHessian<D> h;
  h.xx = (stiffness * rest - damping * b) * q(e, pe) - damping * a * q(dv, pdv) -
         damping / (l * l) * (pe * pdv.transpose() + pdv * pe.transpose());
  h.xv = -damping / l * (pe * u.transpose() + a * p);
  h.xl = stiffness / l * pe;
  return h;
}

// The control penalty γ ψ(L) whose Legendre transform is the regularised minimum S^γ of
// hamiltonian.h: with θ = (L − L−) / (L+ − L−) ∈ (0, 1),
//   ψ(L) = ½ (L+ − L−) [θ ln θ + (1 − θ) ln(1 − θ) + ln 2] ∈ [0, ½ ln2 (L+ − L−)],
//   ψ'(L) = ½ ln(θ / (1 − θ)),   ψ''(L) = 1 / (2 (L+ − L−) θ (1 − θ)),
// and min_L (P L + γ ψ(L)) = S^γ(P), attained at L = dS^γ/dP. Returns false outside (L−, L+).
struct EntropyPenalty {
  double value = 0.0;
  double slope = 0.0;
  double curvature = 0.0;
};
inline bool ControlEntropy(double rest, double rest_min, double rest_max, EntropyPenalty& out) {
  const double range = rest_max - rest_min;
  const double theta = (rest - rest_min) / range;
  if (!(theta > 0.0 && theta < 1.0)) return false;
  out.value =
      0.5 * range * (theta * std::log(theta) + (1.0 - theta) * std::log1p(-theta) + std::log(2.0));
  out.slope = 0.5 * (std::log(theta) - std::log1p(-theta));
  out.curvature = 1.0 / (2.0 * range * theta * (1.0 - theta));
  return true;
}

}  // namespace moreau::bench
