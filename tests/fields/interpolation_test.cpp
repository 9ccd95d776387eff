// Deposit and Sample: conservation, adjointness, exactness on linear fields, faces.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "fields/test_util.h"

namespace moreau::fields {
namespace {

using testing::Fill;
using testing::GridOf;
using testing::SubstrateWith;

// n agents uniformly in the grid's box (seeded), k coordinates each.
std::vector<double> AgentsIn(const Grid& grid, int n, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::vector<double> x;
  for (int i = 0; i < n; ++i) {
    for (int a = 0; a < grid.dimension; ++a) {
      x.push_back(std::uniform_real_distribution<double>(grid.lower[a], grid.upper[a])(rng));
    }
  }
  return x;
}

std::vector<double> Uniform(int n, double lo, double hi, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::vector<double> v(static_cast<std::size_t>(n));
  for (double& x : v) x = std::uniform_real_distribution<double>(lo, hi)(rng);
  return v;
}

// One periodic axis (y), the others zero flux.
Substrate HalfPeriodic() {
  Substrate sub = SubstrateWith(0.3, 0.0, BoundaryKind::kZeroFlux);
  sub.boundary[2].kind = BoundaryKind::kPeriodic;
  sub.boundary[3].kind = BoundaryKind::kPeriodic;
  return sub;
}

// What the agents deposit is what the total gains: Σ_i r_i Δt, to round-off, for both
// interpolations, agents near faces and on the periodic axis included.
TEST(FieldInterpolation, DepositIsConservative) {
  for (int dimension : {2, 3}) {
    for (Interpolation interpolation : {Interpolation::kVoxel, Interpolation::kLinear}) {
      FieldSet fields(GridOf(dimension, {9, 7, 5}, 0.5), {HalfPeriodic()});
      const int n = 300;
      const std::vector<double> x = AgentsIn(fields.grid(), n, 41);
      const std::vector<double> rate = Uniform(n, 0.0, 2.0, 42);
      fields.Deposit(0, x, {}, {}, {}, {}, rate, interpolation);
      double deposited = 0.0;
      for (double r : rate) deposited += r;
      const double dt = 0.1;
      fields.Step(dt);
      EXPECT_NEAR(fields.Total(0), dt * deposited, 1e-13 * dt * deposited)
          << dimension << "D " << EnumName(kInterpolationNames, interpolation);
    }
  }
}

// Σ_i a_i sample_i(c) = V_voxel Σ_v R_v c_v after depositing a_i: the sample is the deposit's
// transpose.
TEST(FieldInterpolation, SampleIsTheDepositsAdjoint) {
  for (Interpolation interpolation : {Interpolation::kVoxel, Interpolation::kLinear}) {
    FieldSet fields(GridOf(3, {9, 7, 5}, 0.5), {HalfPeriodic()});
    const int n = 200;
    const std::vector<double> x = AgentsIn(fields.grid(), n, 51);
    const std::vector<double> a = Uniform(n, -1.0, 1.0, 52);
    const std::vector<double> c =
        Uniform(static_cast<int>(fields.grid().voxel_count()), 0.0, 1.0, 53);
    std::copy(c.begin(), c.end(), fields.values(0).begin());
    fields.Deposit(0, x, {}, {}, {}, {}, a, interpolation);
    std::vector<double> sampled(n);
    fields.Sample(0, x, interpolation, sampled);
    double agents = 0.0;
    for (int i = 0; i < n; ++i) agents += a[i] * sampled[i];
    double voxels = 0.0;
    for (std::size_t v = 0; v < c.size(); ++v) voxels += fields.source(0)[v] * c[v];
    voxels *= fields.grid().voxel_volume();
    EXPECT_NEAR(agents, voxels, 1e-13 * std::abs(voxels) + 1e-14);
  }
}

// A linear field is sampled exactly by kLinear between the first and last voxel centres, and its
// gradient (central differences, one-sided at faces) is exact everywhere.
TEST(FieldInterpolation, LinearFieldSampledExactly) {
  for (int dimension : {2, 3}) {
    FieldSet fields(GridOf(dimension, {8, 6, 5}, 0.25),
                    {SubstrateWith(1.0, 0.0, BoundaryKind::kZeroFlux)});
    const double slope[3] = {0.7, -1.3, 2.1};
    const auto linear = [&](const double* x) {
      double v = 0.5;
      for (int a = 0; a < dimension; ++a) v += slope[a] * x[a];
      return v;
    };
    Fill(fields, 0, linear);
    Grid inner = fields.grid();
    for (int a = 0; a < dimension; ++a) {
      inner.lower[a] += 0.5 * inner.spacing;
      inner.upper[a] -= 0.5 * inner.spacing;
    }
    const int n = 100;
    const std::vector<double> x = AgentsIn(inner, n, 61);
    std::vector<double> value(n), gradient(static_cast<std::size_t>(n * dimension));
    fields.Sample(0, x, Interpolation::kLinear, value, gradient);
    for (int i = 0; i < n; ++i) {
      EXPECT_NEAR(value[i], linear(&x[dimension * i]), 1e-13);
      for (int a = 0; a < dimension; ++a) EXPECT_NEAR(gradient[dimension * i + a], slope[a], 1e-12);
    }
    // kVoxel: the value of the voxel that holds the agent.
    fields.Sample(0, x, Interpolation::kVoxel, value);
    double centre[3];
    fields.grid().Centre(fields.grid().VoxelOf(&x[0]), centre);
    EXPECT_EQ(value[0], linear(centre));
  }
}

// A population large enough to be sampled on several threads gets the bits of one thread.
TEST(FieldInterpolation, SampleHasTheSameBitsOnOneAndTwoThreads) {
  const Grid grid = GridOf(3, {12, 10, 8}, 0.5);
  const std::vector<double> x = AgentsIn(grid, 50000, 67);
  std::vector<std::vector<double>> values, gradients;
  for (int threads : {1, 2}) {
    FieldSet fields(grid, {HalfPeriodic()}, threads);
    Fill(fields, 0, [](const double* p) { return std::sin(p[0]) * std::cos(2.0 * p[1]) + p[2]; });
    values.emplace_back(x.size() / 3);
    gradients.emplace_back(x.size());
    fields.Sample(0, x, Interpolation::kLinear, values.back(), gradients.back());
  }
  EXPECT_EQ(values[0], values[1]);
  EXPECT_EQ(gradients[0], gradients[1]);
}

// A population large enough to be deposited on several threads (each thread adds to its own
// voxels, the agents in order) gets the bits of one thread in every source term, for both
// interpolations and a thread count that does not divide the voxels evenly.
TEST(FieldInterpolation, DepositHasTheSameBitsOnOneTwoAndThreeThreads) {
  const Grid grid = GridOf(3, {12, 10, 8}, 0.5);
  const int n = 50000;
  const std::vector<double> x = AgentsIn(grid, n, 71);
  const std::vector<double> volume = Uniform(n, 0.1, 0.3, 72);
  const std::vector<double> secretion = Uniform(n, 0.0, 2.0, 73);
  const std::vector<double> saturation = Uniform(n, 0.5, 1.5, 74);
  const std::vector<double> uptake = Uniform(n, 0.0, 1.0, 75);
  const std::vector<double> amount = Uniform(n, -1.0, 1.0, 76);
  for (Interpolation interpolation : {Interpolation::kVoxel, Interpolation::kLinear}) {
    std::vector<std::vector<double>> terms;
    for (int threads : {1, 2, 3}) {
      FieldSet fields(grid, {HalfPeriodic()}, threads);
      fields.Deposit(0, x, volume, secretion, saturation, uptake, amount, interpolation);
      for (std::span<double> t :
           {fields.secretion(0), fields.secretion_target(0), fields.uptake(0), fields.source(0)}) {
        terms.emplace_back(t.begin(), t.end());
      }
    }
    for (std::size_t t = 0; t < 4; ++t) {
      EXPECT_GT(*std::max_element(terms[t].begin(), terms[t].end()), 0.0);
      EXPECT_EQ(terms[t], terms[4 + t]) << "term " << t << ", 2 threads";
      EXPECT_EQ(terms[t], terms[8 + t]) << "term " << t << ", 3 threads";
    }
  }
}

// At a zero-flux face the weight beyond the first centre stays on the face voxel; on a periodic
// axis it wraps to the opposite voxel.
TEST(FieldInterpolation, FaceWeights) {
  FieldSet fields(GridOf(2, {4, 4, 1}, 1.0), {HalfPeriodic()});
  const std::vector<double> x = {0.1, 0.25};  // below the first centres along x and y
  fields.Deposit(0, x, {}, {}, {}, {}, std::vector<double>{1.0}, Interpolation::kLinear);
  const std::span<const double> r = fields.source(0);
  // x: all on i = 0; y (periodic): 0.75 on j = 0, 0.25 on j = 3.
  EXPECT_DOUBLE_EQ(r[0], 0.75);
  EXPECT_DOUBLE_EQ(r[12], 0.25);
  double sum = 0.0;
  for (double v : r) sum += v;
  EXPECT_DOUBLE_EQ(sum, 1.0);
}

// Deposit's rates per agent volume: S += s V_i / V_voxel, S c* and U alike.
TEST(FieldInterpolation, RatesScaleWithTheAgentsVolume) {
  FieldSet fields(GridOf(3, {3, 3, 3}, 2.0), {SubstrateWith(1.0, 0.0, BoundaryKind::kZeroFlux)});
  const std::vector<double> x = {3.0, 3.0, 3.0, 3.1, 2.9, 3.0};  // both in the middle voxel
  fields.Deposit(0, x, std::vector<double>{2.0, 4.0}, std::vector<double>{1.0, 0.5},
                 std::vector<double>{10.0, 20.0}, std::vector<double>{0.25, 0.0}, {},
                 Interpolation::kVoxel);
  EXPECT_DOUBLE_EQ(fields.secretion(0)[13], (1.0 * 2.0 + 0.5 * 4.0) / 8.0);
  EXPECT_DOUBLE_EQ(fields.secretion_target(0)[13], (10.0 * 2.0 + 0.5 * 20.0 * 4.0) / 8.0);
  EXPECT_DOUBLE_EQ(fields.uptake(0)[13], 0.25 * 2.0 / 8.0);
  fields.ClearSources();
  EXPECT_EQ(fields.uptake(0)[13], 0.0);
}

}  // namespace
}  // namespace moreau::fields
