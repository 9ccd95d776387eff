// Text trajectories: PeTrack's and JuPedSim's format as PedPy reads it
// (include/moreau/io/text_trajectory.h, docs/io.md).
#include "moreau/io/text_trajectory.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string_view>

#include <fmt/format.h>

#include "moreau/common/error.h"
#include "moreau/common/input_file.h"

namespace moreau::io {
namespace {

class TextTrajectoryWriter final : public TrajectoryWriter {
 public:
  TextTrajectoryWriter(std::filesystem::path path, TextTrajectoryOptions options)
      : path_(std::move(path)), options_(std::move(options)) {
    options_.Validate();
    file_ = std::fopen(path_.c_str(), "w");
    if (file_ == nullptr) throw InputError(fmt::format("{}: cannot be created", path_.string()));
    std::string header =
        "# moreau trajectory: one row per person and frame (the PeTrack, JuPedSim and PedPy "
        "text format)\n";
    for (const std::string& line : options_.comments) header += "# " + line + "\n";
    header += fmt::format("# framerate: {:.12g} fps\n", options_.frame_rate);
    header += "# x, y, z in m\n# id frame x/m y/m z/m\n";
    Put(header);
  }
  ~TextTrajectoryWriter() override {
    try {
      Close();
    } catch (...) {  // NOLINT(bugprone-empty-catch): the destructor must not throw
    }
  }
  TextTrajectoryWriter(const TextTrajectoryWriter&) = delete;
  TextTrajectoryWriter& operator=(const TextTrajectoryWriter&) = delete;

  void Write(const ParticleFrame& frame) override {
    if (file_ == nullptr) {
      throw std::logic_error(fmt::format("{}: Write after Close", path_.string()));
    }
    if (frame.dimension != 2 && frame.dimension != 3) {
      throw InputError(
          fmt::format("{}: dimension must be 2 or 3 (got {})", path_.string(), frame.dimension));
    }
    if (frame.step % options_.steps_per_frame != 0) return;
    const std::int64_t index = frame.step / options_.steps_per_frame;
    const auto k = static_cast<std::size_t>(frame.dimension);
    const int d = options_.decimals;
    std::string rows;
    for (std::size_t i = 0; i < static_cast<std::size_t>(frame.count); ++i) {
      const double* x = frame.positions + k * i;
      const std::int64_t id = frame.ids != nullptr ? frame.ids[i] : static_cast<std::int64_t>(i);
      rows += fmt::format("{} {} {:.{}f} {:.{}f} {:.{}f}\n", id, index, x[0], d, x[1], d,
                          k == 3 ? x[2] : 0.0, d);
    }
    Put(rows);
  }

  void Close() override {
    if (file_ == nullptr) return;
    const bool ok = std::fflush(file_) == 0;
    const bool closed = std::fclose(file_) == 0;
    file_ = nullptr;
    if (!ok || !closed) throw std::runtime_error(fmt::format("{}: write failed", path_.string()));
  }

 private:
  void Put(const std::string& text) {
    if (std::fwrite(text.data(), 1, text.size(), file_) != text.size()) {
      throw std::runtime_error(fmt::format("{}: write failed", path_.string()));
    }
  }

