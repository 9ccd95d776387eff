// Bad input: every InputError names its key; the field lists read and echo every key.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "fields/test_util.h"

namespace moreau::fields {
namespace {

using testing::ExpectKeyError;
using testing::GridOf;
using testing::SubstrateWith;

Substrate Oxygen() { return SubstrateWith(1.0, 0.0, BoundaryKind::kZeroFlux); }

void MakeWith(const Grid& grid, const std::vector<Substrate>& substrates, int threads = 1) {
  FieldSet fields(grid, substrates, threads);
}

TEST(FieldInput, GridKeys) {
  Grid g = GridOf(2, {4, 4, 1}, 0.5);
  g.spacing = 0.0;
  ExpectKeyError([&] { MakeWith(g, {Oxygen()}); }, "grid.spacing");
  g = GridOf(2, {4, 4, 1}, 0.5);
  g.dimension = 4;
  ExpectKeyError([&] { MakeWith(g, {Oxygen()}); }, "grid.dimension");
  g = GridOf(3, {4, 4, 4}, 0.5);
  g.upper[2] = 2.1;  // 4.2 voxels along z
  try {
    MakeWith(g, {Oxygen()});
    ADD_FAILURE() << "no InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.key(), "grid.upper");
    EXPECT_NE(e.reason().find("along z"), std::string::npos) << e.what();
  }
  g = GridOf(2, {4, 4, 1}, 0.5);
  g.upper[1] = g.lower[1];
  ExpectKeyError([&] { MakeWith(g, {Oxygen()}); }, "grid.upper");
  g = GridOf(2, {4, 4, 1}, 0.5);
  g.lower[0] = std::nan("");
  ExpectKeyError([&] { MakeWith(g, {Oxygen()}); }, "grid.lower");
  // In 2D z is not looked at.
  g = GridOf(2, {4, 4, 1}, 0.5);
  g.upper[2] = -3.0;
  EXPECT_NO_THROW(MakeWith(g, {Oxygen()}));
  ExpectKeyError([&] { MakeWith(GridOf(2, {4, 4, 1}, 0.5), {Oxygen()}, -1); }, "threads");
}

TEST(FieldInput, SubstrateKeys) {
  const Grid g = GridOf(2, {4, 4, 1}, 0.5);
  Substrate s = Oxygen();
  s.diffusion = 0.0;
  ExpectKeyError([&] { MakeWith(g, {s}); }, "substrates.oxygen.diffusion");
  s = Oxygen();
  s.decay = -1.0;
  ExpectKeyError([&] { MakeWith(g, {s}); }, "substrates.oxygen.decay");
  s = Oxygen();
  s.initial = std::nan("");
  ExpectKeyError([&] { MakeWith(g, {s}); }, "substrates.oxygen.initial");
  s = Oxygen();
  s.boundary[1].value = std::numeric_limits<double>::infinity();
  ExpectKeyError([&] { MakeWith(g, {s}); }, "substrates.oxygen.x_max_value");
  s = Oxygen();
  s.boundary[2].kind = BoundaryKind::kPeriodic;
  ExpectKeyError([&] { MakeWith(g, {s}); }, "substrates.oxygen.y_max");
  s = Oxygen();
  s.name = "";
  ExpectKeyError([&] { MakeWith(g, {s}); }, "substrates.name");
  ExpectKeyError([&] { MakeWith(g, {Oxygen(), Oxygen()}); }, "substrates");
  ExpectKeyError([&] { MakeWith(g, {}); }, "substrates");
}

TEST(FieldInput, CallsNameTheirArguments) {
  FieldSet fields(GridOf(2, {4, 4, 1}, 0.5), {Oxygen()});
  ExpectKeyError([&] { fields.Step(0.0); }, "dt");
  ExpectKeyError([&] { fields.Step(std::nan("")); }, "dt");
  const std::vector<double> x = {0.5, 0.5};
  const std::vector<double> one = {1.0};
  const std::vector<double> two = {1.0, 2.0};
  const Interpolation voxel = Interpolation::kVoxel;
  ExpectKeyError(
      [&] {
        fields.Deposit(0, {x.data(), 1}, {}, {}, {}, {}, one, voxel);
      },
      "positions");
  ExpectKeyError([&] { fields.Deposit(0, x, two, one, {}, {}, {}, voxel); }, "volumes");
  ExpectKeyError([&] { fields.Deposit(0, x, {}, one, {}, {}, {}, voxel); }, "volumes");
  ExpectKeyError([&] { fields.Deposit(0, x, one, std::vector<double>{-1.0}, {}, {}, {}, voxel); },
                 "secretion");
  ExpectKeyError([&] { fields.Deposit(0, x, one, {}, {}, std::vector<double>{-1.0}, {}, voxel); },
                 "uptake");
  ExpectKeyError(
      [&] { fields.Deposit(0, x, {}, {}, {}, {}, std::vector<double>{std::nan("")}, voxel); },
      "amount_rate");
  ExpectKeyError(
      [&] {
        fields.Deposit(0, std::vector<double>{0.0, std::nan("")}, {}, {}, {}, {}, one, voxel);
      },
      "positions");
  std::vector<double> value(2);
  ExpectKeyError([&] { fields.Sample(0, x, voxel, value); }, "value");
  value.resize(1);
  std::vector<double> gradient(3);
  ExpectKeyError([&] { fields.Sample(0, x, voxel, value, gradient); }, "gradient");
  ExpectKeyError([&] { fields.Restore({{1.0}}, 0.0, 0); }, "values");
  ExpectKeyError([&] { fields.Restore({}, 0.0, 0); }, "values");
  try {
    (void)fields.SubstrateIndex("glucose");
    ADD_FAILURE() << "no InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("unknown substrate 'glucose' (substrates: oxygen)"),
              std::string::npos)
        << e.what();
  }
  EXPECT_EQ(fields.SubstrateIndex("oxygen"), 0);
}

TEST(FieldInput, FieldListsReadAndEcho) {
  Substrate s;
  const FieldList<Substrate>& list = Substrate::Fields();
  list.Set(s, "boundary", "fixed");
  list.Set(s, "boundary_value", 2.5);
  for (const FaceBoundary& f : s.boundary) {
    EXPECT_EQ(f.kind, BoundaryKind::kFixed);
    EXPECT_EQ(f.value, 2.5);
  }
  list.Set(s, "y_max", "zero_flux");
  list.Set(s, "z_min_value", 1.0);
  EXPECT_EQ(s.boundary[3].kind, BoundaryKind::kZeroFlux);
  EXPECT_EQ(s.boundary[4].value, 1.0);
  const nlohmann::json j = list.ToJson(s);
  EXPECT_TRUE(j["boundary"].is_null());  // the faces differ
  EXPECT_EQ(j["x_min"], "fixed");
  EXPECT_EQ(j["z_min_value"], 1.0);
  ExpectKeyError([&] { list.Set(s, "boundary", "open"); }, "boundary");
  ExpectKeyError([&] { list.Set(s, "boundary_value", "high"); }, "boundary_value");
  ExpectKeyError([&] { list.Set(s, "x_max", "open"); }, "x_max");
  Grid g;
  Grid::Fields().Set(g, "upper", nlohmann::json::array({2.0, 3.0}));
  EXPECT_EQ(g.upper[1], 3.0);
  EXPECT_EQ(Grid::Fields().ToJson(g)["upper"], nlohmann::json::array({2.0, 3.0}));
  ExpectKeyError([&] { Grid::Fields().Set(g, "lower", nlohmann::json::array({1.0})); }, "lower");
  ExpectKeyError([&] { Grid::Fields().Set(g, "spacing", -1.0); }, "spacing");
  SteadyStateOptions o;
  ExpectKeyError([&] { SteadyStateOptions::Fields().Set(o, "max_iterations", 0); },
                 "max_iterations");
}

// Sizes and the voxel geometry.
TEST(FieldInput, GridGeometry) {
  Grid g = GridOf(3, {5, 4, 3}, 0.5);
  g.lower = {1.0, -1.0, 0.0};
  g.upper = {3.5, 1.0, 1.5};
  EXPECT_EQ(g.cells(), (std::array<int, 3>{5, 4, 3}));
  EXPECT_EQ(g.voxel_count(), 60);
  EXPECT_EQ(g.voxel_volume(), 0.125);
  const double x[3] = {1.6, 0.9, 1.49};
  EXPECT_EQ(g.VoxelOf(x), 1 + 5 * (3 + 4 * 2));
  const double outside[3] = {-10.0, 10.0, 0.1};
  EXPECT_EQ(g.VoxelOf(outside), 0 + 5 * 3);
  double centre[3];
  g.Centre(1 + 5 * (3 + 4 * 2), centre);
  EXPECT_DOUBLE_EQ(centre[0], 1.75);
  EXPECT_DOUBLE_EQ(centre[1], 0.75);
  EXPECT_DOUBLE_EQ(centre[2], 1.25);
}

}  // namespace
}  // namespace moreau::fields
