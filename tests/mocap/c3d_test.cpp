// C3D reading: the same recording in all six processor/storage formats, every sample file read or
// refused as SOURCES.md says, the faults real writers leave, DEC decoding, and bad input.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <fstream>
#include <map>
#include <set>

#include "mocap/c3d_format.h"
#include "mocap/io_test_util.h"
#include "moreau/common/error.h"
#include "moreau/mocap/inventory.h"
#include "moreau/mocap/recording_io.h"

namespace moreau::mocap {
namespace {

using testing::MocapData;
using testing::ScratchDir;

// The message of the InputError that `read` throws (empty when it throws none).
template <typename F>
std::string InputErrorOf(F&& read) {
  try {
    read();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

bool HasWarning(const std::vector<std::string>& warnings, const std::string& part) {
  for (const auto& w : warnings) {
    if (w.find(part) != std::string::npos) return true;
  }
  return false;
}

std::size_t MarkersWithGaps(const Recording& r) {
  std::set<int> markers;
  for (const Gap& g : FindGaps(r)) markers.insert(g.marker);
  return markers.size();
}

TEST(C3dNumbers, VaxFloatsDecodeToTheirValues) {
  const std::uint8_t one[4] = {0x80, 0x40, 0x00, 0x00};        // 0.1b × 2^1
  const std::uint8_t minus_2_5[4] = {0x20, 0xc1, 0x00, 0x00};  // −0.101b × 2^2
  const std::uint8_t zero[4] = {0x00, 0x00, 0x00, 0x00};
  const std::uint8_t third[4] = {0xaa, 0x3f, 0xab, 0xaa};  // 0.0101…b × 2^−1
  EXPECT_EQ(c3d::DecodeVaxFloat(one), 1.0f);
  EXPECT_EQ(c3d::DecodeVaxFloat(minus_2_5), -2.5f);
  EXPECT_EQ(c3d::DecodeVaxFloat(zero), 0.0f);
  EXPECT_NEAR(c3d::DecodeVaxFloat(third), 1.0f / 3.0f, 1e-7f);
  const c3d::NumberDecoder mips{c3d::Processor::kMips};
  const std::uint8_t ieee_one_be[4] = {0x3f, 0x80, 0x00, 0x00};
  const std::uint8_t minus_two_be[2] = {0xff, 0xfe};
  EXPECT_EQ(mips.Float(ieee_one_be), 1.0f);
  EXPECT_EQ(mips.Int16(minus_two_be), -2);
}

// Eb015: one recording in the Intel (p), SGI/MIPS (s) and DEC (v) formats with integer (i) and
// float (r) storage.
TEST(C3dRead, SixEb015FormatsGiveTheSamePositionsAndGaps) {
  const Recording reference = ReadRecording(MocapData("Eb015pr.c3d"));
  EXPECT_EQ(reference.markers(), 26);
  EXPECT_EQ(reference.frames(), 450);
  EXPECT_EQ(reference.rate(), 50.0);
  EXPECT_EQ(MarkersWithGaps(reference), 10u);
  const std::map<std::string, std::pair<std::string, std::string>> variants = {
      {"pi", {"intel", "integer"}}, {"pr", {"intel", "float"}}, {"si", {"mips", "integer"}},
      {"sr", {"mips", "float"}},    {"vi", {"dec", "integer"}}, {"vr", {"dec", "float"}}};
  for (const auto& [code, format] : variants) {
    SCOPED_TRACE(code);
    std::vector<std::string> warnings;
    const Recording r = ReadRecording(MocapData("Eb015" + code + ".c3d"), {}, &warnings);
    EXPECT_TRUE(warnings.empty());
    EXPECT_EQ(r.format().processor, format.first);
    EXPECT_EQ(r.format().storage, format.second);
    const double tolerance = format.second == "float" ? 1e-3 : std::abs(r.format().scale);
    testing::ExpectSameRecording(reference, r, tolerance);
    EXPECT_EQ(r.descriptions(), reference.descriptions());
    const auto gaps = FindGaps(r), reference_gaps = FindGaps(reference);
    ASSERT_EQ(gaps.size(), reference_gaps.size());
    for (std::size_t i = 0; i < gaps.size(); ++i) {
      EXPECT_EQ(gaps[i].marker, reference_gaps[i].marker);
      EXPECT_EQ(gaps[i].first, reference_gaps[i].first);
      EXPECT_EQ(gaps[i].last, reference_gaps[i].last);
    }
  }
}

// SOURCES.md's table: markers, frames, rate and markers with gaps of every readable file.
TEST(C3dRead, SampleFilesMatchTheirDescription) {
  struct Expected {
    std::string file;
    int markers;
    std::int64_t frames;
    double rate;
    std::size_t markers_with_gaps;
  };
  const std::vector<Expected> table = {{"Qualisys.c3d", 55, 340, 200.0, 0},
                                       {"Vicon.c3d", 51, 580, 100.0, 13},
                                       {"upper_body_25hz.c3d", 23, 670, 25.0, 0}};
  for (const Expected& e : table) {
    SCOPED_TRACE(e.file);
    const Recording r = ReadRecording(MocapData(e.file));
    EXPECT_EQ(r.markers(), e.markers);
    EXPECT_EQ(r.frames(), e.frames);
    EXPECT_EQ(r.rate(), e.rate);
    EXPECT_EQ(MarkersWithGaps(r), e.markers_with_gaps);
    EXPECT_EQ(r.units(), "mm");
  }
}

// Every file but the truncated Optotrak.c3d reads, whatever files the folder gains; a refusal is
// one line naming the file.
TEST(C3dRead, EverySampleFileIsReadOrRefusedWithOneLineNamingIt) {
  std::vector<std::string> read, refused;
  for (const auto& entry : std::filesystem::directory_iterator(MocapData(""))) {
    if (entry.path().extension() != ".c3d") continue;
    SCOPED_TRACE(entry.path().string());
    const std::string error = InputErrorOf([&] { (void)ReadRecording(entry.path()); });
    (error.empty() ? read : refused).push_back(entry.path().filename().string());
    if (error.empty()) continue;
    EXPECT_NE(error.find(entry.path().string()), std::string::npos);
    EXPECT_EQ(error.find('\n'), std::string::npos);
  }
  EXPECT_EQ(refused, std::vector<std::string>{"Optotrak.c3d"});  // the only truncated file
  EXPECT_GE(read.size(), 14u);  // SOURCES.md's readable files at least
  EXPECT_NE(std::find(read.begin(), read.end(), "phasespace_sample.c3d"), read.end());
}

// A little-endian IEEE single at `bytes`, decoded here without the reader's decoder.
float LittleEndianFloat(const char* bytes) {
  std::uint32_t word = 0;
  for (int i = 0; i < 4; ++i) word |= std::uint32_t{static_cast<std::uint8_t>(bytes[i])} << (8 * i);
  return std::bit_cast<float>(word);
}

std::string FileBytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

// PhaseSpace declares no parameters: the header's point count, frame range, float scale and
// rate describe the data, which fill the file from block 3 to its end; the points are named as
// BTK names them (uname*1, …), with one warning. Every sample is checked
// against the file's own bytes: missing where the residual is negative (or x = y = z = 0),
// else the stored position.
TEST(C3dRead, FileWithoutParametersIsReadFromItsHeader) {
  const auto path = MocapData("phasespace_sample.c3d");
  std::vector<std::string> warnings;
  const Recording r = ReadRecording(path, {}, &warnings);
  EXPECT_EQ(r.markers(), 40);
  EXPECT_EQ(r.frames(), 701);
  EXPECT_EQ(r.rate(), 30.0);
  EXPECT_EQ(r.first_frame(), 1);
  EXPECT_EQ(r.units(), "mm");
  EXPECT_EQ(r.format().processor, "intel");
  EXPECT_EQ(r.format().storage, "float");
  for (int m = 0; m < r.markers(); ++m) {
    EXPECT_EQ(r.labels()[static_cast<std::size_t>(m)], "uname*" + std::to_string(m + 1));
  }
  ASSERT_EQ(warnings.size(), 1u);
  for (const char* part : {"no parameters", "header", "uname*1 … uname*40", "mm"}) {
    EXPECT_NE(warnings[0].find(part), std::string::npos) << part;
  }
  EXPECT_NE(warnings[0].find(path.string()), std::string::npos);
  const std::string bytes = FileBytes(path);
  const std::size_t point_bytes = 4 * 4, data_start = 2 * c3d::kBlockBytes;
  ASSERT_EQ(bytes.size(),
            data_start + static_cast<std::size_t>(r.frames() * r.markers()) * point_bytes);
  std::int64_t missing = 0;
  for (std::int64_t f = 0; f < r.frames(); ++f) {
    for (int m = 0; m < r.markers(); ++m) {
      const char* at =
          bytes.data() + data_start + static_cast<std::size_t>(f * r.markers() + m) * point_bytes;
      const Eigen::Vector3d stored(static_cast<double>(LittleEndianFloat(at)),
                                   static_cast<double>(LittleEndianFloat(at + 4)),
                                   static_cast<double>(LittleEndianFloat(at + 8)));
      const bool absent = LittleEndianFloat(at + 12) < 0.0f || stored.isZero(0.0);
      ASSERT_EQ(r.observed(f, m), !absent) << "frame " << f << " marker " << m;
      missing += absent ? 1 : 0;
      if (absent) continue;
      ASSERT_TRUE(stored.allFinite());
      ASSERT_EQ(r.point(f, m), stored);
      ASSERT_LT(stored.norm(), 1e4);  // within 10 m of the origin
    }
  }
  EXPECT_GT(missing, 0);  // the file has gaps, and the reader keeps them
  EXPECT_LT(missing, r.frames() * r.markers() / 10);
}

TEST(C3dRead, TruncatedFileIsRefusedOrReadAsFarAsItGoes) {
  const auto path = MocapData("Optotrak.c3d");
  const std::string error = InputErrorOf([&] { (void)ReadRecording(path); });
  EXPECT_NE(error.find(path.string()), std::string::npos);
  EXPECT_NE(error.find("1149"), std::string::npos);
  EXPECT_NE(error.find("29"), std::string::npos);
  ReadOptions options;
  options.allow_truncated = true;
  std::vector<std::string> warnings;
  const Recording r = ReadRecording(path, options, &warnings);
  // 54 markers in float storage, no analog data, from block 8: the bytes hold whole frames only.
  const auto size = static_cast<std::int64_t>(std::filesystem::file_size(path));
  EXPECT_EQ(r.frames(), (size - 7 * 512) / (54 * 4 * 4));
  EXPECT_EQ(r.frames(), 29);
  EXPECT_EQ(r.markers(), 54);
  EXPECT_EQ(r.rate(), 30.0);
  EXPECT_TRUE(HasWarning(warnings, "truncated"));
}

TEST(C3dRead, CorruptParameterSectionIsReadUpToTheCorruptItem) {
  std::vector<std::string> warnings;
  const Recording r = ReadRecording(MocapData("bad_parameter_section.c3d"), {}, &warnings);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("parameter section"), std::string::npos);
  EXPECT_NE(warnings[0].find("offset -1"), std::string::npos);
  EXPECT_GT(r.markers(), 0);
  EXPECT_GT(r.frames(), 0);
  for (std::int64_t f = 0; f < r.frames(); ++f) {
    for (int m = 0; m < r.markers(); ++m) {
      if (r.observed(f, m)) {
        ASSERT_LT(r.point(f, m).norm(), 1e4);  // within 10 m of the origin
      }
    }
  }
}

TEST(C3dRead, MissingParametersFallBackToTheHeaderAndDuplicateLabelsAreRenamed) {
  const auto path = MocapData("standing_bts.c3d");
  std::vector<std::string> warnings;
  const Recording r = ReadRecording(path, {}, &warnings);
  EXPECT_TRUE(HasWarning(warnings, "POINT:SCALE"));
  EXPECT_TRUE(HasWarning(warnings, "POINT:RATE"));
  EXPECT_TRUE(HasWarning(warnings, "POINT:DATA_START"));
  EXPECT_TRUE(HasWarning(warnings, "labels renamed"));
  EXPECT_EQ(r.format().storage, "float");
  // 38 markers and 6 analog values per frame in floats from block 5: the file holds whole frames.
  EXPECT_EQ(r.markers(), 38);
  const auto size = static_cast<std::int64_t>(std::filesystem::file_size(path));
  EXPECT_EQ(r.frames(), (size - 4 * 512) / ((38 * 4 + 6) * 4));
  std::set<std::string> unique(r.labels().begin(), r.labels().end());
  EXPECT_EQ(unique.size(), r.labels().size());
}

// DEC floats decoded wrongly give wrong scales or noise; the pelvis markers (R.ASIS, L.ASIS,
// V.Sacral) sit on one rigid segment, so their distances stay nearly constant and human-sized.
// Gait.c3d comes from Motion Analysis (EVa RealTime): its points are named by POINT:DESCRIPTIONS
// (unique), its 4-letter POINT:LABELS (RKNE twice: knee and medial knee) become descriptions.
TEST(C3dRead, GaitDecFileDecodesToARigidPelvis) {
  std::vector<std::string> warnings;
  const Recording r = ReadRecording(MocapData("Gait.c3d"), {}, &warnings);
  EXPECT_EQ(r.format().processor, "dec");
  EXPECT_EQ(r.markers(), 33);
  EXPECT_EQ(r.frames(), 487);
  EXPECT_EQ(r.rate(), 100.0);
  EXPECT_TRUE(warnings.empty());
  const int knee = r.FindMarker("R.Knee"), medial = r.FindMarker("R.Knee.Medial");
  ASSERT_GE(std::min(knee, medial), 0);
  EXPECT_EQ(r.descriptions()[static_cast<std::size_t>(knee)], "RKNE");
  EXPECT_EQ(r.descriptions()[static_cast<std::size_t>(medial)], "RKNE");
  EXPECT_EQ(r.labels().front(), "R.Shoulder");
  EXPECT_EQ(r.labels().back(), "PX");
  const int rasi = r.FindMarker("R.ASIS"), lasi = r.FindMarker("L.ASIS"),
            vsac = r.FindMarker("V.Sacral");
  ASSERT_GE(std::min({rasi, lasi, vsac}), 0);
  for (const auto& [a, b] : {std::pair{rasi, lasi}, std::pair{rasi, vsac}, std::pair{lasi, vsac}}) {
    std::vector<double> d;
    for (std::int64_t f = 0; f < r.frames(); ++f) {
      if (r.observed(f, a) && r.observed(f, b)) d.push_back((r.point(f, a) - r.point(f, b)).norm());
    }
    ASSERT_GT(d.size(), 100u);
    double mean = 0.0, var = 0.0;
    for (double x : d) mean += x / static_cast<double>(d.size());
    for (double x : d) var += (x - mean) * (x - mean) / static_cast<double>(d.size());
    EXPECT_GT(mean, 80.0);  // mm: pelvis landmarks are 8–35 cm apart
    EXPECT_LT(mean, 350.0);
    EXPECT_LT(std::sqrt(var), 0.03 * mean);
  }
}

TEST(C3dRead, ZeroPointsAreMissingUnlessSwitchedOff) {
  ScratchDir dir;
  Recording r({"A", "B"}, 2, 100.0);
  r.SetPoint(0, 0, Eigen::Vector3d(1.0, 2.0, 3.0));
  r.SetPoint(0, 1, Eigen::Vector3d::Zero());
  WriteC3d(r, dir / "zero.c3d");
  EXPECT_FALSE(ReadRecording(dir / "zero.c3d").observed(0, 1));
  ReadOptions keep;
  keep.zero_is_missing = false;
  const Recording kept = ReadRecording(dir / "zero.c3d", keep);
  EXPECT_TRUE(kept.observed(0, 1));
  EXPECT_TRUE(kept.observed(0, 0));
  EXPECT_FALSE(kept.observed(1, 0));  // residual −1 stays missing
}

TEST(C3dRead, UnitsAreReportedAndConvertible) {
  const ReadOptions metres{.units = "m"};
  const Recording mm = ReadRecording(MocapData("Qualisys.c3d"));
  const Recording m = ReadRecording(MocapData("Qualisys.c3d"), metres);
  EXPECT_EQ(m.units(), "m");
  EXPECT_NEAR(m.point(10, 3).x(), mm.point(10, 3).x() / 1000.0, 1e-12);
}

TEST(C3dRead, BadInputIsOneInputErrorNamingTheFile) {
  ScratchDir dir;
  const auto write = [&](const std::string& name, const std::string& content) {
    std::ofstream(dir / name, std::ios::binary) << content;
    return dir / name;
  };
  const std::string qualisys = FileBytes(MocapData("Qualisys.c3d"));
  const std::string phasespace = FileBytes(MocapData("phasespace_sample.c3d"));
  // The empty parameter section's end byte replaced by an item of no group: nothing readable.
  std::string unreadable = phasespace;
  unreadable[c3d::kBlockBytes + 4] = 1;
  const std::vector<std::pair<std::filesystem::path, std::string>> cases = {
      {dir / "absent.c3d", "does not exist"},
      {dir.path(), "extension"},
      {write("short.c3d", "C3D?"), "header"},
      {write("text.c3d", std::string(600, 'x')), "not a C3D file"},
      {write("cut.c3d", qualisys.substr(0, 40000)), "truncated"},
      {write("cut_header_only.c3d", phasespace.substr(0, 100000)), "truncated"},
      {write("unreadable_parameters.c3d", unreadable), "no parameter could be read"},
      {write("recording.txt", qualisys), "extension"},
  };
  for (const auto& [path, reason] : cases) {
    SCOPED_TRACE(path.string());
    const std::string error = InputErrorOf([&file = path] { (void)ReadRecording(file); });
    EXPECT_NE(error.find(path.string()), std::string::npos) << error;
    EXPECT_NE(error.find(reason), std::string::npos) << error;
    EXPECT_EQ(error.find('\n'), std::string::npos);
  }
  const std::string directory = InputErrorOf([&] { (void)ReadC3d(dir.path()); });
  EXPECT_NE(directory.find("is a directory"), std::string::npos);
}

}  // namespace
}  // namespace moreau::mocap
