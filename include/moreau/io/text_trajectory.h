// Trajectories as plain text, the format PeTrack and JuPedSim exchange and PedPy's
// load_trajectory reads (docs/io.md "trajectory.txt"): comment lines starting with '#' first,
// among them the frame rate and the unit, then one row per person and frame,
//
//   # framerate: 2 fps
//   # x, y, z in m
//   # id frame x/m y/m z/m
//   0 0 1.250000 3.500000 0.000000
//
// whitespace-separated: id (integer), frame (integer, frame f at time f / framerate), x, y, z.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "moreau/io/trajectory.h"

namespace moreau::io {

// What the header of a text trajectory says.
struct TextTrajectoryOptions {
  double frame_rate = 1.0;           // frames per second, > 0: 1 / (h · steps_per_frame)
  std::int64_t steps_per_frame = 1;  // a frame is written for the steps that are multiples
  int decimals = 6;                  // digits after the point (metres: 6 is a micrometre), 1 … 17
  std::vector<std::string> comments;  // extra header lines (without '#'), one line each

  // Throws InputError(key, reason) for a frame rate ≤ 0 or not finite, steps_per_frame < 1,
  // decimals outside 1 … 17, or a comment with a line break.
  void Validate() const;
};

// A text trajectory at `path`, created (truncated) now with its header. Write() appends one row
// per particle of a frame whose step is a multiple of steps_per_frame, frame = step /
// steps_per_frame (other frames, such as a run's last step off the stride, are left out: the
// format has one frame rate); z is 0 in 2D. Rows are flushed at Close(). Throws InputError for
// bad options or a file that cannot be created, std::runtime_error when a write fails.
std::unique_ptr<TrajectoryWriter> MakeTextTrajectoryWriter(const std::filesystem::path& path,
                                                           const TextTrajectoryOptions& options);

// A text trajectory read back: rows in file order.
struct TextTrajectory {
  double frame_rate = 0.0;  // from the "framerate" comment
  double unit = 1.0;        // metres per file unit: 1 (m) or 0.01 (cm); x, y, z below in metres
  std::vector<std::int64_t> id;
  std::vector<std::int64_t> frame;
  std::vector<double> x, y, z;  // z = 0 where a row has only four columns
  std::size_t rows() const { return id.size(); }
};

// Reads a text trajectory the way PedPy does: the leading '#' lines give the frame rate (the
// first number on a line containing "framerate") and the unit (x/m or "in m": metres; x/cm or
// "in cm": centimetres); later '#' lines and blank lines are skipped; a row is id, frame, x, y
// and optionally z and more columns (ignored). `default_frame_rate` (> 0) is used when the file
// names none. Throws InputError "PATH: line L: REASON" (not a number, too few columns, no frame
// rate, no unit, no rows), or "PATH: cannot be read".
TextTrajectory ReadTextTrajectory(const std::filesystem::path& path,
                                  double default_frame_rate = 0.0);

}  // namespace moreau::io
