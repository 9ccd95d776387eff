// Sources, uptake and decay against the scheme's exact balance and the ODE of a well-mixed box.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "fields/test_util.h"

namespace moreau::fields {
namespace {

using testing::GridOf;
using testing::SubstrateWith;

// A 3D box with zero-flux faces and random (seeded) values.
FieldSet RandomBox(double decay, std::uint32_t seed) {
  FieldSet fields(GridOf(3, {13, 10, 7}, 0.2),
                  {SubstrateWith(0.8, decay, BoundaryKind::kZeroFlux)});
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 2.0);
  for (double& c : fields.values(0)) c = u(rng);
  return fields;
}

// With R only (no decay, zero-flux faces) the total grows by exactly Δt Σ_v R_v V_voxel per step.
TEST(FieldSources, FreeSourcesAddTheirAmount) {
  FieldSet fields = RandomBox(0.0, 11);
  std::mt19937 rng(12);
  std::uniform_real_distribution<double> u(-1.0, 3.0);
  double rate = 0.0;  // Σ_v R_v V_voxel
  for (double& r : fields.source(0)) {
    r = u(rng);
    rate += r * fields.grid().voxel_volume();
  }
  const double dt = 0.05;
  double expected = fields.Total(0);
  for (int step = 0; step < 20; ++step) {
    fields.Step(dt);
    expected += dt * rate;
    EXPECT_NEAR(fields.Total(0), expected, 1e-13 * expected) << "step " << step;
  }
}

// With secretion and uptake too: the sources' implicit update per voxel, then diffusion that
// keeps the total: Total after = V_voxel Σ_v (c_v + Δt (S c* + R)_v) / (1 + Δt (S + U)_v).
TEST(FieldSources, SecretionAndUptakeBalance) {
  FieldSet fields = RandomBox(0.0, 21);
  std::mt19937 rng(22);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int v = 0; v < static_cast<int>(fields.grid().voxel_count()); ++v) {
    const bool cell = u(rng) < 0.3;
    fields.secretion(0)[v] = cell ? 2.0 * u(rng) : 0.0;
    fields.secretion_target(0)[v] = fields.secretion(0)[v] * 1.5;
    fields.uptake(0)[v] = cell ? u(rng) : 0.0;
    fields.source(0)[v] = u(rng) - 0.5;
  }
  const double dt = 0.1;
  for (int step = 0; step < 10; ++step) {
    double expected = 0.0;
    for (int v = 0; v < static_cast<int>(fields.grid().voxel_count()); ++v) {
      expected +=
          (fields.values(0)[v] + dt * (fields.secretion_target(0)[v] + fields.source(0)[v])) /
          (1.0 + dt * (fields.secretion(0)[v] + fields.uptake(0)[v]));
    }
    expected *= fields.grid().voxel_volume();
    fields.Step(dt);
    EXPECT_NEAR(fields.Total(0), expected, 1e-13 * expected) << "step " << step;
  }
  fields.ClearSources();
  const double total = fields.Total(0);
  fields.Step(dt);
  EXPECT_NEAR(fields.Total(0), total, 1e-13 * total);
}

// Decay: each axis's implicit step divides the total by 1 + Δt λ/k, so one step by
// (1 + Δt λ/k)^k, the implicit form of dM/dt = −λ M.
TEST(FieldSources, DecayDividesTheTotalPerAxis) {
  const double decay = 0.7;
  const double dt = 0.2;
  FieldSet fields = RandomBox(decay, 31);
  double expected = fields.Total(0);
  for (int step = 0; step < 20; ++step) {
    fields.Step(dt);
    expected /= std::pow(1.0 + dt * decay / 3.0, 3);
    EXPECT_NEAR(fields.Total(0), expected, 1e-13 * expected) << "step " << step;
  }
}

// A well-mixed box (uniform value and uptake, zero-flux faces): c_n = c0 / (1 + Δt U)^n exactly
// for the scheme, which tends to c0 e^{−U t} at first order in Δt.
TEST(FieldSources, UptakeInAWellMixedBox) {
  const double c0 = 3.0;
  const double uptake = 1.3;
  const double t = 1.0;
  std::vector<double> errors;
  for (int steps : {20, 40, 80}) {
    Substrate sub = SubstrateWith(1.0, 0.0, BoundaryKind::kZeroFlux);
    sub.initial = c0;
    FieldSet fields(GridOf(2, {6, 5, 1}, 0.5), {sub});
    for (double& u : fields.uptake(0)) u = uptake;
    const double dt = t / steps;
    for (int i = 0; i < steps; ++i) fields.Step(dt);
    const double scheme = c0 / std::pow(1.0 + dt * uptake, steps);
    for (double c : fields.values(0)) ASSERT_NEAR(c, scheme, 1e-13 * scheme);
    errors.push_back(std::abs(fields.values(0)[7] - c0 * std::exp(-uptake * t)));
  }
  // First order: halving Δt halves the error.
  EXPECT_NEAR(errors[0] / errors[1], 2.0, 0.1);
  EXPECT_NEAR(errors[1] / errors[2], 2.0, 0.05);
}

}  // namespace
}  // namespace moreau::fields
