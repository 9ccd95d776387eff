// C3D reader: header, parameter section, 3D point data (analog data skipped). A file that
// declares no parameters is read from its header alone. Points that the file does not label are
// named as BTK names them: "uname*1", "uname*2", … (1-based point numbers).
#include <fmt/format.h>

#include <cctype>
#include <cmath>
#include <limits>
#include <span>

#include "mocap/c3d_format.h"
#include "mocap/file_util.h"
#include "moreau/common/error.h"
#include "moreau/mocap/recording_io.h"

namespace moreau::mocap {

namespace {

using internal::Fail;

constexpr std::string_view kUnnamed = "uname*";
// Motion Analysis Corp. software (EVa RealTime, Cortex) stores short names in POINT:LABELS and
// the names it shows in POINT:DESCRIPTIONS, and marks an occluded point by coordinates 9999999.
constexpr std::string_view kMotionAnalysis = "Motion Analysis Corp.";
constexpr double kMotionAnalysisOccluded = 9999999.0;
constexpr double kMotionAnalysisTolerance =
    static_cast<double>(std::numeric_limits<float>::epsilon());  // BTK's

// Where the points are and how they are stored, from the parameters and the header.
struct DataLayout {
  std::int64_t points = 0;
  double scale = 0.0;  // POINT:SCALE; negative: float storage
  double rate = 0.0;
  std::int64_t data_start = 0;  // block number, 1-based
  std::int64_t first_frame = 1;
  std::int64_t frames = 0;
  std::int64_t analog_words = 0;  // analog values per 3D frame
  int analog_channels = 0;
  int analog_samples_per_frame = 0;
  bool motion_analysis = false;  // MANUFACTURER:COMPANY is Motion Analysis Corp.