  std::filesystem::path path_;
  TextTrajectoryOptions options_;
  std::FILE* file_ = nullptr;
};

std::vector<std::string_view> Words(std::string_view line) {
  std::vector<std::string_view> out;
  std::size_t k = 0;
  while (k < line.size()) {
    while (k < line.size() && std::isspace(static_cast<unsigned char>(line[k]))) ++k;
    const std::size_t start = k;
    while (k < line.size() && !std::isspace(static_cast<unsigned char>(line[k]))) ++k;
    if (k > start) out.push_back(line.substr(start, k - start));
  }
  return out;
}

template <class T>
bool Parse(std::string_view word, T& value) {
  if (!word.empty() && word.front() == '+') word.remove_prefix(1);
  const auto [end, ec] = std::from_chars(word.data(), word.data() + word.size(), value);
  return ec == std::errc() && end == word.data() + word.size();
}

std::string Lower(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

// One header line: the frame rate (first number on a "framerate" line) and the unit.
void ReadHeaderLine(std::string_view line, double& frame_rate, double& unit) {
  if (line.find("framerate") != std::string_view::npos && !(frame_rate > 0.0)) {
    for (const std::string_view w : Words(line)) {
      double v = 0.0;
      if (Parse(w, v)) {
        frame_rate = v;
        break;
      }
    }
  }
  const std::string lower = Lower(line);
  if (lower.find("x/cm") != std::string::npos || lower.find("in cm") != std::string::npos) {
    unit = 0.01;
  }
  if (lower.find("x/m") != std::string::npos || lower.find("in m") != std::string::npos) {
    unit = 1.0;
  }
}

}  // namespace

void TextTrajectoryOptions::Validate() const {
  if (!(frame_rate > 0.0) || !std::isfinite(frame_rate)) {
    throw InputError("frame_rate", fmt::format("must be > 0 (got {})", frame_rate));
  }
  if (steps_per_frame < 1) {
    throw InputError("steps_per_frame", fmt::format("must be ≥ 1 (got {})", steps_per_frame));
  }
  if (decimals < 1 || decimals > 17) {
    throw InputError("decimals", fmt::format("must be in 1 … 17 (got {})", decimals));
  }
  for (const std::string& c : comments) {
    if (c.find_first_of("\r\n") != std::string::npos) {
      throw InputError("comments", "a comment must be one line");
    }
  }
}

std::unique_ptr<TrajectoryWriter> MakeTextTrajectoryWriter(const std::filesystem::path& path,
                                                           const TextTrajectoryOptions& options) {
  return std::make_unique<TextTrajectoryWriter>(path, options);
}

TextTrajectory ReadTextTrajectory(const std::filesystem::path& path, double default_frame_rate) {
  const std::string text = ReadInputFile(path.string());
  const std::string_view all = WithoutByteOrderMark(text);
  TextTrajectory out;
  double frame_rate = 0.0;
  double unit = 0.0;
  bool header = true;
  std::size_t line_no = 0;
  const auto fail = [&](const std::string& reason) {
    throw InputError(fmt::format("{}: line {}: {}", path.string(), line_no, reason));
  };
  for (std::size_t pos = 0; pos < all.size();) {
    const std::size_t end = std::min(all.find('\n', pos), all.size());
    std::string_view line = all.substr(pos, end - pos);
    pos = end + 1;
    ++line_no;
    if (header && !line.empty() && line.front() == '#') {
      ReadHeaderLine(line, frame_rate, unit);
      continue;
    }
    header = false;
    line = line.substr(0, std::min(line.find('#'), line.size()));
    const std::vector<std::string_view> w = Words(line);
    if (w.empty()) continue;
    if (w.size() < 4) fail(fmt::format("expected id, frame, x, y[, z] (got {} columns)", w.size()));
    std::int64_t id = 0;
    std::int64_t frame = 0;
    double v[3] = {0.0, 0.0, 0.0};
    if (!Parse(w[0], id) || !Parse(w[1], frame)) fail("id and frame must be integers");
    for (std::size_t a = 0; a < 3 && a + 2 < w.size(); ++a) {
      if (!Parse(w[a + 2], v[a]) || !std::isfinite(v[a])) fail("x, y, z must be finite numbers");
    }
    out.id.push_back(id);
    out.frame.push_back(frame);
    out.x.push_back(v[0]);
    out.y.push_back(v[1]);
    out.z.push_back(v[2]);
  }
  line_no = 0;
  if (!(frame_rate > 0.0) || !std::isfinite(frame_rate)) frame_rate = default_frame_rate;
  if (!(frame_rate > 0.0)) {
    throw InputError(
        fmt::format("{}: no frame rate (a comment line \"# framerate: F\")", path.string()));
  }
  if (unit == 0.0) {
    throw InputError(fmt::format("{}: no unit (a comment line naming x/m or x/cm)", path.string()));
  }
  if (out.id.empty()) throw InputError(fmt::format("{}: no rows", path.string()));
  out.frame_rate = frame_rate;
  out.unit = unit;
  for (std::size_t r = 0; r < out.rows(); ++r) {
    out.x[r] *= unit;
    out.y[r] *= unit;
    out.z[r] *= unit;
  }
  return out;
}

}  // namespace moreau::io
