// Step against exact solutions: a step's erfc profile, a periodic mode's decay, the linear
// profile between two fixed faces.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <numbers>
#include <random>

#include "fields/test_util.h"

namespace moreau::fields {
namespace {

using testing::Fill;
using testing::GridOf;
using testing::MaxError;
using testing::SubstrateWith;

// c = 1 below the middle of axis `axis`, 0 above; after t, 1/2 erfc((x − L/2) / √(4 D t)) while
// the front is far from the faces. 200 voxels along the axis, 2 (3D) or 1 (2D) across.
double ErfcError(int dimension, int axis) {
  std::array<int, 3> n{2, 2, 2};
  if (dimension == 2) n = {1, 1, 1};
  n[axis] = 200;
  const double h = 0.01;
  const double middle = 100 * h;
  const double d = 1.0;
  FieldSet fields(GridOf(dimension, n, h), {SubstrateWith(d, 0.0, BoundaryKind::kZeroFlux)});
  Fill(fields, 0, [&](const double* x) { return x[axis] < middle ? 1.0 : 0.0; });
  const double dt = 2.5e-5;
  const int steps = 400;  // t = 0.01: √(4 D t) = 0.2, a fifth of the half box
  for (int i = 0; i < steps; ++i) fields.Step(dt);
  const double t = dt * steps;
  return MaxError(fields, 0, [&](const double* x) {
    return 0.5 * std::erfc((x[axis] - middle) / std::sqrt(4.0 * d * t));
  });
}

TEST(FieldDiffusion, StepProfileIsErfcAlongEveryAxis) {
  // The step is not smooth: the largest error (3.3e-4) sits at the front.
  EXPECT_LT(ErfcError(2, 0), 1e-3);  // 3.3e-4
  EXPECT_LT(ErfcError(2, 1), 1e-3);
  for (int axis = 0; axis < 3; ++axis) {
    const double e = ErfcError(3, axis);
    EXPECT_LT(e, 1e-3) << "axis " << axis;
    // The three sweeps solve the same lines the same way (up to the round-off of the solves
    // across, on uniform values).
    EXPECT_NEAR(e, ErfcError(3, 0), 1e-12) << "axis " << axis;
  }
}

// A periodic axis: a sine mode decays per step by 1/(1 + D Δt μ), μ = (4/h²) sin²(π h m / L),
// the discrete Laplacian's eigenvalue, and the total is kept.
TEST(FieldDiffusion, PeriodicModeDecaysAtTheDiscreteRate) {
  for (int axis = 0; axis < 3; ++axis) {
    std::array<int, 3> n{4, 6, 5};
    n[axis] = 24;
    const double h = 0.5;
    const double length = n[axis] * h;
    const double d = 0.7;
    const double dt = 0.3;
    Substrate sub = SubstrateWith(d, 0.0, BoundaryKind::kZeroFlux);
    sub.boundary[2 * axis].kind = BoundaryKind::kPeriodic;
    sub.boundary[2 * axis + 1].kind = BoundaryKind::kPeriodic;
    FieldSet fields(GridOf(3, n, h), {sub});
    const double k = 2.0 * std::numbers::pi * 3.0 / length;  // the third mode
    const auto mode = [&](const double* x) { return 2.0 + std::sin(k * x[axis] + 0.4); };
    Fill(fields, 0, mode);
    const double total = fields.Total(0);
    const double mu = 4.0 / (h * h) * std::pow(std::sin(k * h / 2.0), 2);
    double amplitude = 1.0;
    for (int step = 0; step < 10; ++step) {
      fields.Step(dt);
      amplitude /= 1.0 + d * dt * mu;
    }
    EXPECT_LT(
        MaxError(fields, 0,
                 [&](const double* x) { return 2.0 + amplitude * std::sin(k * x[axis] + 0.4); }),
        1e-13)
        << "axis " << axis;
    EXPECT_NEAR(fields.Total(0), total, 1e-13 * total) << "axis " << axis;
  }
}

// Two voxels on a periodic axis see each other on both sides: the mode (1, −1) decays with
// μ = 4/h²; an axis of one voxel does not diffuse.
TEST(FieldDiffusion, PeriodicAxisOfOneOrTwoVoxels) {
  Substrate sub = SubstrateWith(1.0, 0.0, BoundaryKind::kPeriodic);
  FieldSet two(GridOf(2, {2, 1, 1}, 1.0), {sub});
  two.values(0)[0] = 1.0;
  two.values(0)[1] = -1.0;
  two.Step(0.5);
  EXPECT_NEAR(two.values(0)[0], 1.0 / (1.0 + 0.5 * 4.0), 1e-15);
  EXPECT_NEAR(two.values(0)[1], -1.0 / (1.0 + 0.5 * 4.0), 1e-15);
  FieldSet one(GridOf(2, {1, 3, 1}, 1.0), {sub});
  one.values(0)[1] = 2.0;
  one.Step(0.5);
  // x: one voxel, no diffusion; y: three, the mean 2/3 stays, the rest decays by 1/(1 + Δt μ),
  // μ = 4 sin²(π/3) = 3.
  EXPECT_NEAR(one.values(0)[1], 2.0 / 3.0 + (4.0 / 3.0) / (1.0 + 0.5 * 3.0), 1e-15);
}

// Between a face fixed at 1 and one fixed at 3 (zero flux elsewhere) the steady state is the
// linear profile, exactly in the discrete scheme (the ghost value of a linear profile is linear).
TEST(FieldDiffusion, FixedFacesGiveTheLinearSteadyState) {
  for (int axis = 0; axis < 3; ++axis) {
    std::array<int, 3> n{5, 4, 3};
    n[axis] = 16;
    const double h = 0.25;
    Substrate sub = SubstrateWith(2.0, 0.0, BoundaryKind::kZeroFlux);
    sub.boundary[2 * axis] = {BoundaryKind::kFixed, 1.0};
    sub.boundary[2 * axis + 1] = {BoundaryKind::kFixed, 3.0};
    FieldSet fields(GridOf(3, n, h), {sub});
    const auto linear = [&](const double* x) { return 1.0 + 2.0 * x[axis] / (n[axis] * h); };
    const SteadyStateSummary summary = fields.SolveSteadyState();
    ASSERT_TRUE(summary.ok()) << summary.message;
    EXPECT_LT(MaxError(fields, 0, linear), 1e-9) << "axis " << axis;
    FieldSet stepped(GridOf(3, n, h), {sub});
    for (int i = 0; i < 200; ++i) stepped.Step(1.0);
    EXPECT_LT(MaxError(stepped, 0, linear), 1e-9) << "axis " << axis;
    // The linear profile is a fixed point of one step.
    Fill(stepped, 0, linear);
    stepped.Step(0.01);
    EXPECT_LT(MaxError(stepped, 0, linear), 1e-13) << "axis " << axis;
  }
}

// Every line is solved alone, every sum goes in a fixed order: the same bits for 1 and 2 threads
// (odd sizes: groups of lines and blocks of columns with remainders; every kind of face; a grid
// large enough for a team of threads).
TEST(FieldDiffusion, SameBitsForAnyThreadCount) {
  Substrate a = SubstrateWith(0.9, 0.1, BoundaryKind::kZeroFlux);
  a.boundary[2].kind = BoundaryKind::kPeriodic;
  a.boundary[3].kind = BoundaryKind::kPeriodic;
  a.boundary[4] = {BoundaryKind::kFixed, 1.5};
  Substrate b = SubstrateWith(0.2, 0.0, BoundaryKind::kPeriodic);
  b.name = "signal";
  std::vector<std::vector<double>> results;
  for (int threads : {1, 2}) {
    FieldSet fields(GridOf(3, {41, 29, 31}, 0.3), {a, b}, threads);
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (int s = 0; s < 2; ++s) {
      for (double& c : fields.values(s)) c = u(rng);
      for (double& r : fields.source(s)) r = u(rng) < 0.1 ? u(rng) : 0.0;
      for (double& k : fields.uptake(s)) k = u(rng) < 0.1 ? u(rng) : 0.0;
    }
    for (int i = 0; i < 3; ++i) fields.Step(0.05);
    std::vector<double> all(fields.values(0).begin(), fields.values(0).end());
    all.insert(all.end(), fields.values(1).begin(), fields.values(1).end());
    fields.SolveSteadyState({1e-10, 8});  // converged or not, the same bits
    all.insert(all.end(), fields.values(0).begin(), fields.values(0).end());
    all.insert(all.end(), fields.values(1).begin(), fields.values(1).end());
    results.push_back(std::move(all));
  }
  ASSERT_EQ(results[0].size(), results[1].size());
  EXPECT_EQ(std::memcmp(results[0].data(), results[1].data(), results[0].size() * sizeof(double)),
            0);
}

}  // namespace
}  // namespace moreau::fields
