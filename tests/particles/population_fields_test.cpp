// Agents coupled to diffusing fields (population_fields.h): conservation of what the agents
// deposit, a well-mixed box against its exact discrete solution, the rules that read the samples
// (necrosis, proliferation, chemotaxis), thread counts and checkpoints.
#include "moreau/particles/population_fields.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "moreau/common/error.h"
#include "moreau/particles/checkpoint.h"
#include "moreau/particles/population.h"
#include "particles/population_test_util.h"

namespace moreau::particles {
namespace {

using testing::Colony;
using testing::Make;
using testing::SameBits;

// A 2D box [0, 4]² of 16 unit voxels with one agent of radius 0.3 at each voxel centre, no
// motion; one substrate "oxygen" starting at 1 with zero-flux faces.
Colony Lattice() {
  Colony c;
  c.geometry.dimension = 2;
  c.options.h = 0.01;
  AgentType cell;
  cell.radius = 0.3;
  AgentType necrotic;
  necrotic.name = "necrotic";
  necrotic.radius = 0.3;
  c.rules.types = {cell, necrotic};
  c.rules.interval = 10;
  for (int j = 0; j < 4; ++j) {
    for (int i = 0; i < 4; ++i) {
      c.x0.insert(c.x0.end(), {i + 0.5, j + 0.5});
      c.types.push_back(0);
    }
  }
  return c;
}

fields::FieldSet Box(double initial, int threads = 1) {
  fields::Grid grid;
  grid.dimension = 2;
  grid.upper = {4.0, 4.0, 0.0};
  grid.spacing = 1.0;
  fields::Substrate oxygen;
  oxygen.initial = initial;
  return fields::FieldSet(grid, {oxygen}, threads);
}

FieldCouplingOptions Responds(SubstrateResponse r) {
  r.type = "cell";
  r.substrate = "oxygen";
  FieldCouplingOptions o;
  o.responses = {r};
  return o;
}

TEST(PopulationFields, WellMixedUptakeFollowsTheExactDiscreteSolution) {
  const Colony c = Lattice();
  Population p = Make(c);
  SubstrateResponse uptake;
  uptake.uptake_rate = 2.0;
  p.CoupleFields(Box(1.0), Responds(uptake));
  // Per voxel U = u V_agent / V_voxel; one field step per rule step of Δt = 0.1.
  const double U = 2.0 * std::numbers::pi * 0.09, dt = 0.1;
  for (int n = 1; n <= 20; ++n) {
    for (int s = 0; s < c.rules.interval; ++s) ASSERT_TRUE(p.Step());
    const double exact = 16.0 / std::pow(1.0 + dt * U, n);
    EXPECT_NEAR(p.fields()->Total(0), exact, 1e-13 * 16.0) << n;
    EXPECT_NEAR(p.FieldSamples(0)[5], exact / 16.0, 1e-14);
  }
  // The ODE dC/dt = −U C: the backward-Euler solution's error is O(Δt), about e^{n (UΔt)²/2} − 1
  // = 3.2 % here.
  EXPECT_NEAR(p.fields()->Total(0) / (16.0 * std::exp(-U * 2.0)),
              std::exp(20 * (U * dt) * (U * dt) / 2), 2e-3);
}

TEST(PopulationFields, DepositedAmountsAreConservedWithEitherInterpolation) {
  for (const fields::Interpolation interpolation :
       {fields::Interpolation::kVoxel, fields::Interpolation::kLinear}) {
    Colony c = Lattice();
    for (std::size_t q = 0; q < c.x0.size(); ++q) c.x0[q] += 0.13 * std::sin(3.0 * q);  // off-centre
    Population p = Make(c);
    SubstrateResponse source;
    source.amount_rate = 0.7;
    FieldCouplingOptions o = Responds(source);
    o.interpolation = interpolation;
    o.substeps = 3;
    p.CoupleFields(Box(0.0), o);
    for (int s = 0; s < 5 * c.rules.interval; ++s) ASSERT_TRUE(p.Step());
    // Δt Σ r_i per rule step, 5 rule steps of Δt = 0.1.
    EXPECT_NEAR(p.fields()->Total(0), 5 * 0.1 * 16 * 0.7, 1e-13);
  }
}

TEST(PopulationFields, NecrosisKillsOrTurnsTheTypeBelowTheThreshold) {
  const Colony c = Lattice();
  SubstrateResponse starving;
  starving.necrosis_below = 0.5;
  Population dies = Make(c);
  dies.CoupleFields(Box(0.4), Responds(starving));
  for (int s = 0; s < c.rules.interval; ++s) dies.Step();
  EXPECT_EQ(dies.summary().deaths, 16);
  starving.necrotic_type = "necrotic";
  Population turns = Make(c);
  turns.CoupleFields(Box(0.4), Responds(starving));
  for (int s = 0; s < c.rules.interval; ++s) ASSERT_TRUE(turns.Step());
  EXPECT_EQ(turns.count(), 16);
  for (const Agent& a : turns.agents()) EXPECT_EQ(a.type, 1);
  Population lives = Make(c);
  lives.CoupleFields(Box(0.6), Responds(starving));
  for (int s = 0; s < c.rules.interval; ++s) ASSERT_TRUE(lives.Step());
  for (const Agent& a : lives.agents()) EXPECT_EQ(a.type, 0);
}

TEST(PopulationFields, DivisionOnlyAboveTheProliferationThreshold) {
  Colony c = Lattice();
  c.rules.types[0].cycle_time = 0.05;  // divides at the first rule step unless starved
  c.rules.relax = true;
  SubstrateResponse gate;
  gate.proliferation_above = 0.5;
  Population starved = Make(c);
  starved.CoupleFields(Box(0.4), Responds(gate));
  Population fed = Make(c);
  fed.CoupleFields(Box(0.6), Responds(gate));
  for (int s = 0; s < c.rules.interval; ++s) {
    ASSERT_TRUE(starved.Step());
    ASSERT_TRUE(fed.Step());
  }
  EXPECT_EQ(starved.summary().births, 0);
  EXPECT_EQ(fed.summary().births, 16);
}

// One agent in c = x (faces fixed at 0 and 4 along x, zero flux along y: a fixed point of the
// steps) moves by the saturating chemotaxis χ ∇c / (1 + |∇c|/g) per unit time.
TEST(PopulationFields, ChemotaxisDriftsUpTheGradientAtTheSaturatingSpeed) {
  Colony c = Lattice();
  c.x0 = {1.5, 2.0};
  c.types = {0};
  Population p = Make(c);
  fields::FieldSet f = Box(0.0);
  std::vector<fields::Substrate> s = f.substrates();
  s[0].boundary[0] = {fields::BoundaryKind::kFixed, 0.0};
  s[0].boundary[1] = {fields::BoundaryKind::kFixed, 4.0};
  fields::FieldSet linear(f.grid(), s);
  for (std::int64_t v = 0; v < 16; ++v) linear.values(0)[static_cast<std::size_t>(v)] = v % 4 + 0.5;
  SubstrateResponse attract;
  attract.chemotaxis = 3.0;
  attract.gradient_saturation = 0.5;
  FieldCouplingOptions o = Responds(attract);
  o.interpolation = fields::Interpolation::kLinear;
  p.CoupleFields(std::move(linear), o);
  EXPECT_NEAR(p.FieldGradients(0)[0], 1.0, 1e-12);
  for (int step = 0; step < 50; ++step) ASSERT_TRUE(p.Step());
  const double speed = 3.0 / (1.0 + 1.0 / 0.5);  // t = 0.5
  EXPECT_NEAR(p.Positions()[0], 1.5 + 0.5 * speed, 1e-9);
  EXPECT_NEAR(p.Positions()[1], 2.0, 1e-12);
}

// Secreting, taking up, dividing, chemotactic agents with noise: one and two threads, and a run
// resumed from a checkpoint between rule steps, give the same bits (positions and fields).
Population Chemotactic(int threads) {
  Colony c = testing::GrowingColony();
  c.options.threads = threads;
  c.rules.variables = {{"on", 1.0, Inheritance::kCopy}};
  Population p = Make(c);
  fields::Grid grid;
  grid.lower = {-6.0, -6.0, 0.0};
  grid.upper = {7.0, 7.0, 0.0};
  grid.spacing = 0.5;
  fields::Substrate signal;
  signal.name = "signal";
  signal.decay = 0.1;
  signal.boundary[0] = {fields::BoundaryKind::kFixed, 1.0};
  FieldCouplingOptions o;
  SubstrateResponse r;
  r.type = "cell";
  r.substrate = "signal";
  r.secretion_rate = 1.0;
  r.saturation = 2.0;
  r.secretion_variable = "on";
  r.chemotaxis = 0.5;
  SubstrateResponse t = r;
  t.type = "tumour";
  t.secretion_rate = 0.0;
  t.uptake_rate = 0.5;
  t.chemotaxis = -0.2;
  t.gradient_saturation = 1.0;
  o.responses = {r, t};
  o.interpolation = fields::Interpolation::kLinear;
  o.substeps = 2;
  p.CoupleFields(fields::FieldSet(grid, {signal}, threads), o);
  return p;
}

std::vector<double> FieldBits(const Population& p) {
  const std::span<const double> v = p.fields()->values(0);
  return {v.begin(), v.end()};
}

TEST(PopulationFields, SameBitsOnOneAndTwoThreadsAndAfterACheckpointSlow) {
  Population one = Chemotactic(1);
  Population two = Chemotactic(2);
  Population resumed = Chemotactic(1);
  for (int s = 0; s < 453; ++s) {
    ASSERT_TRUE(one.Step());
    ASSERT_TRUE(two.Step());
  }
  for (int s = 0; s < 207; ++s) ASSERT_TRUE(resumed.Step());
  const PopulationState state = resumed.SaveState();
  const nlohmann::json bytes = nlohmann::json::from_cbor(nlohmann::json::to_cbor(state.ToJson()));
  Population restored = Chemotactic(2);
  restored.RestoreState(PopulationState::FromJson(bytes, state.engine));
  for (int s = 207; s < 453; ++s) ASSERT_TRUE(restored.Step());
  EXPECT_GT(one.summary().births, 5);
  EXPECT_TRUE(SameBits(one.Positions(), two.Positions()));
  EXPECT_TRUE(SameBits(FieldBits(one), FieldBits(two)));
  EXPECT_TRUE(SameBits(one.Positions(), restored.Positions()));
  EXPECT_TRUE(SameBits(FieldBits(one), FieldBits(restored)));
  EXPECT_EQ(one.fields()->time(), restored.fields()->time());
  EXPECT_GT(one.fields()->Total(0), 0.0);
}

TEST(PopulationFields, BadCouplingsAreRefusedNamingTheKey) {
  const Colony c = Lattice();
  const auto key_of = [&](SubstrateResponse r, const char* type = "cell",
                          const char* substrate = "oxygen") {
    Population p = Make(c);
    FieldCouplingOptions o = Responds(r);
    o.responses[0].type = type;
    o.responses[0].substrate = substrate;
    try {
      p.CoupleFields(Box(1.0), o);
    } catch (const InputError& e) {
      return e.key();
    }
    return std::string("(none)");
  };
  SubstrateResponse r;
  r.uptake_rate = -1.0;
  EXPECT_EQ(key_of(r), "types.cell.oxygen.uptake_rate");
  EXPECT_EQ(key_of({}, "cell", "sugar"), "types.cell.sugar");
  EXPECT_EQ(key_of({}, "stroma"), "types");
  r = {};
  r.necrotic_type = "cell";
  EXPECT_EQ(key_of(r), "types.cell.oxygen.necrotic_type");
  r.necrotic_type = "dead";
  EXPECT_EQ(key_of(r), "types.cell.oxygen.necrotic_type");
  r = {};
  r.secretion_variable = "switch";
  EXPECT_EQ(key_of(r), "types.cell.oxygen.secretion_variable");
}

}  // namespace
}  // namespace moreau::particles
