// The thesis examples: the 1D oscillator of 5.1/9.1 (Theorem 5.1 bounds, convergence in N) and
// the arm model of 9.2 (continuation, convergence of the trajectory in N, tracking).
#include "moreau/control/examples.h"

#include <gtest/gtest.h>

#include <cmath>

#include "moreau/control/continuation.h"
#include "moreau/control/refinement_study.h"
#include "moreau/control/value_error_bounds.h"

namespace moreau::control {
namespace {

TEST(ControlOscillator, ThesisSection91Reproduced) {
  const OscillatorExample ex;  // the defaults are the values of section 9.1
  const ProblemFamily family = [&ex](double p) { return MakeOscillatorProblem(ex, p); };
  EXPECT_NEAR(family(1.0).RegularizationDelta(), 3.51772e-5, 1e-10);
  RefinementStudyOptions options;
  options.steps = {500, 1000, 1500, 2000, 2500, 3000, 3500, 4000};
  options.compare_samples = 500;
  options.continuation.newton.residual_tolerance = 1e-13;
  const RefinementStudySummary study = RunRefinementStudy(family, options);
  EXPECT_TRUE(study.ok()) << study.message;
  const std::vector<RefinementLevel>& levels = study.levels;
  ASSERT_EQ(levels.size(), options.steps.size());
  const RefinementLevel& finest = levels.back();
  for (std::size_t i = 0; i < levels.size(); ++i) {
    const RefinementLevel& l = levels[i];
    EXPECT_TRUE(l.ok()) << "N = " << l.steps << ": " << l.message;
    EXPECT_LT(l.residual, 1e-10) << "N = " << l.steps;
    EXPECT_LE(l.newton_iterations, 8);
    const ValueErrorBounds b =
        Theorem51Bounds({0.352, 2.00069, 0.0, 3.51772e-5}, ex.horizon, ex.horizon / l.steps);
    const double diff = finest.value - l.value;  // u − ū_N with u ≈ ū_4000
    EXPECT_GE(diff, b.lower) << "N = " << l.steps;
    EXPECT_LE(diff, b.upper) << "N = " << l.steps;
    if (i + 1 < levels.size()) {
      EXPECT_GT(l.diff_finest, 0.0);
      if (i > 0) {
        // Values approach u_4000 monotonically and the displacement converges in max norm.
        EXPECT_LT(std::abs(finest.value - l.value), std::abs(finest.value - levels[i - 1].value));
        EXPECT_LT(l.diff_finest, levels[i - 1].diff_finest) << "N = " << l.steps;
      }
    }
  }
  // First order in Δt: halving Δt (500 → 1000 → 2000) halves the change of ū.
  const double d1 = levels[1].value - levels[0].value;
  const double d2 = levels[3].value - levels[1].value;
  EXPECT_GT(d1 / d2, 1.6);
  EXPECT_LT(d1 / d2, 2.4);
  // The mass follows the reference to 1.01 and stops there.
  EXPECT_NEAR(finest.z(0, finest.steps), ex.target, 1e-4);
  EXPECT_LT(finest.tracking_rms, 2e-4);
}

TEST(ControlOscillator, DampingMakesTheFixedPointSweepConverge) {
  // Section 7.1 on the 1D example with γ = 1e−2: the plain sweep (θ = 1) does not converge,
  // the damped one (θ = 0.3) contracts monotonically to a solution of F(y) = 0. (With
  // γ = 1e−4 neither converges: the effective controls switch; that is why Newton is used.)
  OscillatorExample ex;
  ex.gamma = 1e-2;
  const TrackingProblem problem = MakeOscillatorProblem(ex, 1.0);
  const PontryaginDiscretization disc(problem, 400);
  FixedPointOptions options;
  options.sweeps = 60;
  options.tolerance = 1e-13;
  options.damping = 1.0;
  Eigen::VectorXd y_plain, y;
  const FixedPointSummary plain = FixedPointSweep(disc, ReferenceGuess(disc), options, y_plain);
  EXPECT_GT(plain.change.back(), plain.change.front());
  options.damping = 0.3;
  const FixedPointSummary s = FixedPointSweep(disc, ReferenceGuess(disc), options, y);
  ASSERT_TRUE(s.ok()) << s.message;
  ASSERT_GE(s.change.size(), 10u);
  for (std::size_t i = 1; i < s.change.size(); ++i) EXPECT_LT(s.change[i], s.change[i - 1]);
  PontryaginWorkspace ws;
  Eigen::VectorXd f;
  EXPECT_LT(EvaluateResidual(disc, y, ws, f), 1e-11);
  // Newton from there agrees with Newton from the plain backward sweep.
  Eigen::VectorXd y1 = y, y2;
  FixedPointSweep(disc, ReferenceGuess(disc), FixedPointOptions{}, y2);
  NewtonOptions newton;
  newton.residual_tolerance = 1e-14;
  ASSERT_TRUE(SolveNewton(disc, newton, y1).ok());
  ASSERT_TRUE(SolveNewton(disc, newton, y2).ok());
  EXPECT_LT((y1 - y2).lpNorm<Eigen::Infinity>(), 1e-12);
}

// The continuation of examples/control/arm_2d.toml.
ContinuationOptions ArmContinuation() {
  ContinuationOptions o;
  o.path_start = 0.1;
  o.path_increase = 0.5;
  o.stiffness_start = 0.5;
  o.stiffness_increase = 0.5;
  o.gamma_start = 1.0;
  o.gamma_decrease = 0.1;
  o.max_solves = 200;
  return o;
}

TEST(ControlArm, ModelMatchesPreSymbolic) {
  const ArmExample ex;
  const TrackingProblem problem = MakeArmProblem(ex, 1.0);
  const SpringNetwork& net = problem.network();
  EXPECT_EQ(net.num_nodes(), 6);
  EXPECT_EQ(net.num_free(), 4);
  EXPECT_EQ(net.num_springs(), 8);
  EXPECT_EQ(net.state_size(), 16);
  // Initial configuration (main.m, Global_X.init): nodes 1..4 at (6,1), (6,0), (3,1), (3,0).
  const double expected[4][2] = {{6, 1}, {6, 0}, {3, 1}, {3, 0}};
  for (int j = 0; j < 4; ++j) {
    EXPECT_NEAR(net.node(j).position[0], expected[j][0], 1e-14);
    EXPECT_NEAR(net.node(j).position[1], expected[j][1], 1e-14);
    EXPECT_EQ(net.node(j).mass, 3.0);
  }
  EXPECT_TRUE(net.node(4).fixed);
  EXPECT_TRUE(net.node(5).fixed);
  for (const NetworkSpring& s : net.springs()) {
    EXPECT_EQ(s.stiffness, 20.0);
    EXPECT_EQ(s.damping, 40.0);
    EXPECT_NEAR(s.rest_max / s.rest_min, 3.0, 1e-12);  // (1 + ½) / (1 − ½)
  }
  // The reference keeps the bone geometry: |3–4| = |1–2| = 1 at all times, and it is periodic.
  double x[8], v[8], x0[8], v0[8];
  ArmReference(ex, 1.0, 0.0, x0, v0);
  for (double t : {0.0, 7.5, 15.0, 22.5, 30.0}) {
    ArmReference(ex, 1.0, t, x, v);
    EXPECT_NEAR(std::hypot(x[0] - x[2], x[1] - x[3]), 1.0, 1e-12);
    EXPECT_NEAR(std::hypot(x[4] - x[6], x[5] - x[7]), 1.0, 1e-12);
  }
  ArmReference(ex, 1.0, 30.0, x, v);
  for (int i = 0; i < 8; ++i) EXPECT_NEAR(x[i], x0[i], 1e-12);
  // Reference velocities are the time derivatives of the positions.
  const double h = 1e-6;
  double xp[8], xm[8], vt[8];
  ArmReference(ex, 1.0, 11.0 + h, xp, vt);
  ArmReference(ex, 1.0, 11.0 - h, xm, vt);
  ArmReference(ex, 1.0, 11.0, x, v);
  for (int i = 0; i < 8; ++i) EXPECT_NEAR((xp[i] - xm[i]) / (2 * h), v[i], 1e-8);
}

TEST(ControlArm, SolvesDirectlyAtSmallN) {
  // Cheap enough for the sanitizer build: N = 64 at the target parameters.
  const ArmExample ex;
  const ProblemFamily family = [&ex](double p) { return MakeArmProblem(ex, p); };
  Eigen::VectorXd y;
  const ContinuationSummary s = SolveWithContinuation(family, 64, ContinuationOptions{}, y);
  ASSERT_TRUE(s.ok()) << s.BriefReport();
  EXPECT_LT(s.last_newton.final_residual, 1e-10);
}

// Controls of the target problem after a solve from the documented start with `options`.
Eigen::MatrixXd ArmControls(const ProblemFamily& family, int steps,
                            const ContinuationOptions& options, ContinuationSummary& summary) {
  Eigen::VectorXd y;
  summary = SolveWithContinuation(family, steps, options, y);
  const PontryaginDiscretization disc(family(1.0), steps);
  PontryaginWorkspace ws;
  Eigen::VectorXd f;
  EXPECT_LT(EvaluateResidual(disc, y, ws, f), 1e-10);
  return EffectiveControls(disc, y);
}

TEST(ControlArmSlow, DefaultCoarseToFineReachesThePlainPathsSolution) {
  // N = 256 from the documented start with the default grids: the stages before gamma on 64
  // steps, prolonged at gamma = 1 through 128 to 256, the gamma stages on 256. Against every
  // stage on 256 steps (the plain path): the same root, controls within 1e-8.
  const ArmExample ex;
  const ProblemFamily family = [&ex](double p) { return MakeArmProblem(ex, p); };
  ContinuationOptions plain = ArmContinuation();
  plain.coarse_steps = 0;
  ContinuationSummary sp, sc;
  const Eigen::MatrixXd controls_plain = ArmControls(family, 256, plain, sp);
  const Eigen::MatrixXd controls_c2f = ArmControls(family, 256, ArmContinuation(), sc);
  ASSERT_TRUE(sp.ok()) << sp.BriefReport();
  ASSERT_TRUE(sc.ok()) << sc.BriefReport();
  ASSERT_EQ(sp.grids.size(), 1u);
  ASSERT_EQ(sc.grids.size(), 3u) << sc.ToJson()["grids"].dump();
  EXPECT_EQ(sc.grids[0].steps, 64);
  EXPECT_EQ(sc.grids[1].steps, 128);
  EXPECT_EQ(sc.grids[2].steps, 256);
  for (const ContinuationRecord& r : sc.path) {
    // Every gamma stage on the requested grid; every solve before it on 64 steps.
    if (r.stage == "gamma") {
      EXPECT_EQ(r.steps, 256);
    } else if (r.stage == "refine") {
      EXPECT_EQ(r.gamma, 1.0);
    } else {
      EXPECT_EQ(r.steps, 64) << r.stage;
    }
  }
  EXPECT_EQ(sc.gamma, 1e-4);
  EXPECT_LT((controls_c2f - controls_plain).lpNorm<Eigen::Infinity>(), 1e-8);
}

TEST(ControlArmSlow, CoarseToFineReachesThePlainPathsSolution) {
  // From the documented start at N = 1024: the stages before gamma on 64 steps, the gamma stages
  // on 512 (the default coarse grid), Newton on 1024, against every stage on 1024 steps (the
  // plain path). The same fixed point: controls within 1e-8. (With start_steps = 0 and
  // coarse_steps = 64 the refinement to 128 at gamma = 1e-4 fails and the plain path runs: the
  // grid of the gamma stages has to resolve the switches of the controls.)
  const ArmExample ex;
  const ProblemFamily family = [&ex](double p) { return MakeArmProblem(ex, p); };
  ContinuationOptions plain = ArmContinuation();
  plain.coarse_steps = 0;
  ContinuationOptions c2f = ArmContinuation();
  c2f.coarse_steps = 512;
  c2f.refine_factor = 2;
  ContinuationSummary sp, sc;
  const Eigen::MatrixXd controls_plain = ArmControls(family, 1024, plain, sp);
  const Eigen::MatrixXd controls_c2f = ArmControls(family, 1024, c2f, sc);
  ASSERT_TRUE(sp.ok()) << sp.BriefReport();
  ASSERT_TRUE(sc.ok()) << sc.BriefReport();
  ASSERT_EQ(sp.grids.size(), 1u);
  EXPECT_EQ(sp.grids[0].steps, 1024);
  EXPECT_EQ(sp.grids[0].newton_iterations, sp.newton_iterations);
  ASSERT_EQ(sc.grids.size(), 5u) << sc.ToJson()["grids"].dump();
  EXPECT_EQ(sc.grids[0].steps, 64);
  EXPECT_EQ(sc.grids[3].steps, 512);
  EXPECT_EQ(sc.grids[4].steps, 1024);
  EXPECT_EQ(sc.grids[4].newton_solves, 1);
  EXPECT_EQ(sc.path.back().stage, "refine");
  EXPECT_EQ(sc.path.back().steps, 1024);
  EXPECT_EQ(sc.gamma, 1e-4);
  int total = 0;
  for (const GridRecord& g : sc.grids) total += g.newton_iterations;
  EXPECT_EQ(total, sc.newton_iterations);
  EXPECT_LT((controls_c2f - controls_plain).lpNorm<Eigen::Infinity>(), 1e-8);
  EXPECT_EQ(sc.ToJson()["grids"].size(), 5u);
}

TEST(ControlArmSlow, ConvergesWithContinuationAndRefines) {
  const ArmExample ex;
  const ProblemFamily family = [&ex](double p) { return MakeArmProblem(ex, p); };
  RefinementStudyOptions options;
  options.steps = {32, 64, 128, 256, 512};
  options.continuation = ArmContinuation();
  const std::vector<RefinementLevel> levels = RunRefinementStudy(family, options).levels;
  for (std::size_t i = 0; i < levels.size(); ++i) {
    const RefinementLevel& l = levels[i];
    EXPECT_TRUE(l.ok()) << "N = " << l.steps << ": " << l.message;
    EXPECT_LT(l.residual, 1e-10);
    if (i >= 2) {
      // Successive max-norm differences shrink at least by half per doubling of N (measured:
      // about a quarter, see docs/control.md).
      EXPECT_LT(l.diff_previous, 0.6 * levels[i - 1].diff_previous) << "N = " << l.steps;
      EXPECT_LT(l.tracking_rms, levels[i - 1].tracking_rms);
    }
  }
  EXPECT_LT(levels.back().tracking_rms, 1e-3);
  EXPECT_GT(levels.back().value, 0.0);

  // The continuation path from the documented start, recorded stage by stage.
  Eigen::VectorXd y;
  const ContinuationSummary cs = SolveWithContinuation(family, 128, ArmContinuation(), y);
  ASSERT_TRUE(cs.ok()) << cs.BriefReport();
  ASSERT_GE(cs.path.size(), 3u);
  EXPECT_EQ(cs.path.front().stage, "initial");
  EXPECT_EQ(cs.path.front().path_fraction, 0.1);
  EXPECT_EQ(cs.path.front().gamma, 1.0);
  EXPECT_EQ(cs.path.back().stage, "gamma");
  EXPECT_EQ(cs.path.back().gamma, 1e-4);
  EXPECT_EQ(cs.path_fraction, 1.0);
  EXPECT_EQ(cs.stiffness_scale, 1.0);
  int order = 0;  // stages appear in the order initial, path, stiffness, gamma
  for (const ContinuationRecord& r : cs.path) {
    const int stage = r.stage == "initial"     ? 0
                      : r.stage == "path"      ? 1
                      : r.stage == "stiffness" ? 2
                                               : 3;
    EXPECT_GE(stage, order);
    order = stage;
  }
}

}  // namespace
}  // namespace moreau::control

