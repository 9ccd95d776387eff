// C3D reading as the reference reader (BTK) reads: where the parameter chain ends, the labels of
// unlabelled points, and Motion Analysis files (names in POINT:DESCRIPTIONS, occluded points at
// 9999999). The files are built here byte by byte (Intel, float storage).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cstdint>
#include <fstream>
#include <string>
#include <vector>

#include "mocap/io_test_util.h"
#include "moreau/mocap/recording_io.h"

namespace moreau::mocap {
namespace {

using testing::ScratchDir;

std::string Int16(int value) {
  const auto bits = static_cast<std::uint16_t>(value);
  return {static_cast<char>(bits & 0xffu), static_cast<char>(bits >> 8)};
}

std::string Float32(float value) {
  const auto bits = std::bit_cast<std::uint32_t>(value);
  std::string out;
  for (int i = 0; i < 4; ++i) out.push_back(static_cast<char>((bits >> (8 * i)) & 0xffu));
  return out;
}

// A group (type 0) or a parameter of group `id`, of type −1, 2 or 4, without description.
struct Item {
  int id = 0;
  std::string name;
  int type = 0;
  std::vector<int> dimensions;
  std::string data;
};

Item Group(int id, std::string name) { return {-id, std::move(name), 0, {}, ""}; }
Item Short(int group, std::string name, int value) { return {group, name, 2, {}, Int16(value)}; }
Item Real(int group, std::string name, float value) { return {group, name, 4, {}, Float32(value)}; }
// Strings padded with spaces to the longest: dimensions [length, count].
Item Texts(int group, std::string name, const std::vector<std::string>& texts) {
  std::size_t length = 1;
  for (const std::string& t : texts) length = std::max(length, t.size());
  Item item{
      group, std::move(name), -1, {static_cast<int>(length), static_cast<int>(texts.size())}, ""};
  for (const std::string& t : texts) item.data += t + std::string(length - t.size(), ' ');
  return item;
}

constexpr std::size_t kBlock = 512;

// Header (block 1), one declared parameter block (block 2) and the points from block 3, each
// sample x, y, z, residual. The last item links to `last_link` bytes past its link (0: the end).
std::string C3dFile(const std::vector<Item>& items, int points,
                    const std::vector<std::array<float, 4>>& samples, int last_link = 0) {
  const int frames = static_cast<int>(samples.size()) / points;
  std::string file = std::string{2, 0x50} + Int16(points) + Int16(0) + Int16(1) + Int16(frames) +
                     Int16(0) + Float32(-1.0f) + Int16(3) + Int16(0) + Float32(50.0f);
  file.resize(kBlock, '\0');
  file += std::string{1, 0x50, 1, 84};
  for (std::size_t i = 0; i < items.size(); ++i) {
    const Item& item = items[i];
    std::string rest;
    if (item.id > 0) {
      rest = std::string{static_cast<char>(item.type), static_cast<char>(item.dimensions.size())};
      for (int d : item.dimensions) rest.push_back(static_cast<char>(d));
      rest += item.data;
    }
    rest.push_back('\0');  // description length
    const int link = i + 1 < items.size() ? static_cast<int>(2 + rest.size()) : last_link;
    file += std::string{static_cast<char>(item.name.size()), static_cast<char>(item.id)} +
            item.name + Int16(link) + rest;
  }
  EXPECT_LE(file.size(), 2 * kBlock);
  file.resize(2 * kBlock, '\0');
  for (const auto& s : samples) {
    for (float v : s) file += Float32(v);
  }
  return file;
}

std::filesystem::path Write(const ScratchDir& dir, const std::string& name,
                            const std::string& content) {
  std::ofstream(dir / name, std::ios::binary) << content;
  return dir / name;
}

std::vector<Item> PointGroup(int points, const std::vector<std::string>& labels,
                             const std::vector<std::string>& descriptions) {
  return {Group(1, "POINT"),
          Short(1, "USED", points),
          Real(1, "SCALE", -1.0f),
          Real(1, "RATE", 50.0f),
          Short(1, "DATA_START", 3),
          Texts(1, "LABELS", labels),
          Texts(1, "DESCRIPTIONS", descriptions)};
}

// BTK names a point beyond POINT:LABELS "uname*<its 1-based number>".
TEST(C3dReader, PointsBeyondTheLabelListAreNamedAsBtkNamesThem) {
  ScratchDir dir;
  const auto path = Write(
      dir, "short_list.c3d",
      C3dFile(PointGroup(3, {"A", "B"}, {"a"}), 3, {{1, 2, 3, 0}, {4, 5, 6, 0}, {7, 8, 9, 0}}));
  std::vector<std::string> warnings;
  const Recording r = ReadRecording(path, {}, &warnings);
  EXPECT_EQ(r.labels(), (std::vector<std::string>{"A", "B", "uname*3"}));
  EXPECT_EQ(r.descriptions(), (std::vector<std::string>{"a", "", ""}));
  EXPECT_TRUE(warnings.empty());
  EXPECT_EQ(r.point(0, 2), Eigen::Vector3d(7, 8, 9));
}

// Writers leave the last item's link pointing past the declared parameter blocks, into the data:
// the section ends there, silently, with every parameter before it read.
TEST(C3dReader, ParameterChainEndsAtTheDeclaredBlocks) {
  ScratchDir dir;
  const std::vector<std::array<float, 4>> samples = {{123.456f, -77.7f, 901.25f, 0.5f},
                                                     {-3.25f, 1234.5f, 66.125f, 1.5f}};
  std::vector<Item> items = PointGroup(2, {"A", "B"}, {"a", "b"});
  items.push_back(Group(2, "NEXT"));  // its link goes into block 3, the point data
  std::string file = C3dFile(items, 2, samples);
  const std::size_t link_at = file.rfind("NEXT") + 4;
  const int into_data = static_cast<int>(2 * kBlock - link_at);
  file = C3dFile(items, 2, samples, into_data);
  ASSERT_NE(file[link_at + static_cast<std::size_t>(into_data)], '\0');  // not an end byte
  std::vector<std::string> warnings;
  const Recording r = ReadRecording(Write(dir, "link_into_data.c3d", file), {}, &warnings);
  EXPECT_TRUE(warnings.empty()) << warnings.front();
  EXPECT_EQ(r.labels(), (std::vector<std::string>{"A", "B"}));
  EXPECT_EQ(r.descriptions(), (std::vector<std::string>{"a", "b"}));
  EXPECT_EQ(r.rate(), 50.0);
  EXPECT_EQ(r.point(0, 1), Eigen::Vector3d(-3.25, 1234.5, 66.125));
}

// Motion Analysis Corp. (MANUFACTURER:COMPANY) names its points in POINT:DESCRIPTIONS and marks
// occluded ones by 9999999; other files keep POINT:LABELS and read 9999999 as a position.
TEST(C3dReader, MotionAnalysisFilesNameTheirPointsByTheirDescriptions) {
  ScratchDir dir;
  const std::vector<std::array<float, 4>> samples = {
      {1, 2, 3, 0}, {9999999, 9999999, 9999999, 0}, {4, 5, 6, 0}, {7, 8, 9, 0}};
  for (const std::string company : {"Motion Analysis Corp.", "Vicon"}) {
    SCOPED_TRACE(company);
    std::vector<Item> items = PointGroup(2, {"RKNE", "RKNE"}, {"R.Knee", "R.Knee.Medial"});
    items.push_back(Group(2, "MANUFACTURER"));
    items.push_back(Texts(2, "Company", {company}));
    std::vector<std::string> warnings;
    const Recording r =
        ReadRecording(Write(dir, "file.c3d", C3dFile(items, 2, samples)), {}, &warnings);
    const bool motion = company != "Vicon";
    EXPECT_EQ(r.labels(), motion ? (std::vector<std::string>{"R.Knee", "R.Knee.Medial"})
                                 : (std::vector<std::string>{"RKNE", "RKNE_2"}));
    EXPECT_EQ(r.descriptions(), motion ? (std::vector<std::string>{"RKNE", "RKNE"})
                                       : (std::vector<std::string>{"R.Knee", "R.Knee.Medial"}));
    EXPECT_EQ(warnings.empty(), motion);
    EXPECT_EQ(r.observed(0, 1), !motion);
    EXPECT_TRUE(r.observed(0, 0) && r.observed(1, 0) && r.observed(1, 1));
  }
}

}  // namespace
}  // namespace moreau::mocap
