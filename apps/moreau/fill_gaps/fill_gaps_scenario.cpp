#include "fill_gaps/fill_gaps_scenario.h"

#include <algorithm>
#include <charconv>
#include <sstream>
#include <tuple>

#include <fmt/format.h>

#include "moreau/common/error.h"
#include "moreau/common/input_file.h"

namespace moreau::cli {

FieldTable<FillGapsSettings> FillGapsFields() {
  using FG = FillGapsSettings;
  FieldTable<FG> t;
  // fill.method and fill.max_gap_seconds are GapFillOptions' method and max_gap_seconds; the
  // method blocks (interpolation.*, rigid.*, pca.*, ocp.*) keep their names.
  t.Mount("", &FG::fill, mocap::GapFillOptions::Fields(),
          {{"method", "fill.method"}, {"max_gap_seconds", "fill.max_gap_seconds"}})
      .CapThreads("ocp.newton.threads")
      .Mount("read", &FG::read, mocap::ReadOptions::Fields());
  return t;
}

FillGapsSettings ReadFillGapsSettings(Scenario& scenario) {
  FillGapsSettings settings;
  FillGapsFields().Read(scenario, settings);
  scenario.CheckAllKeysUsed();
  return settings;
}

nlohmann::json EchoFillGapsSettings(const FillGapsSettings& settings) {
  return FillGapsFields().Echo(settings);
}

namespace {

std::string_view Trim(std::string_view s) {
  const auto first = s.find_first_not_of(" \t\r");
  if (first == std::string_view::npos) return {};
  return s.substr(first, s.find_last_not_of(" \t\r") - first + 1);
}

std::vector<std::string_view> SplitFields(std::string_view line) {
  std::vector<std::string_view> fields;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = line.find(',', start);
    fields.push_back(
        Trim(line.substr(start, comma == std::string_view::npos ? comma : comma - start)));
    if (comma == std::string_view::npos) return fields;
    start = comma + 1;
  }
}

// A non-negative integer, or -1 when `text` is not one.
std::int64_t ParseIndex(std::string_view text) {
  std::int64_t value = -1;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  return ec == std::errc() && end == text.data() + text.size() && value >= 0 ? value : -1;
}

// "WHERE: FIELD: WHY" (WHERE = "FILE: line N").
[[noreturn]] void FailAt(const std::string& where, std::string_view field, const std::string& why) {
  throw InputError(field.empty() ? fmt::format("{}: {}", where, why)
                                 : fmt::format("{}: {}: {}", where, field, why));
}

mocap::Gap ParseGapLine(const std::vector<std::string_view>& fields,
                        const mocap::Recording& recording, const std::string& where) {
  if (fields.size() != 3) {
    FailAt(where, "",
           fmt::format("expected marker,first_frame,last_frame (got {} fields)", fields.size()));
  }
  mocap::Gap gap;
  gap.marker = recording.FindMarker(fields[0]);
  if (gap.marker < 0) {
    const std::int64_t index = ParseIndex(fields[0]);
    if (index < 0 || index >= recording.markers()) {
      FailAt(where, "marker",
             fmt::format("'{}' is neither a label of the recording nor a marker index "
                         "in 0 … {}",
                         fields[0], recording.markers() - 1));
    }
    gap.marker = static_cast<int>(index);
  }
  if (!recording.is_marker(gap.marker)) {
    FailAt(where, "marker",
           fmt::format("'{}' is a model output ({}), not a marker", fields[0],
                       ToString(recording.type(gap.marker))));
  }
  const std::int64_t last_frame = recording.frames() - 1;
  const char* names[] = {"first_frame", "last_frame"};
  std::int64_t frames[2] = {0, 0};
  for (int k = 0; k < 2; ++k) {
    frames[k] = ParseIndex(fields[1 + static_cast<std::size_t>(k)]);
    if (frames[k] < 0 || frames[k] > last_frame) {
      FailAt(where, names[k],
             fmt::format("'{}' is not a frame of the recording (0 … {})",
                         fields[1 + static_cast<std::size_t>(k)], last_frame));
    }
  }
  if (frames[0] > frames[1]) {
    FailAt(where, "last_frame", fmt::format("{} is before first_frame {}", frames[1], frames[0]));
  }
  gap.first = frames[0];
  gap.last = frames[1];
  return gap;
}

// A row of GAPS.csv and its line number.
struct GapRow {
  mocap::Gap gap;
  int line = 0;
};

// Throws InputError "FILE: lines A and B: …" for two rows of one marker that share a frame
// (the first such pair by marker, then by first frame).
void CheckNoOverlap(const std::string& path, std::vector<GapRow> rows,
                    const mocap::Recording& recording) {
  std::sort(rows.begin(), rows.end(), [](const GapRow& a, const GapRow& b) {
    return std::tie(a.gap.marker, a.gap.first, a.line) <
           std::tie(b.gap.marker, b.gap.first, b.line);
  });
  const GapRow* reach = nullptr;  // of the rows before, the one of this marker reaching furthest
  for (const GapRow& row : rows) {
    if (reach == nullptr || reach->gap.marker != row.gap.marker) {
      reach = &row;
      continue;
    }
    if (row.gap.first <= reach->gap.last) {
      const GapRow& a = reach->line < row.line ? *reach : row;
      const GapRow& b = reach->line < row.line ? row : *reach;
      const std::string& label = recording.labels()[static_cast<std::size_t>(row.gap.marker)];
      const bool same = a.gap.first == b.gap.first && a.gap.last == b.gap.last;
      throw InputError(
          same ? fmt::format("{}: lines {} and {}: duplicate rows (marker {}, frames {} … {}); "
                             "list each sample once",
                             path, a.line, b.line, label, a.gap.first, a.gap.last)
               : fmt::format("{}: lines {} and {}: overlapping rows (marker {}, frames {} … {} "
                             "and {} … {}); list each sample once",
                             path, a.line, b.line, label, a.gap.first, a.gap.last, b.gap.first,
                             b.gap.last));
    }
    if (row.gap.last > reach->gap.last) reach = &row;
  }
}

}  // namespace

std::vector<mocap::Gap> ReadGapList(const std::string& path, const mocap::Recording& recording) {
  // A regular file only (a FIFO or /dev/zero is refused), no larger than what may be allocated.
  const std::string content = ReadInputFile(path);
  std::istringstream in(std::string(WithoutByteOrderMark(content)));
  std::vector<GapRow> rows;
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    const std::string_view text = Trim(line);
    if (text.empty() || text.front() == '#') continue;
    const std::vector<std::string_view> fields = SplitFields(text);
    if (rows.empty() && fields[0] == "marker") continue;  // the header
    rows.push_back(
        {ParseGapLine(fields, recording, fmt::format("{}: line {}", path, number)), number});
  }
  CheckNoOverlap(path, rows, recording);
  std::vector<mocap::Gap> gaps;
  for (const GapRow& row : rows) gaps.push_back(row.gap);
  return gaps;
}

}  // namespace moreau::cli
