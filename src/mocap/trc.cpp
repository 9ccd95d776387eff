// TRC (OpenSim marker trajectories, PathFileType 4): tab-separated, a five-line header, then one
// row per frame: frame number, time, x y z of every marker (blank where missing).
#include <fmt/format.h>

#include <cctype>
#include <cmath>
#include <map>

#include "mocap/file_util.h"
#include "moreau/common/input_file.h"
#include "moreau/mocap/recording_io.h"

namespace moreau::mocap {

namespace {

using internal::Fail;

// The header values of lines 2 (keys) and 3 (values).
struct TrcHeader {
  double rate = 0.0;
  std::int64_t frames = 0;
  std::int64_t markers = 0;
  std::string units;
};

TrcHeader ReadTrcHeader(const std::filesystem::path& path,
                        const std::vector<std::string_view>& lines) {
  if (lines.size() < 5 || !lines[0].starts_with("PathFileType")) {
    Fail(path, "line 1",
         "not a TRC file (it must start with PathFileType and have 5 header lines)");
  }
  const auto keys = internal::SplitFields(lines[1], '\t');
  const auto values = internal::SplitFields(lines[2], '\t');
  std::map<std::string, std::string_view, std::less<>> header;
  for (std::size_t i = 0; i < keys.size() && i < values.size(); ++i) {
    header[std::string(internal::TrimBlanks(keys[i]))] = internal::TrimBlanks(values[i]);
  }
  const auto number = [&](std::string_view key) {
    const auto it = header.find(key);
    double value = 0.0;
    if (it == header.end()) Fail(path, key, "missing from header lines 2–3");
    if (!internal::ParseNumber(it->second, value) || !std::isfinite(value) || value < 0.0) {
      Fail(path, key, fmt::format("'{}' is not a non-negative number", it->second));
    }
    return value;
  };
  TrcHeader h;
  h.rate = number("DataRate");
  if (h.rate <= 0.0)
    Fail(path, "DataRate", fmt::format("{} frames per second is not positive", h.rate));
  h.frames = static_cast<std::int64_t>(number("NumFrames"));
  h.markers = static_cast<std::int64_t>(number("NumMarkers"));
  const auto units = header.find("Units");
  if (units == header.end()) Fail(path, "Units", "missing from header lines 2–3");
  h.units = internal::ToLower(units->second);
  if (!IsLengthUnit(h.units)) {
    Fail(path, "Units", fmt::format("'{}' is not mm, cm or m", units->second));
  }
  return h;
}

// Marker names from line 4: columns 3, 6, 9, … (after Frame# and Time).
std::vector<std::string> ReadTrcLabels(const std::filesystem::path& path, std::string_view line,
                                       std::int64_t markers) {
  const auto fields = internal::SplitFields(line, '\t');
  std::vector<std::string> labels;
  for (std::size_t c = 2; c < fields.size(); c += 3) {
    const std::string_view name = internal::TrimBlanks(fields[c]);
    if (!name.empty() || static_cast<std::int64_t>(labels.size()) < markers)
      labels.emplace_back(name);
  }
  while (!labels.empty() && labels.back().empty() &&
         static_cast<std::int64_t>(labels.size()) > markers) {
    labels.pop_back();
  }
  if (static_cast<std::int64_t>(labels.size()) != markers) {
    Fail(path, "line 4",
         fmt::format("{} marker names but NumMarkers is {}", labels.size(), markers));
  }
  return labels;
}

// One data row into frame f.
void ReadTrcRow(const std::filesystem::path& path, std::size_t line_number, std::string_view line,
                std::int64_t f, const ReadOptions& options, Recording& r) {
  const auto fields = internal::SplitFields(line, '\t');
  for (int m = 0; m < r.markers(); ++m) {
    Eigen::Vector3d p = Eigen::Vector3d::Constant(std::nan(""));
    bool present = true;
    for (int c = 0; c < 3; ++c) {
      const std::size_t column = 2 + 3 * static_cast<std::size_t>(m) + static_cast<std::size_t>(c);
      const std::string_view text =
          column < fields.size() ? internal::TrimBlanks(fields[column]) : "";
      if (text.empty()) {
        present = false;
      } else if (!internal::ParseNumber(text, p[c])) {
        Fail(path, fmt::format("line {}, column {}", line_number, column + 1),
             fmt::format("'{}' is not a number", text));
      }
    }
    const bool zero = (p.array() == 0.0).all();
    if (present && p.allFinite() && !(zero && options.zero_is_missing)) r.SetPoint(f, m, p);
  }
}

}  // namespace

Recording ReadTrc(const std::filesystem::path& path, const ReadOptions& options,
                  std::vector<std::string>* warnings) {
  options.Validate();
  const std::string text = internal::ReadWholeFile(path);
  const std::vector<std::string_view> lines = internal::SplitLines(WithoutByteOrderMark(text));
  const TrcHeader header = ReadTrcHeader(path, lines);
  std::vector<std::string> labels = ReadTrcLabels(path, lines[3], header.markers);
  std::vector<std::string> local_warnings;
  internal::MakeLabelsUnique(labels, path, "line 4", local_warnings);
  std::vector<std::size_t> rows;  // line indices of the data rows
  for (std::size_t i = 5; i < lines.size(); ++i) {
    if (!internal::TrimBlanks(lines[i]).empty()) rows.push_back(i);
  }
  std::int64_t frames = header.frames;
  if (static_cast<std::int64_t>(rows.size()) > frames) {
    Fail(path, "NumFrames", fmt::format("{} but the file holds {} data rows", frames, rows.size()));
  }
  if (static_cast<std::int64_t>(rows.size()) < frames) {
    const std::string what =
        fmt::format("{} but the file holds {} data rows (truncated)", frames, rows.size());
    if (!options.allow_truncated) {
      Fail(path, "NumFrames", what + "; allow_truncated reads the rows present");
    }
    local_warnings.push_back(fmt::format("{}: NumFrames: {}", path.string(), what));
    frames = static_cast<std::int64_t>(rows.size());
  }
  Recording r(std::move(labels), frames, header.rate, header.units);
  r.format().container = "trc";
  if (!rows.empty()) {
    double first = 0.0;
    const std::string_view field = internal::SplitFields(lines[rows[0]], '\t')[0];
    if (!internal::ParseNumber(field, first) || first != std::floor(first)) {
      Fail(path, fmt::format("line {}, Frame#", rows[0] + 1),
           fmt::format("'{}' is not a frame number", field));
    }
    r.set_first_frame(static_cast<std::int64_t>(first));
  }
  for (std::int64_t f = 0; f < frames; ++f) {
    const std::size_t i = rows[static_cast<std::size_t>(f)];
    ReadTrcRow(path, i + 1, lines[i], f, options, r);
  }
  if (!options.units.empty()) r.ConvertUnits(options.units);
  if (warnings != nullptr)
    warnings->insert(warnings->end(), local_warnings.begin(), local_warnings.end());
  return r;
}

void WriteTrc(const Recording& r, const std::filesystem::path& path) {
  for (const auto& label : r.labels()) {
    if (label.find_first_of("\t\r\n") != std::string::npos || label.empty()) {
      Fail(path, "marker label", fmt::format("'{}' is empty or holds a tab or line break", label));
    }
  }
  const std::string rate = internal::FormatNumber(r.rate());
  std::string out = fmt::format("PathFileType\t4\t(X/Y/Z)\t{}\n", path.filename().string());
  out +=
      "DataRate\tCameraRate\tNumFrames\tNumMarkers\tUnits\tOrigDataRate\tOrigDataStartFrame\tOrigNu"
      "mFrames\n";
  out += fmt::format("{}\t{}\t{}\t{}\t{}\t{}\t{}\t{}\n", rate, rate, r.frames(), r.markers(),
                     r.units(), rate, r.first_frame(), r.frames());
  out += "Frame#\tTime";
  for (const auto& label : r.labels()) out += fmt::format("\t{}\t\t", label);
  out += "\n\t";
  for (int m = 1; m <= r.markers(); ++m) out += fmt::format("\tX{0}\tY{0}\tZ{0}", m);
  out += "\n\n";
  for (std::int64_t f = 0; f < r.frames(); ++f) {
    out += fmt::format("{}\t{}", r.first_frame() + f,
                       internal::FormatNumber(static_cast<double>(f) / r.rate()));
    for (int m = 0; m < r.markers(); ++m) {
      if (!r.observed(f, m)) {
        out += "\t\t\t";
        continue;
      }
      const auto p = r.point(f, m);
      out += fmt::format("\t{}\t{}\t{}", p[0], p[1], p[2]);
    }
    out += '\n';
  }
  internal::WriteFileAtomically(path, out);
}

}  // namespace moreau::mocap