namespace moreau::control {
namespace {

// A reference that cannot be followed within the bounds: as γ decreases the effective rest
// lengths saturate at L− or L+ except near switching points, the switching structure settles
// and the discrete value converges.
TEST(ControlSaturating, ControlsBecomeBangBangAsGammaDecreases) {
  const SaturatingExample ex;
  const int steps = 400;
  const std::vector<double> gammas = {1e-1, 1e-2, 1e-3, 1e-4, 1e-5};
  ContinuationOptions options;
  options.gamma_start = 1.0;  // continuation in γ from a smooth problem
  options.gamma_decrease = 0.1;
  options.newton.residual_tolerance = 1e-12;
  std::vector<double> values, saturated;
  std::vector<int> switches;
  Eigen::VectorXd y;
  for (double gamma : gammas) {
    SaturatingExample e = ex;
    e.gamma = gamma;
    const ProblemFamily family = [&e](double p) { return MakeSaturatingProblem(e, p); };
    const ContinuationSummary cs = SolveWithContinuation(family, steps, options, y);
    ASSERT_TRUE(cs.ok()) << "gamma " << gamma << ": " << cs.message;
    const PontryaginDiscretization disc(family(1.0), steps);
    PontryaginWorkspace ws;
    values.push_back(DiscreteValue(disc, y, ws));
    const Eigen::MatrixXd controls = EffectiveControls(disc, y);
    const double range = ex.rest_max - ex.rest_min, mid = 0.5 * (ex.rest_max + ex.rest_min);
    int at_bound = 0, changes = 0;
    for (int n = 0; n < steps; ++n) {
      const double l = controls(0, n);
      ASSERT_GE(l, ex.rest_min - 1e-12);
      ASSERT_LE(l, ex.rest_max + 1e-12);
      if (std::min(l - ex.rest_min, ex.rest_max - l) < 1e-3 * range) ++at_bound;
      if (n > 0 && (controls(0, n - 1) - mid) * (l - mid) < 0.0) ++changes;
    }
    saturated.push_back(static_cast<double>(at_bound) / steps);
    switches.push_back(changes);
    options.gamma_start = gamma;  // the next γ starts from this solution's γ
  }
  // Saturation grows as γ → 0 and covers almost every step at the smallest γ.
  for (std::size_t k = 1; k < gammas.size(); ++k) {
    EXPECT_GE(saturated[k], saturated[k - 1]) << "gamma " << gammas[k];
  }
  EXPECT_GT(saturated.back(), 0.95);
  // The switching structure settles: the same number of switches at the two smallest γ.
  EXPECT_EQ(switches[gammas.size() - 1], switches[gammas.size() - 2]);
  EXPECT_GE(switches.back(), 3);  // a genuinely bang-bang control: it switches repeatedly
  // The value converges: successive differences shrink, and within T δ(γ) of the smallest γ's.
  const double delta_per_gamma = 0.5 * std::log(2.0) * (ex.rest_max - ex.rest_min);
  for (std::size_t k = 0; k + 1 < gammas.size(); ++k) {
    EXPECT_LE(std::abs(values[k] - values.back()),
              ex.horizon * delta_per_gamma * (gammas[k] + gammas.back()))
        << "gamma " << gammas[k];
    if (k + 2 < gammas.size()) {
      EXPECT_LT(std::abs(values[k + 2] - values[k + 1]), std::abs(values[k + 1] - values[k]));
    }
  }
}

}  // namespace
}  // namespace moreau::control