  bool float_storage() const { return scale < 0.0; }
  std::size_t word_bytes() const { return float_storage() ? 4 : 2; }
  std::size_t frame_bytes() const {
    return static_cast<std::size_t>(4 * points + analog_words) * word_bytes();
  }
};

// The header's 16-bit word `word` (1-based, as the C3D user guide numbers them) and float at
// words `word`, `word` + 1.
struct Header {
  std::span<const std::uint8_t> bytes;
  c3d::NumberDecoder decode;
  std::uint16_t Word(int word) const {
    return decode.UInt16(&bytes[2 * static_cast<std::size_t>(word - 1)]);
  }
  float Float(int word) const {
    return decode.Float(&bytes[2 * static_cast<std::size_t>(word - 1)]);
  }
};

// The number of frames: the header's range unless it saturates at 65535, then
// TRIAL:ACTUAL_START_FIELD/ACTUAL_END_FIELD (two 16-bit words each, low first) or POINT:FRAMES.
void ReadFrameRange(const Header& header, const c3d::ParameterSection& p, DataLayout& layout) {
  const std::int64_t first = header.Word(4), last = header.Word(5);
  layout.first_frame = first;
  layout.frames = last >= first ? last - first + 1 : 0;
  if (last < 65535) return;
  const auto field = [&](std::string_view name) -> std::optional<std::int64_t> {
    const auto low = p.Count("TRIAL", name, 0), high = p.Count("TRIAL", name, 1);
    if (!low || !high) return std::nullopt;
    return *low + 65536 * *high;
  };
  const auto start = field("ACTUAL_START_FIELD"), end = field("ACTUAL_END_FIELD");
  if (start && end && *end >= *start) {
    layout.first_frame = *start;
    layout.frames = *end - *start + 1;
  } else if (const auto frames = p.Count("POINT", "FRAMES"); frames && *frames > layout.frames) {
    layout.frames = *frames;
  }
}

// Analog values per 3D frame: ANALOG:USED × (ANALOG:RATE / POINT:RATE) when the parameters are
// there, else the header's word 3.
void ReadAnalogLayout(const std::filesystem::path& path, const Header& header,
                      const c3d::ParameterSection& p, DataLayout& layout,
                      std::vector<std::string>& warnings) {
  const std::int64_t header_words = header.Word(3);
  const auto used = p.Count("ANALOG", "USED");
  const auto analog_rate = p.Number("ANALOG", "RATE");
  layout.analog_words = header_words;
  layout.analog_samples_per_frame = header.Word(10);
  layout.analog_channels = layout.analog_samples_per_frame > 0
                               ? static_cast<int>(header_words / layout.analog_samples_per_frame)
                               : 0;
  if (!used) return;
  layout.analog_channels = static_cast<int>(*used);
  if (*used == 0) {
    layout.analog_words = 0;
  } else if (analog_rate && *analog_rate > 0.0) {
    layout.analog_samples_per_frame = static_cast<int>(std::lround(*analog_rate / layout.rate));
    layout.analog_words = *used * layout.analog_samples_per_frame;
  }
  if (layout.analog_words != header_words) {
    warnings.push_back(fmt::format(
        "{}: ANALOG:USED: {} channels × {} samples per frame disagree with the header's {} analog "
        "values per frame; the parameters are used",
        path.string(), *used, layout.analog_samples_per_frame, header_words));
  }
}

DataLayout ReadLayout(const std::filesystem::path& path, const Header& header,
                      const c3d::ParameterSection& p, std::vector<std::string>& warnings) {
  DataLayout layout;
  const auto fallback = [&](std::string_view field, double value) {
    if (!p.parameters.empty()) {  // a file without any parameter gets one warning (ReadC3d)
      warnings.push_back(fmt::format("{}: {}: missing; the header's value {} is used",
                                     path.string(), field, value));
    }
    return value;
  };
  layout.points = p.Count("POINT", "USED").value_or(header.Word(2));
  const auto scale = p.Number("POINT", "SCALE");
  layout.scale = scale ? *scale : fallback("POINT:SCALE", static_cast<double>(header.Float(7)));
  if (!std::isfinite(layout.scale) || layout.scale == 0.0) {
    Fail(path, "POINT:SCALE",
         fmt::format("{} is neither a positive integer scale nor negative "
                     "(float storage)",
                     layout.scale));
  }
  const auto rate = p.Number("POINT", "RATE");
  layout.rate = rate ? *rate : fallback("POINT:RATE", static_cast<double>(header.Float(11)));
  if (!std::isfinite(layout.rate) || layout.rate <= 0.0) {
    Fail(path, "POINT:RATE", fmt::format("{} frames per second is not positive", layout.rate));
  }
  const auto start = p.Count("POINT", "DATA_START");
  layout.data_start = header.Word(9);
  if (!start) {
    fallback("POINT:DATA_START", header.Word(9));
  } else if (*start >= 2) {
    layout.data_start = *start;
  } else {
    warnings.push_back(
        fmt::format("{}: POINT:DATA_START: block {} is not a data block; the "
                    "header's value {} is used",
                    path.string(), *start, header.Word(9)));
  }
  ReadFrameRange(header, p, layout);
  ReadAnalogLayout(path, header, p, layout, warnings);
  return layout;
}

// POINT:NAME, NAME2, NAME3, … concatenated.
std::vector<std::string> ReadNameList(const c3d::ParameterSection& p, std::string_view name) {
  std::vector<std::string> names = p.Strings("POINT", name);
  for (int k = 2; p.Find("POINT", fmt::format("{}{}", name, k)) != nullptr; ++k) {
    const auto more = p.Strings("POINT", fmt::format("{}{}", name, k));
    names.insert(names.end(), more.begin(), more.end());
  }
  return names;
}

// POINT:LABELS, LABELS2, LABELS3, … (or DESCRIPTIONS…) concatenated, cut or padded to `count`;
// a point past the list gets GeneratedLabel(its index, `prefix`), or "" when `prefix` is empty.
std::vector<std::string> ReadNames(const c3d::ParameterSection& p, std::string_view name,
                                   std::int64_t count, std::string_view prefix = {}) {
  std::vector<std::string> names = ReadNameList(p, name);
  const std::size_t listed = names.size();
  names.resize(static_cast<std::size_t>(count));
  for (std::size_t m = listed; m < names.size() && !prefix.empty(); ++m) {
    names[m] = internal::GeneratedLabel(m, prefix);
  }
  return names;
}

bool WrittenByMotionAnalysis(const c3d::ParameterSection& p) {
  const auto company = p.Strings("MANUFACTURER", "COMPANY");
  return !company.empty() && company[0] == kMotionAnalysis;
}

// The model outputs: a point whose label POINT:ANGLES, FORCES, … lists gets that type (names
// that label no point are ignored), and the type's units from POINT:ANGLE_UNITS, ….
void ReadPointTypes(const c3d::ParameterSection& p, Recording& recording) {
  for (const auto& group : c3d::kPointTypeParameters) {
    for (const std::string& name : ReadNameList(p, group.labels)) {
      const int point = name.empty() ? -1 : recording.FindMarker(name);
      if (point >= 0) recording.set_type(point, group.type);
    }
    const auto units = p.Strings("POINT", group.units);
    if (!units.empty()) recording.set_type_units(group.type, units[0]);
  }
}

std::string ReadUnits(const std::filesystem::path& path, const c3d::ParameterSection& p,
                      std::vector<std::string>& warnings) {
  const auto strings = p.Strings("POINT", "UNITS");
  if (strings.empty() || strings[0].empty()) return "mm";
  const std::string units = internal::ToLower(strings[0]);
  if (IsLengthUnit(units)) return units;
  warnings.push_back(fmt::format("{}: POINT:UNITS: '{}' is not mm, cm or m; read as mm",
                                 path.string(), strings[0]));
  return "mm";
}

// The labels of a file that declares no parameters: uname*1 … uname*<count>, with one warning
// saying that the layout came from the header and the labels and units were supplied.
std::vector<std::string> HeaderOnlyLabels(const std::filesystem::path& path, std::int64_t count,
                                          std::vector<std::string>& warnings) {
  std::vector<std::string> labels;
  for (std::size_t m = 0; m < static_cast<std::size_t>(count); ++m) {
    labels.push_back(internal::GeneratedLabel(m, kUnnamed));
  }
  const std::string range =
      labels.empty() ? "none" : fmt::format("{} … {}", labels.front(), labels.back());
  warnings.push_back(
      fmt::format("{}: parameter section: the file declares no parameters; the header gives the "
                  "points, frames, scale and rate; labels generated ({}), units taken as mm",
                  path.string(), range));
  return labels;
}

// The frames that the file holds in full; InputError (or a warning with allow_truncated) when
// fewer than declared.
std::int64_t FramesPresent(const std::filesystem::path& path, std::size_t file_bytes,
                           const DataLayout& layout, const ReadOptions& options,
                           std::vector<std::string>& warnings) {
  const std::size_t offset = static_cast<std::size_t>(layout.data_start - 1) * c3d::kBlockBytes;
  if (layout.data_start < 2 || offset > file_bytes) {
    Fail(path, "POINT:DATA_START",
         fmt::format("block {} is outside the file ({} bytes)", layout.data_start, file_bytes));
  }
  if (layout.frame_bytes() == 0) return layout.frames;
  const auto present = static_cast<std::int64_t>((file_bytes - offset) / layout.frame_bytes());
  if (present >= layout.frames) return layout.frames;
  const std::string what =
      fmt::format("the file declares {} frames but holds {} (truncated)", layout.frames, present);
  if (!options.allow_truncated) {
    Fail(path, "POINT data", what + "; allow_truncated reads the frames present");
  }
  warnings.push_back(
      fmt::format("{}: POINT data: {}; read {} frames", path.string(), what, present));
  return present;
}

void ReadPoints(std::span<const std::uint8_t> bytes, const DataLayout& layout,
                const c3d::NumberDecoder& decode, const ReadOptions& options,
                Recording& recording) {
  const std::size_t word = layout.word_bytes();
  const double scale = std::abs(layout.scale);
  const std::uint8_t* frame_start =
      bytes.data() + static_cast<std::size_t>(layout.data_start - 1) * c3d::kBlockBytes;
  for (std::int64_t f = 0; f < recording.frames(); ++f, frame_start += layout.frame_bytes()) {
    for (int m = 0; m < recording.markers(); ++m) {
      const std::uint8_t* at = frame_start + 4 * word * static_cast<std::size_t>(m);
      Eigen::Vector3d p;
      double residual = 0.0;
      if (layout.float_storage()) {
        for (int c = 0; c < 3; ++c)
          p[c] = static_cast<double>(decode.Float(at + 4 * static_cast<std::size_t>(c)));
        residual = static_cast<double>(decode.Float(at + 12));
      } else {
        for (int c = 0; c < 3; ++c)
          p[c] = scale * decode.Int16(at + 2 * static_cast<std::size_t>(c));
        residual = decode.Int16(at + 6);
      }
      const bool zero = p[0] == 0.0 && p[1] == 0.0 && p[2] == 0.0;
      if (residual < 0.0 || !p.allFinite() || (zero && options.zero_is_missing)) continue;
      if (layout.motion_analysis &&
          std::abs(p.mean() - kMotionAnalysisOccluded) < kMotionAnalysisTolerance) {
        continue;
      }
      recording.SetPoint(f, m, p);
    }
  }
}

}  // namespace

Recording ReadC3d(const std::filesystem::path& path, const ReadOptions& options,
                  std::vector<std::string>* warnings_out) {
  options.Validate();
  std::vector<std::string> warnings;
  const std::string content = internal::ReadWholeFile(path);
  const std::span<const std::uint8_t> bytes(reinterpret_cast<const std::uint8_t*>(content.data()),
                                            content.size());
  if (bytes.size() < c3d::kBlockBytes) {
    Fail(path, "header",
         fmt::format("the file has {} bytes, fewer than the 512 of a C3D header", bytes.size()));
  }
  if (bytes[1] != 0x50 || bytes[0] < 2) {
    Fail(path, "header",
         fmt::format("bytes 1–2 are {} and 0x{:02x}, not a parameter block ≥ 2 and "
                     "0x50: not a C3D file",
                     bytes[0], bytes[1]));
  }
  const c3d::ParameterSection section = c3d::ParseParameterSection(
      bytes, (std::size_t{bytes[0]} - 1) * c3d::kBlockBytes, path, warnings);
  const Header header{bytes, c3d::NumberDecoder{section.processor}};
  DataLayout layout = ReadLayout(path, header, section, warnings);
  layout.frames = FramesPresent(path, bytes.size(), layout, options, warnings);

  layout.motion_analysis = WrittenByMotionAnalysis(section);
  // Motion Analysis: the names are the descriptions, and the short labels become descriptions.
  const std::string_view names = layout.motion_analysis ? "DESCRIPTIONS" : "LABELS";
  const std::string_view notes = layout.motion_analysis ? "LABELS" : "DESCRIPTIONS";
  std::vector<std::string> labels = section.parameters.empty()
                                        ? HeaderOnlyLabels(path, layout.points, warnings)
                                        : ReadNames(section, names, layout.points, kUnnamed);
  internal::MakeLabelsUnique(labels, path, fmt::format("POINT:{}", names), warnings, kUnnamed);
  Recording recording(std::move(labels), layout.frames, layout.rate,
                      ReadUnits(path, section, warnings));
  recording.descriptions() = ReadNames(section, notes, layout.points);
  recording.set_first_frame(layout.first_frame);
  ReadPointTypes(section, recording);
  SourceFormat& format = recording.format();
  format.container = "c3d";
  format.processor = std::string(c3d::ProcessorName(section.processor));
  format.storage = layout.float_storage() ? "float" : "integer";
  format.scale = layout.scale;
  format.analog_channels = layout.analog_channels;
  format.analog_samples_per_frame = layout.analog_samples_per_frame;
  ReadPoints(bytes, layout, header.decode, options, recording);
  if (!options.units.empty()) recording.ConvertUnits(options.units);
  if (warnings_out != nullptr)
    warnings_out->insert(warnings_out->end(), warnings.begin(), warnings.end());
  return recording;
}

}  // namespace moreau::mocap
