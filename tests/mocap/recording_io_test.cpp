// Writing recordings: round trips C3D → C3D, C3D → TRC → C3D and C3D → CSV → C3D, more than
// 65535 frames and more than 255 markers, atomic writes, the inventory, and malformed TRC/CSV.
#include <gtest/gtest.h>

#include <fmt/format.h>

#include <fstream>
#include <sstream>

#include "mocap/c3d_format.h"
#include "mocap/io_test_util.h"
#include "moreau/common/error.h"
#include "moreau/mocap/inventory.h"
#include "moreau/mocap/recording_io.h"

namespace moreau::mocap {
namespace {

using testing::ExpectSameRecording;
using testing::MocapData;
using testing::ScratchDir;

std::string Slurp(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

// Largest position magnitude: float storage keeps positions to within half a float ulp of it.
double FloatTolerance(const Recording& r) {
  double largest = 0.0;
  for (double v : r.positions()) {
    if (std::isfinite(v)) largest = std::max(largest, std::abs(v));
  }
  return largest * 0x1p-24;
}

TEST(RecordingWrite, RoundTripsThroughEveryFormatKeepSamplesGapsLabelsRateAndUnits) {
  ScratchDir dir;
  for (const char* source : {"Vicon.c3d", "Eb015pi.c3d", "Gait.c3d"}) {
    SCOPED_TRACE(source);
    const Recording original = ReadRecording(MocapData(source));
    const double tolerance = FloatTolerance(original);
    WriteRecording(original, dir / "copy.c3d");
    const Recording c3d = ReadRecording(dir / "copy.c3d");
    ExpectSameRecording(original, c3d, tolerance);
    EXPECT_EQ(c3d.descriptions(), original.descriptions());
    EXPECT_EQ(c3d.format().storage, "float");
    for (const char* text : {"copy.trc", "copy.csv"}) {
      SCOPED_TRACE(text);
      WriteRecording(c3d, dir / text);
      const Recording via_text = ReadRecording(dir / text);
      ExpectSameRecording(c3d, via_text, 0.0);  // shortest decimal text is exact
      WriteRecording(via_text, dir / "again.c3d");
      ExpectSameRecording(original, ReadRecording(dir / "again.c3d"), tolerance);
    }
  }
}

TEST(RecordingWrite, UnitsOtherThanMillimetresSurviveC3dAndTrc) {
  ScratchDir dir;
  ReadOptions metres;
  metres.units = "m";
  const Recording m = ReadRecording(MocapData("Eb015pr.c3d"), metres);
  for (const char* name : {"m.c3d", "m.trc"}) {
    WriteRecording(m, dir / name);
    const Recording back = ReadRecording(dir / name);
    EXPECT_EQ(back.units(), "m") << name;
    ExpectSameRecording(m, back, FloatTolerance(m));
  }
  ReadOptions csv_in_metres;
  csv_in_metres.units_if_unstated = "m";
  WriteRecording(m, dir / "m.csv");
  ExpectSameRecording(m, ReadRecording(dir / "m.csv", csv_in_metres), 0.0);
}

// Positions that floats hold exactly, with a gap every 7th frame of marker 1.
Recording Synthetic(int markers, std::int64_t frames) {
  std::vector<std::string> labels;
  for (int m = 0; m < markers; ++m) labels.push_back(fmt::format("M{}", m + 1));
  Recording r(labels, frames, 240.0);
  for (std::int64_t f = 0; f < frames; ++f) {
    for (int m = 0; m < markers; ++m) {
      if (m == 1 && f % 7 == 3) continue;
      r.SetPoint(f, m,
                 Eigen::Vector3d(0.25 * static_cast<double>(f % 4000), m + 1.5, -0.5 * m - 1.0));
    }
  }
  return r;
}

TEST(RecordingWrite, MoreThan65535FramesUseTrialFieldsAndReadBackIdentically) {
  ScratchDir dir;
  Recording r = Synthetic(2, 70001);
  r.set_first_frame(5);
  WriteC3d(r, dir / "long.c3d");
  ExpectSameRecording(r, ReadRecording(dir / "long.c3d"), 0.0);
  std::vector<std::string> warnings;
  const std::string bytes = Slurp(dir / "long.c3d");
  const auto section = c3d::ParseParameterSection(
      std::span(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size()), 512,
      dir / "long.c3d", warnings);
  EXPECT_TRUE(warnings.empty());
  // A 16-bit count saturated at 65535 (ezc3d rejects a float), as the header's last frame.
  EXPECT_EQ(section.Find("POINT", "FRAMES")->type, 2);
  EXPECT_EQ(section.Count("POINT", "FRAMES").value_or(0), 65535);
  const auto end_low = section.Count("TRIAL", "ACTUAL_END_FIELD", 0);
  const auto end_high = section.Count("TRIAL", "ACTUAL_END_FIELD", 1);
  EXPECT_EQ(*end_low + 65536 * *end_high, 5 + 70001 - 1);
}

TEST(RecordingWrite, MoreThan255MarkersUseLabels2AndReadBackIdentically) {
  ScratchDir dir;
  const Recording r = Synthetic(600, 3);
  WriteC3d(r, dir / "wide.c3d");
  ExpectSameRecording(r, ReadRecording(dir / "wide.c3d"), 0.0);
  std::vector<std::string> warnings;
  const std::string bytes = Slurp(dir / "wide.c3d");
  const auto section = c3d::ParseParameterSection(
      std::span(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size()), 512,
      dir / "wide.c3d", warnings);
  EXPECT_EQ(section.Strings("POINT", "LABELS").size(), 255u);
  EXPECT_EQ(section.Strings("POINT", "LABELS2").size(), 255u);
  EXPECT_EQ(section.Strings("POINT", "LABELS3").size(), 90u);
  EXPECT_EQ(section.Strings("POINT", "LABELS3").back(), "M600");
}

TEST(RecordingWrite, WritesAreAtomicAndFailuresNameTheFile) {
  ScratchDir dir;
  const Recording r = Synthetic(3, 10);
  WriteRecording(r, dir / "out.trc");
  for (const auto& entry : std::filesystem::directory_iterator(dir.path())) {
    EXPECT_EQ(entry.path().filename(), "out.trc");  // no temporary left behind
  }
  const auto message = [](const auto& write) -> std::string {
    try {
      write();
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  };
  const auto missing_dir = dir / "no" / "such.c3d";
  EXPECT_NE(message([&] { WriteRecording(r, missing_dir); }).find(missing_dir.string()),
            std::string::npos);
  EXPECT_FALSE(std::filesystem::exists(missing_dir));
  EXPECT_NE(message([&] { WriteRecording(r, dir / "out.xyz"); }).find("extension"),
            std::string::npos);
  Recording comma({"a,b"}, 1, 10.0);
  EXPECT_NE(message([&] { WriteRecording(comma, dir / "comma.csv"); }).find("comma"),
            std::string::npos);
  EXPECT_FALSE(std::filesystem::exists(dir / "comma.csv"));
}

TEST(RecordingText, MissingSamplesAreBlankFields) {
  ScratchDir dir;
  const Recording r = Synthetic(2, 5);  // marker 2 missing at frame 3
  WriteRecording(r, dir / "r.csv");
  WriteRecording(r, dir / "r.trc");
  std::istringstream csv(Slurp(dir / "r.csv"));
  std::string line;
  std::getline(csv, line);
  EXPECT_EQ(line, "frame,time,marker,x,y,z");
  int blank_rows = 0, rows = 0;
  while (std::getline(csv, line)) {
    ++rows;
    if (line.ends_with(",,,")) {
      ++blank_rows;
      EXPECT_TRUE(line.starts_with("4,") && line.find(",M2,") != std::string::npos) << line;
    }
  }
  EXPECT_EQ(rows, 10);
  EXPECT_EQ(blank_rows, 1);
  EXPECT_NE(Slurp(dir / "r.trc").find("\n4\t0.0125\t0.75\t1.5\t-1\t\t\t\n"), std::string::npos);
}

TEST(RecordingText, MalformedFilesGiveOneLineErrorsNamingFileAndField) {
  ScratchDir dir;
  const auto check = [&](const std::string& name, const std::string& content,
                         const std::string& field) {
    std::ofstream(dir / name) << content;
    try {
      (void)ReadRecording(dir / name);
      ADD_FAILURE() << name << " was read";
    } catch (const InputError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find((dir / name).string()), std::string::npos) << what;
      EXPECT_NE(what.find(field), std::string::npos) << what;
      EXPECT_EQ(what.find('\n'), std::string::npos);
    }
  };
  check("header.csv", "frame,time,x\n", "header");
  check("fields.csv", "frame,time,marker,x,y,z\n1,0,A,1,2\n", "line 2");
  check("number.csv", "frame,time,marker,x,y,z\n1,0,A,1,two,3\n2,0.1,A,1,2,3\n", "line 2, y");
  check("twice.csv", "frame,time,marker,x,y,z\n1,0,A,1,2,3\n1,0,A,1,2,3\n", "twice");
  check("single.csv", "frame,time,marker,x,y,z\n1,0,A,1,2,3\n", "rate_if_unstated");
  check("notrc.trc", "hello\n", "line 1");
  const std::string trc_head =
      "PathFileType\t4\t(X/Y/Z)\tx.trc\nDataRate\tCameraRate\tNumFrames\tNumMarkers\tUnits\n"
      "100\t100\t3\t1\tmm\nFrame#\tTime\tA\t\t\n\t\tX1\tY1\tZ1\n";
  check("short.trc", trc_head + "1\t0\t1\t2\t3\n", "truncated");
  check("units.trc",
        "PathFileType\t4\nDataRate\tNumFrames\tNumMarkers\tUnits\n100\t1\t1\tinch\n"
        "Frame#\tTime\tA\n\t\tX1\tY1\tZ1\n1\t0\t1\t2\t3\n",
        "Units");
  check("value.trc", trc_head + "1\t0\t1\t2\t3\n2\t0.01\t1\tx\t3\n3\t0.02\t1\t2\t3\n",
        "line 7, column 4");
}

TEST(RecordingInventory, ListsMarkersFramesFormatAndGaps) {
  std::vector<std::string> warnings;
  const Recording r = ReadRecording(MocapData("Eb015vi.c3d"), {}, &warnings);
  const RecordingInventory inv = TakeInventory(r, warnings);
  EXPECT_EQ(inv.markers, 26);
  EXPECT_EQ(inv.frames, 450);
  EXPECT_DOUBLE_EQ(inv.duration_seconds, 9.0);
  const auto gaps = FindGaps(r);
  ASSERT_EQ(inv.gaps.size(), gaps.size());
  std::int64_t missing = 0;
  for (std::size_t i = 0; i < gaps.size(); ++i) {
    EXPECT_EQ(inv.gaps[i].marker, r.labels()[static_cast<std::size_t>(gaps[i].marker)]);
    EXPECT_DOUBLE_EQ(inv.gaps[i].length_seconds, static_cast<double>(gaps[i].length()) / 50.0);
    missing += gaps[i].length();
  }
  const nlohmann::json j = inv.ToJson();
  EXPECT_EQ(j["format"]["processor"], "dec");
  EXPECT_EQ(j["format"]["storage"], "integer");
  EXPECT_EQ(j["rate"], 50.0);
  EXPECT_EQ(j["units"], "mm");
  EXPECT_EQ(j["missing_samples"], missing);
  EXPECT_EQ(j["gaps"].size(), gaps.size());
  EXPECT_EQ(j["gaps"][0]["length_frames"], gaps[0].length());
}

}  // namespace
}  // namespace moreau::mocap
