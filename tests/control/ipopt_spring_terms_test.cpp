// The closed-form spring derivatives and the control entropy of the IPOPT benchmark
// (bench/ipopt/spring_terms.h): the force Jacobian against central differences of the
// library's dynamics, the Hessian against central differences of the Jacobian, and the entropy
// penalty as the Legendre partner of the regularised minimum S^γ of hamiltonian.h.
#include "../../bench/ipopt/spring_terms.h"

#include <gtest/gtest.h>

#include "moreau/control/hamiltonian.h"
#include "moreau/control/spring_network.h"

namespace moreau::bench {
namespace {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;

constexpr double kStiffness = 20.0;
constexpr double kDamping = 4.0;
constexpr double kMass = 2.0;

// A fixed node at the origin and a free node b at (x, v): its acceleration is F / m.
Vec3 Force(const Vec3& x, const Vec3& v, double rest) {
  control::NetworkNode anchor;
  anchor.fixed = true;
  control::NetworkNode free_node;
  free_node.mass = kMass;
  free_node.position = x;
  control::NetworkSpring spring{0, 1, kStiffness, kDamping, 0.5, 2.0};
  const control::SpringNetwork net(3, {anchor, free_node}, {spring});
  Eigen::VectorXd z(6), rate(6);
  z << x, v;
  control::EvaluateDynamics(net, 0.0, z, Eigen::VectorXd::Constant(1, rest), rate);
  return kMass * rate.tail<3>();
}

const Vec3 kDx(0.7, -0.4, 1.1);
const Vec3 kDv(0.3, 0.8, -0.5);
const Vec3 kE(-1.3, 0.6, 0.9);
constexpr double kRest = 1.2;
constexpr double kStep = 1e-6;

TEST(IpoptSpringTerms, ForceJacobianMatchesCentralDifferencesOfTheDynamics) {
  const SpringForceJacobian<3> jac = ForceJacobian<3>(kDx, kDv, kRest, kStiffness, kDamping);
  Mat3 dx, dv;
  for (int j = 0; j < 3; ++j) {
    const Vec3 h = kStep * Vec3::Unit(j);
    dx.col(j) = (Force(kDx + h, kDv, kRest) - Force(kDx - h, kDv, kRest)) / (2.0 * kStep);
    dv.col(j) = (Force(kDx, kDv + h, kRest) - Force(kDx, kDv - h, kRest)) / (2.0 * kStep);
  }
  const Vec3 dl = (Force(kDx, kDv, kRest + kStep) - Force(kDx, kDv, kRest - kStep)) / (2.0 * kStep);
  EXPECT_LT((jac.dx - dx).cwiseAbs().maxCoeff(), 1e-7 * kStiffness);
  EXPECT_LT((jac.dv - dv).cwiseAbs().maxCoeff(), 1e-7 * kDamping);
  EXPECT_LT((jac.dl - dl).cwiseAbs().maxCoeff(), 1e-7 * kStiffness);
}

TEST(IpoptSpringTerms, ForceHessianMatchesCentralDifferencesOfTheJacobian) {
  const SpringForceHessian<3> hess = ForceHessian<3>(kDx, kDv, kE, kRest, kStiffness, kDamping);
  // Gradient of e · F in Δx: eᵀ ∂F/∂Δx.
  auto grad_x = [](const Vec3& dx, const Vec3& dv, double rest) -> Vec3 {
    return ForceJacobian<3>(dx, dv, rest, kStiffness, kDamping).dx.transpose() * kE;
  };
  Mat3 xx, xv;
  for (int j = 0; j < 3; ++j) {
    const Vec3 h = kStep * Vec3::Unit(j);
    xx.col(j) = (grad_x(kDx + h, kDv, kRest) - grad_x(kDx - h, kDv, kRest)) / (2.0 * kStep);
    xv.col(j) = (grad_x(kDx, kDv + h, kRest) - grad_x(kDx, kDv - h, kRest)) / (2.0 * kStep);
  }
  const Vec3 xl =
      (grad_x(kDx, kDv, kRest + kStep) - grad_x(kDx, kDv, kRest - kStep)) / (2.0 * kStep);
  EXPECT_LT((hess.xx - xx).cwiseAbs().maxCoeff(), 1e-7 * kStiffness);
  EXPECT_LT((hess.xx - hess.xx.transpose()).cwiseAbs().maxCoeff(), 1e-12 * kStiffness);
  EXPECT_LT((hess.xv - xv).cwiseAbs().maxCoeff(), 1e-7 * kDamping);
  EXPECT_LT((hess.xl - xl).cwiseAbs().maxCoeff(), 1e-7 * kStiffness);
  // e · F is linear in Δv: its Δv-gradient eᵀ ∂F/∂Δv must not change with Δv.
  const Vec3 gv0 = ForceJacobian<3>(kDx, kDv, kRest, kStiffness, kDamping).dv.transpose() * kE;
  const Vec3 gv1 =
      ForceJacobian<3>(kDx, 2.0 * kDv, kRest, kStiffness, kDamping).dv.transpose() * kE;
  EXPECT_LT((gv0 - gv1).cwiseAbs().maxCoeff(), 1e-14);
}

// min_L (P L + γ ψ(L)) = S^γ(P), attained at L = dS^γ/dP: the IPOPT problem's control penalty
// is exactly the regularisation of moreau's Hamiltonian.
TEST(IpoptSpringTerms, EntropyIsTheLegendrePartnerOfTheRegularisedMinimum) {
  const double lo = 0.6;
  const double hi = 1.9;
  for (const double gamma : {1e-4, 1e-2, 1.0}) {
    for (const double p_over_gamma : {-6.0, -1.5, -0.2, 0.0, 0.4, 3.0, 6.0}) {
      const double p = p_over_gamma * gamma;
      const control::SmoothMin s = control::RegularizedSpringMin(p, lo, hi, gamma);
      EntropyPenalty pen;
      ASSERT_TRUE(ControlEntropy(s.slope, lo, hi, pen));
      EXPECT_NEAR(p * s.slope + gamma * pen.value, s.value, 1e-13 * (1.0 + std::abs(s.value)));
      EXPECT_NEAR(p + gamma * pen.slope, 0.0, 1e-8 * gamma);  // stationary
      // ψ'' = 1 / S^γ'' · (−1/γ): the curvatures of a Legendre pair are reciprocal.
      if (std::abs(p_over_gamma) < 5.0) {
        EXPECT_NEAR(gamma * pen.curvature * -s.curvature, 1.0, 1e-8);
      }
    }
  }
}

TEST(IpoptSpringTerms, EntropyDerivativesMatchCentralDifferences) {
  const double lo = 0.6;
  const double hi = 1.9;
  for (const double rest : {0.61, 0.9, 1.25, 1.7, 1.89}) {
    EntropyPenalty at, plus, minus;
    ASSERT_TRUE(ControlEntropy(rest, lo, hi, at));
    ASSERT_TRUE(ControlEntropy(rest + kStep, lo, hi, plus));
    ASSERT_TRUE(ControlEntropy(rest - kStep, lo, hi, minus));
    EXPECT_NEAR(at.slope, (plus.value - minus.value) / (2.0 * kStep), 1e-7);
    EXPECT_NEAR(at.curvature, (plus.slope - minus.slope) / (2.0 * kStep), 1e-6 * at.curvature);
  }
  EntropyPenalty pen;
  EXPECT_FALSE(ControlEntropy(lo, lo, hi, pen));
  EXPECT_FALSE(ControlEntropy(hi + 0.1, lo, hi, pen));
  ASSERT_TRUE(ControlEntropy(0.5 * (lo + hi), lo, hi, pen));
  EXPECT_NEAR(pen.value, 0.0, 1e-15);  // ψ = 0 at the middle, ½ ln2 (L+ − L−) at the bounds
}

}  // namespace
}  // namespace moreau::bench
