// CSV recordings: header `frame,time,marker,x,y,z`, one row per frame and marker.
#include <fmt/format.h>

#include <cmath>
#include <limits>
#include <map>

#include "mocap/file_util.h"
#include "moreau/common/input_file.h"
#include "moreau/mocap/recording_io.h"

namespace moreau::mocap {

namespace {

using internal::Fail;

constexpr std::string_view kCsvHeader = "frame,time,marker,x,y,z";
// The largest coordinate a CSV row may give (in the file's unit; 10^12 mm is a million km).
constexpr double kMaxCsvCoordinate = 1e12;

struct CsvSample {
  std::int64_t frame = 0;
  int marker = 0;
  Eigen::Vector3d p;
  bool present = false;
};

// The samples of all rows, the marker labels in order of first appearance, and the frame range
// with the times of its ends.
struct CsvTable {
  std::vector<CsvSample> samples;
  std::vector<std::string> labels;
  std::int64_t first = std::numeric_limits<std::int64_t>::max();
  std::int64_t last = std::numeric_limits<std::int64_t>::min();
  double first_time = 0.0, last_time = 0.0;
};

CsvSample ReadCsvRow(const std::filesystem::path& path, std::size_t line_number,
                     std::string_view line, std::map<std::string, int, std::less<>>& markers,
                     CsvTable& table, double& time) {
  const auto fields = internal::SplitFields(line, ',');
  const std::string where = fmt::format("line {}", line_number);
  if (fields.size() != 6)
    Fail(path, where, fmt::format("{} fields, expected 6 ({})", fields.size(), kCsvHeader));
  CsvSample s;
  double frame = 0.0;
  if (!internal::ParseNumber(fields[0], frame) || frame != std::floor(frame) ||
      std::abs(frame) > 1e15) {
    Fail(path, where + ", frame", fmt::format("'{}' is not a frame number", fields[0]));
  }
  s.frame = static_cast<std::int64_t>(frame);
  if (!internal::ParseNumber(fields[1], time) || !std::isfinite(time)) {
    Fail(path, where + ", time", fmt::format("'{}' is not a number", fields[1]));
  }
  const std::string label(internal::TrimBlanks(fields[2]));
  if (label.empty()) Fail(path, where + ", marker", "empty");
  const auto [it, added] = markers.try_emplace(label, static_cast<int>(table.labels.size()));
  if (added) table.labels.push_back(label);
  s.marker = it->second;
  s.present = true;
  for (int c = 0; c < 3; ++c) {
    const std::string_view text = internal::TrimBlanks(fields[3 + static_cast<std::size_t>(c)]);
    if (text.empty()) {
      s.present = false;
    } else if (!internal::ParseNumber(text, s.p[c])) {
      Fail(path, fmt::format("{}, {}", where, "xyz"[c]), fmt::format("'{}' is not a number", text));
    } else if (std::isfinite(s.p[c]) && std::abs(s.p[c]) > kMaxCsvCoordinate) {
      Fail(path, fmt::format("{}, {}", where, "xyz"[c]),
           fmt::format("{} is beyond ±{:g}: not a position (the fills' sums of squares would "
                       "overflow)",
                       text, kMaxCsvCoordinate));
    }
  }
  return s;
}

CsvTable ReadCsvTable(const std::filesystem::path& path,
                      const std::vector<std::string_view>& lines) {
  std::size_t i = 0;
  while (i < lines.size() && internal::TrimBlanks(lines[i]).empty()) ++i;
  if (i == lines.size() || internal::TrimBlanks(lines[i]) != kCsvHeader) {
    Fail(path, "header", fmt::format("the first line must be '{}'", kCsvHeader));
  }
  CsvTable table;
  std::map<std::string, int, std::less<>> markers;
  for (++i; i < lines.size(); ++i) {
    if (internal::TrimBlanks(lines[i]).empty()) continue;
    double time = 0.0;
    table.samples.push_back(ReadCsvRow(path, i + 1, lines[i], markers, table, time));
    const std::int64_t frame = table.samples.back().frame;
    if (frame < table.first) table.first = frame, table.first_time = time;
    if (frame > table.last) table.last = frame, table.last_time = time;
  }
  if (table.samples.empty()) Fail(path, "rows", "no data row after the header");
  return table;
}

}  // namespace

Recording ReadCsv(const std::filesystem::path& path, const ReadOptions& options,
                  std::vector<std::string>* /*warnings*/) {
  options.Validate();
  const std::string text = internal::ReadWholeFile(path);
  const CsvTable table = ReadCsvTable(path, internal::SplitLines(WithoutByteOrderMark(text)));
  double rate = options.rate_if_unstated;
  if (table.last > table.first) {
    rate = static_cast<double>(table.last - table.first) / (table.last_time - table.first_time);
    if (!std::isfinite(rate) || rate <= 0.0) {
      Fail(path, "time", "does not increase with the frame number");
    }
  } else if (rate <= 0.0) {
    Fail(path, "time", "a single frame does not give the rate; set ReadOptions::rate_if_unstated");
  }
  if (table.last - table.first >= 1000000 + 4 * static_cast<std::int64_t>(table.samples.size())) {
    Fail(path, "frame",
         fmt::format("frames {} … {} span far more frames than the {} rows hold", table.first,
                     table.last, table.samples.size()));
  }
  Recording r(table.labels, table.last - table.first + 1, rate, options.units_if_unstated);
  r.set_first_frame(table.first);
  r.format().container = "csv";
  std::vector<std::uint8_t> seen(static_cast<std::size_t>(r.frames()) * table.labels.size(), 0);
  for (const CsvSample& s : table.samples) {
    const std::int64_t f = s.frame - table.first;
    auto& once = seen[static_cast<std::size_t>(f) * table.labels.size() +
                      static_cast<std::size_t>(s.marker)];
    if (once != 0) {
      Fail(path, "rows",
           fmt::format("marker {} appears twice in frame {}",
                       table.labels[static_cast<std::size_t>(s.marker)], s.frame));
    }
    once = 1;
    const bool zero = s.present && (s.p.array() == 0.0).all();
    if (s.present && s.p.allFinite() && !(zero && options.zero_is_missing))
      r.SetPoint(f, s.marker, s.p);
  }
  if (!options.units.empty()) r.ConvertUnits(options.units);
  return r;
}

void WriteCsv(const Recording& r, const std::filesystem::path& path) {
  for (const auto& label : r.labels()) {
    if (label.empty() || label.find_first_of(",\"\r\n") != std::string::npos) {
      Fail(path, "marker label",
           fmt::format("'{}' is empty or holds a comma, quote or line break", label));
    }
  }
  std::string out = std::string(kCsvHeader) + "\n";
  for (std::int64_t f = 0; f < r.frames(); ++f) {
    const std::string prefix = fmt::format(
        "{},{},", r.first_frame() + f, internal::FormatNumber(static_cast<double>(f) / r.rate()));
    for (int m = 0; m < r.markers(); ++m) {
      out += prefix;
      out += r.labels()[static_cast<std::size_t>(m)];
      if (r.observed(f, m)) {
        const auto p = r.point(f, m);
        out += fmt::format(",{},{},{}\n", p[0], p[1], p[2]);
      } else {
        out += ",,,\n";
      }
    }
  }
  internal::WriteFileAtomically(path, out);
}

}  // namespace moreau::mocap
