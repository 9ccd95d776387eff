// Finite-difference and property checks of the Hamiltonian, its regularisation and derivatives.
#include "moreau/control/hamiltonian.h"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>

#include <cmath>
#include <random>

#include "control/hamiltonian_internal.h"
#include "control/random_network.h"

namespace moreau::control {
namespace {

using testing::RandomProblem;
using testing::RandomVector;

// Relative max-norm difference ‖a − b‖_∞ / max(‖b‖_∞, floor).
double RelDiff(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b, double floor = 1.0) {
  return (a - b).lpNorm<Eigen::Infinity>() / std::max(b.lpNorm<Eigen::Infinity>(), floor);
}

struct Point {
  Eigen::VectorXd z, rho;
};

// Random (z, ρ) near the network's initial state.
Point RandomPoint(const TrackingProblem& problem, std::mt19937& rng) {
  const Eigen::Index n = problem.network().state_size();
  Point p;
  p.z = problem.network().InitialState() + RandomVector(n, 0.1, rng);
  p.rho = RandomVector(n, 1.0, rng);
  return p;
}

class ControlHamiltonianFd : public ::testing::TestWithParam<int> {};

TEST_P(ControlHamiltonianFd, GradientsMatchCentralDifferences) {
  const int d = GetParam();
  std::mt19937 rng(1000 + d);
  for (int trial = 0; trial < 4; ++trial) {
    const TrackingProblem problem = RandomProblem(d, 4, 2, 0.3, rng);
    const Instant instant = MakeInstant(problem, 0.37);
    const Point pt = RandomPoint(problem, rng);
    HamiltonianEval ev, tmp;
    EvaluateRegularizedHamiltonian(problem, instant, pt.z, pt.rho, HamiltonianOrder::kHessian, ev);
    const Eigen::Index n = pt.z.size();
    const double h = 1e-6;
    Eigen::VectorXd fd_z(n), fd_rho(n);
    Eigen::MatrixXd fd_zz(n, n), fd_rz(n, n), fd_rr(n, n);
    for (Eigen::Index i = 0; i < n; ++i) {
      Eigen::VectorXd zp = pt.z, zm = pt.z;
      zp[i] += h;
      zm[i] -= h;
      EvaluateRegularizedHamiltonian(problem, instant, zp, pt.rho, HamiltonianOrder::kGradient,
                                     tmp);
      const double hp = tmp.value;
      const Eigen::VectorXd gzp = tmp.dz, grp = tmp.drho;
      EvaluateRegularizedHamiltonian(problem, instant, zm, pt.rho, HamiltonianOrder::kGradient,
                                     tmp);
      fd_z[i] = (hp - tmp.value) / (2 * h);
      fd_zz.col(i) = (gzp - tmp.dz) / (2 * h);
      fd_rz.col(i) = (grp - tmp.drho) / (2 * h);

      Eigen::VectorXd rp = pt.rho, rm = pt.rho;
      rp[i] += h;
      rm[i] -= h;
      EvaluateRegularizedHamiltonian(problem, instant, pt.z, rp, HamiltonianOrder::kGradient, tmp);
      const double hrp = tmp.value;
      const Eigen::VectorXd grrp = tmp.drho;
      EvaluateRegularizedHamiltonian(problem, instant, pt.z, rm, HamiltonianOrder::kGradient, tmp);
      fd_rho[i] = (hrp - tmp.value) / (2 * h);
      fd_rr.col(i) = (grrp - tmp.drho) / (2 * h);
    }
    EXPECT_LT(RelDiff(ev.dz, fd_z), 1e-6) << "d=" << d << " trial " << trial;
    EXPECT_LT(RelDiff(ev.drho, fd_rho), 1e-6);
    EXPECT_LT(RelDiff(ev.zz, fd_zz), 1e-6);
    EXPECT_LT(RelDiff(ev.rho_z, fd_rz), 1e-6);
    EXPECT_LT(RelDiff(ev.rho_rho, fd_rr), 1e-6);
    // Symmetry of the Hessian blocks and concavity in ρ.
    EXPECT_LT(RelDiff(ev.zz, ev.zz.transpose()), 1e-14);
    EXPECT_LT(RelDiff(ev.rho_rho, ev.rho_rho.transpose()), 1e-14);
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(ev.rho_rho);
    EXPECT_LE(eig.eigenvalues().maxCoeff(), 1e-12 * std::max(1.0, ev.rho_rho.norm()));
  }
}

TEST_P(ControlHamiltonianFd, RhoGradientIsDynamicsAtEffectiveRestLengths) {
  const int d = GetParam();
  std::mt19937 rng(2000 + d);
  const TrackingProblem problem = RandomProblem(d, 3, 2, 0.05, rng);
  const Instant instant = MakeInstant(problem, 0.8);
  const Point pt = RandomPoint(problem, rng);
  HamiltonianEval ev;
  EvaluateRegularizedHamiltonian(problem, instant, pt.z, pt.rho, HamiltonianOrder::kGradient, ev);
  Eigen::VectorXd rest, rate;
  EffectiveRestLengths(problem, instant, pt.z, pt.rho, rest);
  for (int s = 0; s < problem.network().num_springs(); ++s) {
    EXPECT_GE(rest[s], problem.network().spring(s).rest_min - 1e-15);
    EXPECT_LE(rest[s], problem.network().spring(s).rest_max + 1e-15);
  }
  EvaluateDynamics(problem.network(), instant.t, pt.z, rest, rate);
  EXPECT_LT(RelDiff(ev.drho, rate), 1e-13);
  // h^δ = H^δ − ρ·H^δ_ρ equals h plus Σ (S^γ − P S^γ') which is within δ of h.
  const double h = RunningCost(problem, instant, pt.z);
  EXPECT_NEAR(ev.running_cost, h, problem.RegularizationDelta() * 1.0000001);
}

TEST_P(ControlHamiltonianFd, RegularizedIsWithinDeltaAndBangBangIsTheMinimum) {
  const int d = GetParam();
  std::mt19937 rng(3000 + d);
  const TrackingProblem problem = RandomProblem(d, 4, 1, 0.02, rng);
  const Instant instant = MakeInstant(problem, 0.1);
  const double delta = problem.RegularizationDelta();
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int trial = 0; trial < 20; ++trial) {
    const Point pt = RandomPoint(problem, rng);
    HamiltonianEval ev;
    EvaluateRegularizedHamiltonian(problem, instant, pt.z, pt.rho, HamiltonianOrder::kValue, ev);
    Eigen::VectorXd minimiser, rate;
    const double exact = EvaluateHamiltonian(problem, instant, pt.z, pt.rho, &minimiser);
    EXPECT_LE(std::abs(exact - ev.value), delta * (1 + 1e-9));
    // No admissible control does better than the bang-bang minimiser.
    const SpringNetwork& net = problem.network();
    for (int k = 0; k < 10; ++k) {
      Eigen::VectorXd rest(net.num_springs());
      for (int s = 0; s < net.num_springs(); ++s) {
        rest[s] =
            net.spring(s).rest_min + u(rng) * (net.spring(s).rest_max - net.spring(s).rest_min);
      }
      EvaluateDynamics(net, instant.t, pt.z, rest, rate);
      const double candidate = pt.rho.dot(rate) + RunningCost(problem, instant, pt.z);
      EXPECT_GE(candidate, exact - 1e-12 * std::max(1.0, std::abs(exact)));
    }
    EvaluateDynamics(net, instant.t, pt.z, minimiser, rate);
    EXPECT_NEAR(pt.rho.dot(rate) + RunningCost(problem, instant, pt.z), exact,
                1e-12 * std::max(1.0, std::abs(exact)));
  }
}

TEST_P(ControlHamiltonianFd, ClosedFormSpringTermsMatchTheJets) {
  // The closed-form spring derivatives (spring_term.h) against the original forward-mode jets,
  // on random networks with fixed nodes, at random points and far from the switching point.
  const int d = GetParam();
  std::mt19937 rng(5000 + d);
  for (int trial = 0; trial < 6; ++trial) {
    const TrackingProblem problem = RandomProblem(d, 4, 2, trial < 3 ? 0.3 : 1e-3, rng);
    const Instant instant = MakeInstant(problem, 0.21 * trial);
    const Point pt = RandomPoint(problem, rng);
    for (HamiltonianOrder order :
         {HamiltonianOrder::kValue, HamiltonianOrder::kGradient, HamiltonianOrder::kHessian}) {
      HamiltonianEval closed, jets;
      EvaluateRegularizedHamiltonian(problem, instant, pt.z, pt.rho, order, closed);
      internal::EvaluateRegularizedHamiltonianWithJets(problem, instant, pt.z, pt.rho, order, jets);
      EXPECT_NEAR(closed.value, jets.value, 1e-13 * std::max(1.0, std::abs(jets.value)));
      EXPECT_NEAR(closed.running_cost, jets.running_cost,
                  1e-12 * std::max(1.0, std::abs(jets.value)));
      EXPECT_LT(RelDiff(closed.dz, jets.dz), 1e-13) << "d = " << d << ", trial " << trial;
      EXPECT_LT(RelDiff(closed.drho, jets.drho), 1e-13);
      if (order != HamiltonianOrder::kHessian) continue;
      EXPECT_LT(RelDiff(closed.zz, jets.zz), 1e-13) << "d = " << d << ", trial " << trial;
      EXPECT_LT(RelDiff(closed.rho_z, jets.rho_z), 1e-13);
      EXPECT_LT(RelDiff(closed.rho_rho, jets.rho_rho), 1e-13);
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Dimensions, ControlHamiltonianFd, ::testing::Values(1, 2, 3));

TEST(ControlSmoothMin, OverflowSafeAndConsistent) {
  const double lo = 0.5, hi = 1.515, gamma = 1e-4;
  // Far from 0 the regularised minimum approaches P L∓ − ½ ln2 (L+ − L−) γ sign… without
  // overflowing (cosh(1e6) would overflow).
  for (double p : {1e2, -1e2, 1e3, -1e3}) {
    const SmoothMin s = RegularizedSpringMin(p, lo, hi, gamma);
    ASSERT_TRUE(std::isfinite(s.value));
    const double exact = std::min(p * lo, p * hi);
    EXPECT_NEAR(std::abs(s.value - exact), 0.5 * std::log(2.0) * (hi - lo) * gamma, 1e-12);
    EXPECT_NEAR(s.slope, p > 0 ? lo : hi, 1e-15);
    EXPECT_EQ(s.curvature, 0.0 * s.curvature);  // finite
  }
  // At P = 0 it coincides with S (integration constant 0) and the slope is the midpoint.
  const SmoothMin z = RegularizedSpringMin(0.0, lo, hi, gamma);
  EXPECT_EQ(z.value, 0.0);
  EXPECT_DOUBLE_EQ(z.slope, 0.5 * (lo + hi));
  // Finite differences of value and slope near the switching point.
  for (double p : {-3e-4, -5e-5, 0.0, 2e-5, 1e-4}) {
    const double h = 1e-9;
    const SmoothMin sp = RegularizedSpringMin(p + h, lo, hi, gamma);
    const SmoothMin sm = RegularizedSpringMin(p - h, lo, hi, gamma);
    const SmoothMin s = RegularizedSpringMin(p, lo, hi, gamma);
    EXPECT_NEAR((sp.value - sm.value) / (2 * h), s.slope, 1e-6 * std::abs(s.slope));
    EXPECT_NEAR((sp.slope - sm.slope) / (2 * h), s.curvature, 1e-6 * std::abs(s.curvature) + 1e-6);
  }
}

TEST(ControlDelta, ThesisOneDimensionalValue) {
  NetworkNode wall;
  wall.fixed = true;
  NetworkNode mass;
  mass.mass = 100;
  mass.position[0] = 1.0;
  SpringNetwork net(1, {wall, mass}, {NetworkSpring{0, 1, 10, 20, 0.5, 1.515}});
  TrackingProblem problem(
      net, 2.0,
      [](double, double* x, double* v, double* w) {
        x[0] = 1;
        v[0] = 0;
        w[0] = 1;
      },
      {}, 1e-4);
  EXPECT_NEAR(problem.RegularizationDelta(), 3.51772e-5, 5e-11);
}

}  // namespace
}  // namespace moreau::control
