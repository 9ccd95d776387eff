// The discretisation (29)/(41): Jacobian against finite differences, the Riccati solve against
// sparse LU, Newton and the fixed-point sweep on small random problems.
#include "moreau/control/pontryagin.h"

#include <gtest/gtest.h>

#include <Eigen/SparseLU>
#include <random>

#include "control/random_network.h"
#include "moreau/control/continuation.h"
#include "moreau/control/linear_solver.h"
#include "moreau/control/newton.h"

namespace moreau::control {
namespace {

using testing::RandomProblem;
using testing::RandomVector;

Eigen::VectorXd RandomUnknowns(const PontryaginDiscretization& disc, std::mt19937& rng) {
  Eigen::MatrixXd z(disc.state_size(), disc.steps() + 1), rho(disc.state_size(), disc.steps() + 1);
  for (int n = 0; n <= disc.steps(); ++n) {
    z.col(n) = disc.initial_state() + RandomVector(disc.state_size(), 0.1, rng);
    rho.col(n) = RandomVector(disc.state_size(), 1.0, rng);
  }
  return disc.Pack(z, rho);
}

class ControlPontryaginByDimension : public ::testing::TestWithParam<int> {};

TEST_P(ControlPontryaginByDimension, JacobianMatchesFiniteDifferences) {
  const int d = GetParam();
  std::mt19937 rng(4000 + d);
  for (bool terminal : {false, true}) {
    const TrackingProblem problem = RandomProblem(d, 3, 2, 0.3, rng, terminal);
    const PontryaginDiscretization disc(problem, 4);
    const Eigen::VectorXd y = RandomUnknowns(disc, rng);
    PontryaginWorkspace ws;
    Eigen::VectorXd f, fp, fm;
    EvaluateResidualAndJacobian(disc, y, ws, f);
    const Eigen::MatrixXd jac = Eigen::MatrixXd(AssembleSparseJacobian(disc, ws.jacobian));
    Eigen::MatrixXd fd(jac.rows(), jac.cols());
    const double h = 1e-6;
    PontryaginWorkspace ws2;
    for (Eigen::Index i = 0; i < y.size(); ++i) {
      Eigen::VectorXd yp = y, ym = y;
      yp[i] += h;
      ym[i] -= h;
      EvaluateResidual(disc, yp, ws2, fp);
      EvaluateResidual(disc, ym, ws2, fm);
      fd.col(i) = (fp - fm) / (2 * h);
    }
    const double rel = (jac - fd).lpNorm<Eigen::Infinity>() / fd.lpNorm<Eigen::Infinity>();
    EXPECT_LT(rel, 1e-6) << "d = " << d << ", terminal cost " << terminal;
  }
}

TEST_P(ControlPontryaginByDimension, ResidualAndJacobianDoNotDependOnThreads) {
  // Each time step writes only its own blocks: bit-identical for 1, 2 and 3 threads (N >= 64,
  // so that the parallel region is used).
  const int d = GetParam();
  std::mt19937 rng(4500 + d);
  const TrackingProblem problem = RandomProblem(d, 3, 2, 0.3, rng, true);
  const PontryaginDiscretization disc(problem, 97);
  const Eigen::VectorXd y = RandomUnknowns(disc, rng);
  PontryaginWorkspace serial;
  serial.threads = 1;
  Eigen::VectorXd f1, f;
  const double norm1 = EvaluateResidualAndJacobian(disc, y, serial, f1);
  for (int threads : {2, 3}) {
    PontryaginWorkspace ws;
    ws.threads = threads;
    EXPECT_EQ(EvaluateResidualAndJacobian(disc, y, ws, f), norm1);
    EXPECT_TRUE(f == f1) << threads << " threads";
    for (std::size_t k = 0; k < serial.jacobian.A.size(); ++k) {
      ASSERT_TRUE(ws.jacobian.A[k] == serial.jacobian.A[k]) << "step " << k;
      ASSERT_TRUE(ws.jacobian.B[k] == serial.jacobian.B[k]) << "step " << k;
      ASSERT_TRUE(ws.jacobian.C[k] == serial.jacobian.C[k]) << "step " << k;
    }
    EXPECT_EQ(EvaluateResidual(disc, y, ws, f), norm1);
    EXPECT_TRUE(f == f1);
  }
}

TEST_P(ControlPontryaginByDimension, RiccatiSolveAgreesWithSparseLu) {
  const int d = GetParam();
  std::mt19937 rng(5000 + d);
  for (int steps : {1, 7, 60}) {
    // 4 free nodes: n_z = 8, 16, 24 (the split path at d = 3); 5 in d = 2 (n_z = 20, split).
    const TrackingProblem problem =
        RandomProblem(d, d == 2 && steps == 60 ? 5 : 4, 2, 0.2, rng, true);
    const PontryaginDiscretization disc(problem, steps);
    const Eigen::VectorXd y = RandomUnknowns(disc, rng);
    PontryaginWorkspace ws;
    Eigen::VectorXd f;
    EvaluateResidualAndJacobian(disc, y, ws, f);
    const Eigen::VectorXd rhs = RandomVector(y.size(), 1.0, rng);
    // The scheme's Jacobian (split path), then one whose B_0 has a position entry and whose A_0
    // has a position row other than [I, Δt I] (the general path).
    for (bool split : {true, false}) {
      if (!split) {
        ws.jacobian.B[0](0, 0) = -0.1;
        ws.jacobian.A[0](0, 1) = 0.05;
      }
      RiccatiSolver riccati;
      SparseLuSolver lu;
      ASSERT_TRUE(riccati.Factorize(disc, ws.jacobian));
      EXPECT_EQ(riccati.split(), split && disc.state_size() >= RiccatiSolver::kSplitMinStateSize);
      ASSERT_TRUE(lu.Factorize(disc, ws.jacobian));
      Eigen::VectorXd x1, x2;
      riccati.Solve(rhs, x1);
      lu.Solve(rhs, x2);
      EXPECT_LT((x1 - x2).norm() / x2.norm(), 1e-10) << "N = " << steps << ", split " << split;
      // And it really solves the system.
      const Eigen::SparseMatrix<double> jac = AssembleSparseJacobian(disc, ws.jacobian);
      EXPECT_LT((jac * x1 - rhs).norm() / rhs.norm(), 1e-10);
    }
  }
}

TEST_P(ControlPontryaginByDimension, NewtonConvergesQuadraticallyFromFixedPointGuess) {
  const int d = GetParam();
  std::mt19937 rng(6000 + d);
  const TrackingProblem problem = RandomProblem(d, 3, 1, 0.5, rng, true);
  const PontryaginDiscretization disc(problem, 40);
  Eigen::VectorXd y;
  FixedPointOptions fp;
  fp.sweeps = 3;
  const FixedPointSummary fps = FixedPointSweep(disc, ReferenceGuess(disc), fp, y);
  EXPECT_TRUE(fps.ok()) << fps.message;
  EXPECT_EQ(fps.sweeps, 3);
  for (LinearSolverType type : {LinearSolverType::kRiccati, LinearSolverType::kSparseLU}) {
    Eigen::VectorXd yy = y;
    NewtonOptions options;
    options.linear_solver = type;
    const NewtonSummary s = SolveNewton(disc, options, yy);
    ASSERT_TRUE(s.ok()) << s.BriefReport();
    EXPECT_LE(s.final_residual, 1e-10);
    EXPECT_EQ(s.residual_norms.size(), static_cast<std::size_t>(s.iterations) + 1);
    EXPECT_EQ(s.step_lengths.size(), static_cast<std::size_t>(s.iterations));
    EXPECT_GT(s.factorize_seconds, 0.0);
    EXPECT_NE(s.BriefReport().find("converged"), std::string::npos);
    EXPECT_NE(s.FullReport().find("factorize"), std::string::npos);
    EXPECT_LE(s.iterations, 12);
    // Quadratic convergence: once small, the residual roughly squares.
    const auto& r = s.residual_norms;
    ASSERT_GE(r.size(), 3u);
    const double a = r[r.size() - 3], b = r[r.size() - 2];
    if (a < 1e-2 && a > 1e-7) {
      EXPECT_LT(b, 1e3 * a * a) << s.BriefReport();
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Dimensions, ControlPontryaginByDimension, ::testing::Values(1, 2, 3));

TEST(ControlPontryagin, DiscreteValueIsTheCostOfTheDiscreteTrajectory) {
  // With z^{n+1} = z^n + Δt H_ρ = z^n + Δt f(z^n, L^γ) at a solution, ū = Σ h^δ Δt + g and
  // h^δ = h + Σ_s (S^γ − P S^γ'), so ū − Σ h(z^n) Δt − g is within T δ.
  std::mt19937 rng(77);
  const TrackingProblem problem = RandomProblem(2, 3, 1, 0.05, rng, true);
  const PontryaginDiscretization disc(problem, 50);
  Eigen::VectorXd y;
  FixedPointSweep(disc, ReferenceGuess(disc), FixedPointOptions{}, y);
  const NewtonSummary s = SolveNewton(disc, NewtonOptions{}, y);
  ASSERT_TRUE(s.ok()) << s.BriefReport();
  PontryaginWorkspace ws;
  const double value = DiscreteValue(disc, y, ws);
  Eigen::MatrixXd z, rho;
  disc.Unpack(y, z, rho);
  double cost = 0.0;
  for (int n = 0; n < disc.steps(); ++n) {
    cost += RunningCost(problem, disc.instant(n), z.col(n)) * disc.dt();
  }
  cost += TerminalCost(problem, disc.instant(disc.steps()), z.col(disc.steps()));
  EXPECT_LE(std::abs(value - cost), problem.horizon() * problem.RegularizationDelta());
  EXPECT_GT(std::abs(value - cost), 0.0);
  // The state trajectory is the forward Euler trajectory of the effective controls.
  const Eigen::MatrixXd controls = EffectiveControls(disc, y);
  Eigen::VectorXd rate;
  for (int n = 0; n < disc.steps(); ++n) {
    EvaluateDynamics(problem.network(), disc.instant(n).t, z.col(n), controls.col(n), rate);
    EXPECT_LT((z.col(n + 1) - z.col(n) - disc.dt() * rate).lpNorm<Eigen::Infinity>(), 1e-10);
  }
}

TEST(ControlPontryagin, NewtonDivergenceIsReportedNotThrown) {
  std::mt19937 rng(78);
  const TrackingProblem problem = RandomProblem(2, 3, 1, 0.05, rng, true);
  const PontryaginDiscretization disc(problem, 20);
  Eigen::VectorXd y = Eigen::VectorXd::Constant(disc.unknowns(), 1e200);
  const NewtonSummary s = SolveNewton(disc, NewtonOptions{}, y);
  EXPECT_FALSE(s.ok());
  EXPECT_EQ(s.termination, Termination::kDiverged);
  EXPECT_FALSE(s.message.empty());
  NewtonOptions few;
  few.max_iterations = 1;
  Eigen::VectorXd y2;
  FixedPointSweep(disc, ReferenceGuess(disc), FixedPointOptions{}, y2);
  PontryaginWorkspace ws;
  Eigen::VectorXd f;
  const double before = EvaluateResidual(disc, y2, ws, f);
  const NewtonSummary s2 = SolveNewton(disc, few, y2);
  EXPECT_EQ(s2.termination, Termination::kMaxIterations);
  // The best iterate is kept: it is no worse than the start.
  EXPECT_LE(EvaluateResidual(disc, y2, ws, f), before);
}

}  // namespace
}  // namespace moreau::control
