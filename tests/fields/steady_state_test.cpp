// Steady states: a point source with decay in 3D against the free-space Green's function,
// by conjugate gradients and by stepping long; uniqueness and the solver's report.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "fields/test_util.h"

namespace moreau::fields {
namespace {

using testing::GridOf;
using testing::SubstrateWith;

constexpr double kPointD = 1.0;
constexpr double kPointLength = 4.0;  // λ_len = √(D / decay), 4 voxel edges
constexpr int kPointCells = 41;       // h = 1: the faces 20 from the source, 5 decay lengths
constexpr double kPointAmount = 5.0;  // amount per time from the source voxel

FieldSet PointSource() {
  const double decay = kPointD / (kPointLength * kPointLength);
  FieldSet fields(GridOf(3, {kPointCells, kPointCells, kPointCells}, 1.0),
                  {SubstrateWith(kPointD, decay, BoundaryKind::kZeroFlux)});
  const double centre[3] = {kPointCells / 2.0, kPointCells / 2.0, kPointCells / 2.0};
  fields.Deposit(0, centre, {}, {}, {}, {}, std::vector<double>{kPointAmount},
                 Interpolation::kVoxel);
  return fields;
}

// The distance of voxel v's centre from the source.
double FromSource(const FieldSet& fields, std::size_t v) {
  double x[3];
  fields.grid().Centre(static_cast<std::int64_t>(v), x);
  return std::hypot(x[0] - kPointCells / 2.0, x[1] - kPointCells / 2.0, x[2] - kPointCells / 2.0);
}

// The largest relative error against amount · exp(−r/λ)/(4π D r) over the voxels 4 to 10 voxel
// edges from the source (away from the source voxel, where the lattice's Green's function differs
// by O(h²/r²), and from the faces).
double PointSourceError(const FieldSet& fields) {
  const std::span<const double> c = fields.values(0);
  double worst = 0.0;
  for (std::size_t v = 0; v < c.size(); ++v) {
    const double r = FromSource(fields, v);
    if (r < 4.0 || r > 10.0) continue;
    const double exact =
        kPointAmount * std::exp(-r / kPointLength) / (4.0 * std::numbers::pi * kPointD * r);
    worst = std::max(worst, std::abs(c[v] - exact) / exact);
  }
  return worst;
}

TEST(FieldSteadyState, PointSourceWithDecay) {
  FieldSet fields = PointSource();
  const SteadyStateSummary summary = fields.SolveSteadyState();
  ASSERT_TRUE(summary.ok()) << summary.message;
  EXPECT_LE(summary.residual, 1e-10);
  EXPECT_GT(summary.iterations, 5);
  EXPECT_LT(PointSourceError(fields), 0.05);  // 4.4 % at r = 4, 1.8 % at r = 10 along the axes
  // Stepping long (t = 100, 6 decay times) reaches the LOD scheme's own steady state, O(Δt) from
  // the operator's.
  FieldSet stepped = PointSource();
  for (int i = 0; i < 1000; ++i) stepped.Step(0.1);
  EXPECT_LT(PointSourceError(stepped), 0.09);
  double worst = 0.0;
  for (std::size_t v = 0; v < fields.values(0).size(); ++v) {
    const double r = FromSource(fields, v);
    if (r < 4.0 || r > 10.0) continue;
    worst = std::max(worst, std::abs(stepped.values(0)[v] / fields.values(0)[v] - 1.0));
  }
  EXPECT_LT(worst, 0.04);
}

// The conjugate-gradient answer satisfies the discrete equations: one step of any length from it
// changes nothing beyond the LOD splitting, which vanishes with Δt.
TEST(FieldSteadyState, ResidualMeasuredIndependently) {
  Substrate sub = SubstrateWith(0.5, 0.2, BoundaryKind::kZeroFlux);
  sub.boundary[0] = {BoundaryKind::kFixed, 2.0};
  FieldSet fields(GridOf(2, {20, 12, 1}, 0.5), {sub});
  for (int v = 0; v < 240; v += 7) fields.source(0)[v] = 1.0 + v % 3;
  for (int v = 3; v < 240; v += 11) fields.uptake(0)[v] = 0.5;
  const SteadyStateSummary summary = fields.SolveSteadyState({1e-12, 1000});
  ASSERT_TRUE(summary.ok()) << summary.message;
  const std::vector<double> steady(fields.values(0).begin(), fields.values(0).end());
  // The change per step divided by Δt tends to the residual, 0 here.
  double previous = 0.0;
  for (double dt : {1e-2, 1e-3}) {
    fields.Restore({steady}, 0.0, 0);
    fields.Step(dt);
    double change = 0.0;
    for (std::size_t v = 0; v < steady.size(); ++v) {
      change = std::max(change, std::abs(fields.values(0)[v] - steady[v]) / dt);
    }
    if (previous > 0.0) {
      EXPECT_LT(change, 0.2 * previous);  // O(Δt)
    }
    previous = change;
  }
}

TEST(FieldSteadyState, ReportsMaxIterations) {
  FieldSet fields = PointSource();
  const SteadyStateSummary summary = fields.SolveSteadyState({1e-12, 3});
  EXPECT_EQ(summary.termination, Termination::kMaxIterations);
  EXPECT_EQ(summary.iterations, 3);
  EXPECT_NE(summary.message.find("oxygen"), std::string::npos) << summary.message;
  EXPECT_EQ(summary.ToJson()["termination"], "max_iterations");
}

TEST(FieldSteadyState, NoUniqueSteadyStateIsBadInput) {
  FieldSet fields(GridOf(2, {4, 4, 1}, 1.0), {SubstrateWith(1.0, 0.0, BoundaryKind::kZeroFlux)});
  testing::ExpectKeyError([&] { fields.SolveSteadyState(); }, "substrates.oxygen");
  fields.uptake(0)[5] = 0.1;  // one absorbing voxel makes it unique
  EXPECT_TRUE(fields.SolveSteadyState().ok());
  testing::ExpectKeyError([&] { fields.SolveSteadyState({0.0, 10}); }, "tolerance");
}

}  // namespace
}  // namespace moreau::fields
