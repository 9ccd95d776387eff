// Point types: the model outputs a C3D file names in POINT:ANGLES, FORCES, MOMENTS, POWERS,
// SCALARS and REACTIONS are read as such, kept out of the gaps and the fills, and written back.
#include <gtest/gtest.h>

#include "mocap/c3d_format.h"
#include "mocap/file_util.h"
#include "mocap/io_test_util.h"
#include "mocap/synthetic.h"
#include "moreau/mocap/evaluate.h"
#include "moreau/mocap/gap_fill.h"
#include "moreau/mocap/inventory.h"
#include "moreau/mocap/recording_io.h"

namespace moreau::mocap {
namespace {

using testing::MocapData;
using testing::ScratchDir;

// The labels that the file's POINT:<list> names and that label a point.
int CountListed(const c3d::ParameterSection& p, std::string_view list,
                const std::vector<std::string>& labels) {
  int n = 0;
  for (const std::string& name : p.Strings("POINT", list)) {
    n += static_cast<int>(std::count(labels.begin(), labels.end(), name) > 0);
  }
  return n;
}

TEST(PointTypes, PlugInGaitOutputsAreTypedAsTheFileListsThem) {
  const Recording r = ReadRecording(MocapData("PlugInC3D.c3d"));
  const std::string content = internal::ReadWholeFile(MocapData("PlugInC3D.c3d"));
  const std::span<const std::uint8_t> bytes(reinterpret_cast<const std::uint8_t*>(content.data()),
                                            content.size());
  std::vector<std::string> warnings;
  const c3d::ParameterSection p = c3d::ParseParameterSection(
      bytes, (std::size_t{bytes[0]} - 1) * c3d::kBlockBytes, MocapData("PlugInC3D.c3d"), warnings);
  int outputs = 0;
  for (const auto& group : c3d::kPointTypeParameters) {
    const int listed = CountListed(p, group.labels, r.labels());
    EXPECT_EQ(r.CountPoints(group.type), listed) << group.labels;
    outputs += listed;
  }
  EXPECT_EQ(r.markers(), 86);
  EXPECT_EQ(r.CountPoints(PointType::kMarker), 54);
  EXPECT_EQ(outputs, 32);
  EXPECT_EQ(r.CountPoints(PointType::kAngle), 10);
  EXPECT_EQ(r.CountPoints(PointType::kForce), 8);
  EXPECT_EQ(r.CountPoints(PointType::kMoment), 8);
  EXPECT_EQ(r.CountPoints(PointType::kPower), 6);
  EXPECT_EQ(r.type_units(PointType::kAngle), "deg");
  for (int m = 0; m < r.markers(); ++m) {
    const std::string& label = r.labels()[static_cast<std::size_t>(m)];
    if (label.find("Angles") != std::string::npos) {
      EXPECT_EQ(r.type(m), PointType::kAngle) << label;
    }
  }
  const RecordingInventory inv = TakeInventory(r);
  EXPECT_EQ(inv.markers, 54);
  EXPECT_EQ(inv.model_outputs.size(), 32u);
  EXPECT_EQ(inv.labels.size(), 54u);
  EXPECT_EQ(inv.ToJson()["point_types"]["angle"], 10);
  for (const Gap& gap : FindGaps(r)) EXPECT_TRUE(r.is_marker(gap.marker));
}

// A recording of two markers and an angle, the angle and one marker with a hole.
Recording MixedRecording() {
  Recording r({"A", "B", "KneeAngle"}, 20, 100.0);
  r.set_type(2, PointType::kAngle);
  r.set_type_units(PointType::kAngle, "deg");
  for (std::int64_t f = 0; f < r.frames(); ++f) {
    const double t = static_cast<double>(f);
    r.SetPoint(f, 0, Eigen::Vector3d(t, 1.0, 2.0));
    r.SetPoint(f, 1, Eigen::Vector3d(2.0 * t, 3.0, 4.0));
    r.SetPoint(f, 2, Eigen::Vector3d(10.0 + t, -5.0, 0.5));
  }
  for (std::int64_t f = 5; f < 9; ++f) {
    r.ClearPoint(f, 0);
    r.ClearPoint(f, 2);
  }
  return r;
}

TEST(PointTypes, GapsAndFillsLeaveModelOutputsAlone) {
  const Recording r = MixedRecording();
  const std::vector<Gap> gaps = FindGaps(r);
  ASSERT_EQ(gaps.size(), 1u);
  EXPECT_EQ(gaps[0].marker, 0);
  EXPECT_THROW(CheckGaps(r, {Gap{2, 5, 8}}), InputError);
  GapFillOptions options;
  options.method = GapFillMethod::kLinear;
  Recording filled;
  FillGaps(r, gaps, options, &filled);
  for (std::int64_t f = 5; f < 9; ++f) {
    EXPECT_TRUE(filled.observed(f, 0));
    EXPECT_DOUBLE_EQ(filled.point(f, 0)[0], static_cast<double>(f));
    EXPECT_FALSE(filled.observed(f, 2));
  }
  EXPECT_EQ(filled.type(2), PointType::kAngle);
}

TEST(PointTypes, UnitConversionScalesMarkersOnly) {
  Recording r = MixedRecording();
  r.ConvertUnits("m");
  EXPECT_DOUBLE_EQ(r.point(1, 1)[0], 2e-3);
  EXPECT_DOUBLE_EQ(r.point(1, 2)[0], 11.0);
}

TEST(PointTypes, C3dWriterRoundTripsTypesAndUnits) {
  ScratchDir dir;
  Recording r = MixedRecording();
  r.set_type(1, PointType::kPower);
  WriteRecording(r, dir / "mixed.c3d");
  const Recording back = ReadRecording(dir / "mixed.c3d");
  EXPECT_EQ(back.types(), r.types());
  EXPECT_EQ(back.type_units(PointType::kAngle), "deg");
  EXPECT_EQ(back.type_units(PointType::kPower), "");
  testing::ExpectSameRecording(r, back, 1e-5);

  const Recording plug_in = ReadRecording(MocapData("PlugInC3D.c3d"));
  WriteRecording(plug_in, dir / "plug_in.c3d");
  const Recording plug_in_back = ReadRecording(dir / "plug_in.c3d");
  EXPECT_EQ(plug_in_back.types(), plug_in.types());
  for (const PointType type : AllPointTypes()) {
    EXPECT_EQ(plug_in_back.type_units(type), plug_in.type_units(type)) << ToString(type);
  }
}

TEST(PointTypes, PlugInGaitFillTouchesMarkersOnly) {
  ScratchDir dir;
  const Recording in = ReadRecording(MocapData("PlugInC3D.c3d"));
  GapFillOptions options;
  options.method = GapFillMethod::kLinear;
  Recording filled;
  const FillSummary summary = FillGaps(in, FindGaps(in), options, &filled);
  for (const GapReport& gap : summary.gaps) EXPECT_TRUE(in.is_marker(gap.marker));
  WriteRecording(filled, dir / "filled.c3d");
  const Recording back = ReadRecording(dir / "filled.c3d");
  EXPECT_EQ(back.types(), in.types());
  for (int m = 0; m < in.markers(); ++m) {
    if (in.is_marker(m)) continue;
    for (std::int64_t f = 0; f < in.frames(); ++f) {
      ASSERT_EQ(back.observed(f, m), in.observed(f, m)) << m << " " << f;
      if (!in.observed(f, m)) continue;
      const double scale = 1.0 + in.point(f, m).cwiseAbs().maxCoeff();
      EXPECT_LE((back.point(f, m) - in.point(f, m)).cwiseAbs().maxCoeff(), 1e-6 * scale);
    }
  }
}

TEST(PointTypes, EvaluationHidesMarkersOnly) {
  Recording body = testing::MakeRigidBodyRecording(6, 150, 100.0, 1);
  body.set_type(1, PointType::kAngle);
  body.set_type(4, PointType::kForce);
  for (std::int64_t f = 0; f < 10; ++f) body.ClearPoint(f, 4);  // outputs may have holes
  EvaluationOptions options;
  options.methods = {GapFillMethod::kLinear, GapFillMethod::kRigid};
  options.gap_seconds = {0.05, 0.2};
  options.trials = 8;
  options.seed = 3;
  const EvaluationSummary summary = EvaluateFillMethods(body, options);
  ASSERT_EQ(summary.rows.size(), 2u * 2u * 8u);
  for (const EvaluationRow& row : summary.rows) EXPECT_TRUE(body.is_marker(row.marker));
  options.markers_per_gap = 5;  // four markers
  EXPECT_THROW(EvaluateFillMethods(body, options), InputError);
}

}  // namespace
}  // namespace moreau::mocap
