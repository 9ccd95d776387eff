// Text trajectories (include/moreau/io/text_trajectory.h): the header PedPy reads, rows only for
// the frames on the stride, positions back to the written decimals, centimetre files, bad input.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <string>
#include <vector>

#include "io/io_test_util.h"
#include "moreau/common/error.h"
#include "moreau/io/text_trajectory.h"

namespace moreau::io {
namespace {

using test_util::ReadText;
using test_util::TempDir;

void WriteFile(const std::filesystem::path& path, const std::string& text) {
  std::ofstream(path) << text;
}

std::string ReadError(const std::filesystem::path& path) {
  try {
    ReadTextTrajectory(path);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(TextTrajectory, WritesTheStrideFramesAndReadsThemBack) {
  TempDir dir;
  const auto path = dir.path() / "trajectory.txt";
  TextTrajectoryOptions options;
  options.frame_rate = 4.0;
  options.steps_per_frame = 5;
  options.comments = {"scenario: crowd.toml"};
  auto writer = MakeTextTrajectoryWriter(path, options);
  const std::vector<std::int64_t> ids{7, 3};
  const std::vector<double> radii{0.2, 0.25};
  std::vector<std::vector<double>> written;
  for (const std::int64_t step : {0, 5, 10, 12}) {  // 12: off the stride, left out
    const double s = static_cast<double>(step);
    written.push_back({1.0 / 3.0 + s, -2.0 + 0.1234567891 * s, 14.5, 1e-7 * s});
    writer->Write({step, 0.05 * s, 2, written.back().data(), ids.data(), radii.data(), 2, {}});
  }
  writer->Close();
  const std::string text = ReadText(path);
  EXPECT_NE(text.find("\n# framerate: 4 fps\n"), std::string::npos) << text;
  EXPECT_NE(text.find("\n# scenario: crowd.toml\n"), std::string::npos);
  EXPECT_NE(text.find("\n# id frame x/m y/m z/m\n7 0 0.333333 -2.000000 0.000000\n"),
            std::string::npos)
      << text;
  const TextTrajectory t = ReadTextTrajectory(path);
  EXPECT_EQ(t.frame_rate, 4.0);
  EXPECT_EQ(t.unit, 1.0);
  ASSERT_EQ(t.rows(), 6U);
  for (std::size_t r = 0; r < t.rows(); ++r) {
    const std::size_t f = r / 2;
    const std::size_t i = r % 2;
    EXPECT_EQ(t.frame[r], static_cast<std::int64_t>(f));
    EXPECT_EQ(t.id[r], ids[i]);
    EXPECT_NEAR(t.x[r], written[f][2 * i], 5e-7);
    EXPECT_NEAR(t.y[r], written[f][2 * i + 1], 5e-7);
    EXPECT_EQ(t.z[r], 0.0);
  }
}

TEST(TextTrajectory, ReadsPeTrackCentimetresAndFourColumns) {
  TempDir dir;
  const auto path = dir.path() / "petrack.txt";
  WriteFile(path,
            "\xEF\xBB\xBF# PeTrack project: x.pet\n# framerate: 25 fps\n# z: 0 cm\n"
            "# id frame x/cm y/cm z/cm\n1 10 150.5 -20 170\n\n1 11 151.5 -20  # a note\n");
  const TextTrajectory t = ReadTextTrajectory(path);
  EXPECT_EQ(t.frame_rate, 25.0);
  EXPECT_EQ(t.unit, 0.01);
  ASSERT_EQ(t.rows(), 2U);
  EXPECT_DOUBLE_EQ(t.x[0], 1.505);
  EXPECT_DOUBLE_EQ(t.z[0], 1.7);
  EXPECT_EQ(t.frame[1], 11);
  EXPECT_EQ(t.z[1], 0.0);
}

TEST(TextTrajectory, BadFilesAreOneLineInputErrors) {
  TempDir dir;
  const auto path = dir.path() / "t.txt";
  WriteFile(path, "# x/m\n1 0 0 0\n");
  EXPECT_NE(ReadError(path).find("no frame rate"), std::string::npos);
  EXPECT_EQ(ReadTextTrajectory(path, 10.0).frame_rate, 10.0);
  WriteFile(path, "# framerate: 10\n1 0 0 0\n");
  EXPECT_NE(ReadError(path).find("no unit"), std::string::npos);
  WriteFile(path, "# framerate: 10\n# x/m\n1 0 0\n");
  EXPECT_NE(ReadError(path).find("line 3: expected id, frame, x, y"), std::string::npos);
  WriteFile(path, "# framerate: 10\n# x/m\n1.5 0 0 0\n");
  EXPECT_NE(ReadError(path).find("line 3: id and frame must be integers"), std::string::npos);
  WriteFile(path, "# framerate: 10\n# x/m\n1 0 nan 0\n");
  EXPECT_NE(ReadError(path).find("finite"), std::string::npos);
  WriteFile(path, "# framerate: 10\n# x/m\n");
  EXPECT_NE(ReadError(path).find("no rows"), std::string::npos);
  EXPECT_NE(ReadError(dir.path() / "missing.txt").find("does not exist"), std::string::npos);
  TextTrajectoryOptions options;
  options.frame_rate = 0.0;
  EXPECT_THROW(MakeTextTrajectoryWriter(dir.path() / "w.txt", options), InputError);
}

}  // namespace
}  // namespace moreau::io
