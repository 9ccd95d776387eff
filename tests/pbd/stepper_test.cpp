// Time steppers: counting, options, failure handling, and the study helpers.
#include "moreau/pbd/stepper.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "moreau/common/error.h"
#include "moreau/pbd/study.h"

namespace moreau::pbd {
namespace {

// The exterior of two unit balls in the plane; S = S_1 ∩ S_2.
std::unique_ptr<ConstraintSetList> TwoBalls() {
  auto list = std::make_unique<ConstraintSetList>(2);
  list->Add(std::make_unique<BallExterior>(Eigen::Vector2d(0.0, -1.5), 1.0));
  list->Add(std::make_unique<BallExterior>(Eigen::Vector2d(1.2, -1.5), 1.0));
  return list;
}

TEST(Stepper, CountsConstraintEvaluations) {
  const ConstantDrift drift(Eigen::Vector2d(0.1, -1.0));
  const Vector x0 = Eigen::Vector2d(0.3, 0.2);
  for (Method m : {Method::kPBD, Method::kPNGS, Method::kPGS, Method::kPenalty}) {
    auto sets = TwoBalls();
    StepperOptions o;
    o.method = m;
    o.h = 0.01;
    const SimulationSummary s = Simulate(drift, *sets, o, x0, 1.0);
    ASSERT_TRUE(s.ok());
    EXPECT_EQ(s.counters.steps, 100);
    if (m == Method::kPBD || m == Method::kPenalty) {
      EXPECT_EQ(s.counters.constraint_evaluations, 2 * 100);
      EXPECT_EQ(s.counters.sweeps, 100);
    } else if (m == Method::kPNGS) {
      EXPECT_EQ(s.counters.constraint_evaluations, 2 * s.counters.sweeps);
      EXPECT_GT(s.counters.sweeps, 100);
    } else {
      // Linearisation (m per step) plus m per sweep.
      EXPECT_EQ(s.counters.constraint_evaluations, 2 * 100 + 2 * s.counters.sweeps);
    }
  }
}

TEST(Stepper, PngsReachesTheIntersection) {
  // Started inside both balls, PNGS with tight tolerances ends in S; one PBD sweep need not.
  auto sets = TwoBalls();
  StepperOptions o;
  o.method = Method::kPNGS;
  o.h = 0.5;
  o.abstol = 1e-14;
  o.reltol = 0.0;
  const ConstantDrift drift(Eigen::Vector2d(0.0, -1.0));
  TimeStepper stepper(drift, *sets, o);
  Vector x = Eigen::Vector2d(0.6, -0.3);
  stepper.Step(x);
  EXPECT_LE(sets->MaxViolation(x), 1e-12);
  EXPECT_EQ(stepper.counters().capped_steps, 0);
}

TEST(Stepper, MaxSweepsCapIsReported) {
  auto sets = TwoBalls();
  StepperOptions o;
  o.method = Method::kPNGS;
  o.h = 0.5;
  o.max_sweeps = 1;
  o.abstol = 1e-15;
  o.reltol = 0.0;
  const ConstantDrift drift(Eigen::Vector2d(0.0, -1.0));
  TimeStepper stepper(drift, *sets, o);
  Vector x = Eigen::Vector2d(0.6, -0.3);
  stepper.Step(x);
  EXPECT_EQ(stepper.counters().capped_steps, 1);
}

TEST(Stepper, NonFiniteStateStopsAndKeepsTheLastGoodState) {
  // f blows up at t = 0.25: the summary names the step, the state is the last finite one.
  const FunctionDrift drift([](ConstVectorRef x, VectorRef out) {
    out.setConstant(x[0] >= 0.25 - 1e-12 ? std::numeric_limits<double>::infinity() : 1.0);
  });
  auto sets = std::make_unique<ConstraintSetList>(1);
  sets->Add(std::make_unique<HalfSpace>(Vector::Ones(1), -10.0));
  StepperOptions o;
  o.h = 0.05;
  Vector final_state;
  const SimulationSummary s = Simulate(drift, *sets, o, Vector::Zero(1), 1.0, {}, &final_state);
  EXPECT_FALSE(s.ok());
  EXPECT_EQ(s.termination, Termination::kNonFinite);
  EXPECT_EQ(s.failed_step, 6);
  EXPECT_NEAR(final_state[0], 0.25, 1e-12);
  EXPECT_NE(s.message.find("step 6"), std::string::npos) << s.message;
}

TEST(Stepper, AnObserverThatReturnsFalseStopsAfterTheStepItSaw) {
  const ConstantDrift drift(Vector::Ones(1));
  auto sets = std::make_unique<ConstraintSetList>(1);
  sets->Add(std::make_unique<HalfSpace>(Vector::Ones(1), -10.0));
  StepperOptions o;
  o.h = 0.1;
  std::int64_t last_seen = -1;
  Vector x;
  const SimulationSummary s = Simulate(
      drift, *sets, o, Vector::Zero(1), 1.0,
      [&](std::int64_t k, double, ConstVectorRef) {
        last_seen = k;
        return k < 3;
      },
      &x);
  EXPECT_EQ(s.termination, Termination::kInterrupted);
  EXPECT_EQ(last_seen, 3);
  EXPECT_NEAR(x[0], 0.3, 1e-12);  // x' = 1 from 0: three steps taken
  EXPECT_NEAR(s.final_time, 0.3, 1e-12);
  // Returning false at the last step is a completed run.
  const SimulationSummary full = Simulate(
      drift, *sets, o, Vector::Zero(1), 1.0, [](std::int64_t, double, ConstVectorRef) {
        return false;
      });
  EXPECT_EQ(full.termination, Termination::kInterrupted);  // stopped at step 0
  const SimulationSummary last = Simulate(
      drift, *sets, o, Vector::Zero(1), 1.0,
      [](std::int64_t k, double, ConstVectorRef) { return k < 10 ? true : false; });
  EXPECT_TRUE(last.ok());
}

TEST(Stepper, OptionsAreValidated) {
  auto sets = TwoBalls();
  const ConstantDrift drift(Eigen::Vector2d(0.0, -1.0));
  const auto bad = [&](auto mutate) {
    StepperOptions o;
    mutate(o);
    EXPECT_THROW(TimeStepper(drift, *sets, o), InputError);
  };
  bad([](StepperOptions& o) { o.h = 0.0; });
  bad([](StepperOptions& o) { o.h = -1.0; });
  bad([](StepperOptions& o) { o.abstol = -1.0; });
  bad([](StepperOptions& o) { o.abstol = 0.0; o.reltol = 0.0; });
  bad([](StepperOptions& o) { o.max_sweeps = 0; });
  bad([](StepperOptions& o) { o.penalty = 0.0; });
  EXPECT_THROW(StepCount(1.0, 0.3), InputError);
  EXPECT_EQ(StepCount(1.0, 0.125), 8);
  EXPECT_THROW(ParseMethod("rk4"), InputError);
  for (Method m : {Method::kPBD, Method::kPNGS, Method::kPGS, Method::kPenalty}) {
    EXPECT_EQ(ParseMethod(MethodName(m)), m);
  }
  EXPECT_THROW(ParseMethodSpec("penalty:-3"), InputError);
  EXPECT_THROW(ParseMethodSpec("pbd:3"), InputError);
  EXPECT_EQ(ParseMethodSpec("penalty:250").penalty, 250.0);
}

TEST(Stepper, DriftJacobiansMatchFiniteDifferences) {
  const Vector center = Eigen::Vector3d(0.1, -0.2, 0.3);
  const HarmonicDrift harmonic(2.5, center);
  const ConstantDrift constant(Eigen::Vector3d(1.0, 2.0, 3.0));
  const Vector x = Eigen::Vector3d(0.7, 0.4, -0.9);
  for (const Drift* d : {static_cast<const Drift*>(&harmonic), static_cast<const Drift*>(&constant)}) {
    Eigen::MatrixXd J;
    ASSERT_TRUE(d->Jacobian(x, &J));
    Eigen::MatrixXd fd(3, 3);
    const double eps = 1e-6;
    for (int c = 0; c < 3; ++c) {
      Vector xp = x, xm = x, fp(3), fm(3);
      xp[c] += eps;
      xm[c] -= eps;
      d->Evaluate(xp, fp);
      d->Evaluate(xm, fm);
      fd.col(c) = (fp - fm) / (2 * eps);
    }
    EXPECT_LE((J - fd).norm(), 1e-8 * std::max(1.0, J.norm()));
  }
}

TEST(Stepper, PenaltyDirectionIsDistanceTimesGradient) {
  // Σ_j (x − P_j x) = Σ_j d_j ∇d_j: compare with finite differences of ½ Σ_j d_j².
  auto sets = TwoBalls();
  const Vector x = Eigen::Vector2d(0.6, -0.9);
  Vector dir = Vector::Zero(2);
  sets->AddPenaltyDirection(x, dir);
  const auto energy = [&](const Vector& y) {
    double e = 0.0;
    for (int j = 0; j < 2; ++j) e += 0.5 * std::pow(sets->set(j).Distance(y), 2);
    return e;
  };
  const double eps = 1e-6;
  for (int c = 0; c < 2; ++c) {
    Vector xp = x, xm = x;
    xp[c] += eps;
    xm[c] -= eps;
    EXPECT_NEAR(dir[c], (energy(xp) - energy(xm)) / (2 * eps), 1e-8);
  }
}

TEST(Study, ObservedOrderAndBudgetInterpolation) {
  EXPECT_NEAR(ObservedOrder({0.1, 0.05, 0.025}, {3e-1, 1.5e-1, 0.75e-1}), 1.0, 1e-12);
  EXPECT_NEAR(ObservedOrder({0.1, 0.05, 0.025}, {1e-2, 2.5e-3, 6.25e-4}), 2.0, 1e-12);
  EXPECT_TRUE(std::isnan(ObservedOrder({0.1}, {1.0})));
  std::vector<StudyRow> rows(2);
  rows[0].label = rows[1].label = "pbd";
  rows[0].constraint_evaluations = 100;
  rows[0].error = 1e-2;
  rows[1].constraint_evaluations = 10000;
  rows[1].error = 1e-4;
  EXPECT_NEAR(ErrorAtBudget(rows, "pbd", 1000), 1e-3, 1e-15);
  EXPECT_TRUE(std::isnan(ErrorAtBudget(rows, "pbd", 1e6)));
  SampledTrajectory traj(0.5);
  traj.Append(Vector::Zero(1));
  traj.Append(Vector::Ones(1));
  EXPECT_DOUBLE_EQ(traj.At(0.25)[0], 0.5);
  EXPECT_THROW(traj.At(0.75), InputError);
}

}  // namespace
}  // namespace moreau::pbd
