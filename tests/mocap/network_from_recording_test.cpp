// The network built from a recording: most rigid partners, bounds from the observed range,
// dynamics from the options, explicit springs, bad options.
#include "moreau/mocap/network_from_recording.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "mocap/ocp_test_util.h"
#include "moreau/common/error.h"

namespace moreau::mocap {
namespace {

TEST(MocapNetwork, PartnersAreOnTheSameRigidBody) {
  const Recording rec = testing::RigidBodies(2, 5, 120, 100.0);
  MarkerNetworkOptions o;
  o.partners = 4;
  const MarkerNetwork net = BuildMarkerNetwork(rec, o);
  // Each body's 5 markers choose the other 4 of their body: the 10 pairs of each body, no more.
  ASSERT_EQ(net.springs.size(), 20u);
  for (const MarkerSpring& s : net.springs) {
    EXPECT_EQ(s.a / 5, s.b / 5) << "spring across bodies " << s.a << "-" << s.b;
    EXPECT_LT(s.spread, 1e-9);
    EXPECT_EQ(s.common_frames, 120);
    const double d = (rec.point(0, s.a) - rec.point(0, s.b)).norm();
    EXPECT_NEAR(s.mean, d, 1e-12);
    // Zero range: the margin is the floor, bound_floor × mean.
    EXPECT_NEAR(s.rest_min, d - o.bound_floor * d, 1e-9);
    EXPECT_NEAR(s.rest_max, d + o.bound_floor * d, 1e-9);
  }
  for (int m = 0; m < rec.markers(); ++m) EXPECT_EQ(net.springs_of[m].size(), 4u);
  const double omega = 2.0 * std::numbers::pi / o.natural_period_seconds;
  EXPECT_DOUBLE_EQ(net.stiffness, omega * omega);
  EXPECT_DOUBLE_EQ(net.damping, 2.0 * o.damping_ratio * omega);
  const nlohmann::json j = net.ToJson(rec);
  EXPECT_EQ(j["springs"].size(), 20u);
  EXPECT_EQ(j["springs"][0]["a"], "B0M0");
  EXPECT_EQ(j["units"], "m");
}

TEST(MocapNetwork, PointsThatCoincideAreNeverJoined) {
  // Marker 1 duplicated as marker 5 (a label written twice), and marker 2 placed on marker 3 in
  // one frame: a spring between them would have no direction there, so neither pair is chosen
  // although both are the most rigid pairs of their markers.
  const Recording bodies = testing::RigidBodies(1, 5, 60, 100.0);
  std::vector<std::string> labels = bodies.labels();
  labels.push_back("copy");
  Recording rec(labels, bodies.frames(), bodies.rate(), bodies.units());
  for (std::int64_t f = 0; f < rec.frames(); ++f) {
    for (int m = 0; m < 5; ++m) rec.SetPoint(f, m, bodies.point(f, m));
    rec.SetPoint(f, 5, bodies.point(f, 1));
  }
  rec.SetPoint(30, 2, rec.point(30, 3));
  MarkerNetworkOptions o;
  o.partners = 4;
  const MarkerNetwork net = BuildMarkerNetwork(rec, o);
  ASSERT_FALSE(net.springs.empty());
  for (const MarkerSpring& s : net.springs) {
    EXPECT_FALSE(s.a == 1 && s.b == 5) << "the duplicate joined";
    EXPECT_FALSE(s.a == 2 && s.b == 3) << "the pair that meets in frame 30 joined";
    EXPECT_GT(s.min, 0.0);
  }
}

TEST(MocapNetwork, BoundsFollowTheObservedRangeWithMargin) {
  Recording rec({"A", "B"}, 4, 50.0, "mm");
  const double x[] = {100.0, 110.0, 90.0, 105.0};
  for (int f = 0; f < 4; ++f) {
    rec.SetPoint(f, 0, Eigen::Vector3d::Zero());
    rec.SetPoint(f, 1, Eigen::Vector3d(x[f], 0.0, 0.0));
  }
  rec.ClearPoint(3, 1);  // only frames 0-2 are seen together
  MarkerNetworkOptions o;
  o.min_common_frames = 3;
  const MarkerNetwork net = BuildMarkerNetwork(rec, o);
  ASSERT_EQ(net.springs.size(), 1u);
  const MarkerSpring& s = net.springs[0];
  EXPECT_EQ(s.common_frames, 3);
  EXPECT_DOUBLE_EQ(s.mean, 100.0);
  EXPECT_NEAR(s.spread, std::sqrt(200.0 / 3.0), 1e-12);
  const double margin = o.bound_margin * 20.0 + o.bound_floor * 100.0;
  EXPECT_DOUBLE_EQ(s.rest_min, 90.0 - margin);
  EXPECT_DOUBLE_EQ(s.rest_max, 110.0 + margin);
  EXPECT_DOUBLE_EQ(net.length_scale, 100.0);
  o.min_common_frames = 4;  // now the pair is never a candidate: no spring
  EXPECT_TRUE(BuildMarkerNetwork(rec, o).springs.empty());
}

TEST(MocapNetwork, ExplicitSpringsReplaceTheAutomaticChoice) {
  const Recording rec = testing::RigidBodies(2, 4, 60, 100.0);
  MarkerNetworkOptions o;
  o.springs = {{"B0M0", "B1M3"}, {"B1M3", "B0M0"}};  // the same pair twice: one spring
  const MarkerNetwork net = BuildMarkerNetwork(rec, o);
  ASSERT_EQ(net.springs.size(), 1u);
  EXPECT_EQ(net.springs[0].a, 0);
  EXPECT_EQ(net.springs[0].b, 7);
  EXPECT_GT(net.springs[0].spread, 1e-3);  // across bodies: the distance varies
  EXPECT_EQ(net.Partner(0, 7), 0);
  o.springs = {{"B0M0", "nope"}};
  EXPECT_THROW(BuildMarkerNetwork(rec, o), InputError);
  o.springs = {{"B0M0", "B0M0"}};
  EXPECT_THROW(BuildMarkerNetwork(rec, o), InputError);
}

TEST(MocapNetwork, BadOptionsNameTheField) {
  const Recording rec = testing::RigidBodies(1, 4, 20, 100.0);
  auto message = [&](MarkerNetworkOptions o) {
    try {
      BuildMarkerNetwork(rec, o);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  MarkerNetworkOptions o;
  o.partners = 0;
  EXPECT_NE(message(o).find("partners: must be ≥ 1 (got 0)"), std::string::npos) << message(o);
  o = {};
  o.bound_margin = -1.0;
  EXPECT_NE(message(o).find("bound_margin: must be ≥ 0 (got -1)"), std::string::npos);
  o = {};
  o.natural_period_seconds = 0.0;
  EXPECT_NE(message(o).find("natural_period_seconds: must be > 0 (got 0)"), std::string::npos);
  o = {};
  o.min_common_frames = 1;
  EXPECT_NE(message(o).find("min_common_frames: must be ≥ 2 (got 1)"), std::string::npos);
}

}  // namespace
}  // namespace moreau::mocap
