#include "moreau/mocap/recording_io.h"

#include <fmt/format.h>

#include <cctype>
#include <cmath>

#include "mocap/file_util.h"
#include "moreau/common/error.h"
#include "moreau/mocap/inventory.h"

namespace moreau::mocap {

namespace {

// The extension in lower case, without the dot.
std::string Extension(const std::filesystem::path& path) {
  std::string ext = internal::ToLower(path.extension().string());
  if (!ext.empty()) ext.erase(0, 1);
  return ext;
}

}  // namespace

const FieldList<ReadOptions>& ReadOptions::Fields() {
  using O = ReadOptions;
  static const FieldList<O> list = [] {
    FieldList<O> t;
    t.Flag("zero_is_missing", &O::zero_is_missing, "a sample at exactly (0, 0, 0) is missing")
        .Flag("allow_truncated", &O::allow_truncated,
              "read the frames present in a file shorter than it declares")
        .Text("units", &O::units, "convert positions to these units (\"\": the file's)",
              {"", "mm", "cm", "m"})
        .Text("units_if_unstated", &O::units_if_unstated,
              "units of a file that does not state them (CSV)", {"mm", "cm", "m"})
        .Number("rate_if_unstated", &O::rate_if_unstated, Range::NonNegative(), "Hz",
                "rate of a CSV file with a single frame (0: none)");
    return t;
  }();
  return list;
}

void ReadOptions::Validate() const { Fields().Validate(*this); }

Recording ReadRecording(const std::filesystem::path& path, const ReadOptions& options,
                        std::vector<std::string>* warnings) {
  const std::string ext = Extension(path);
  if (ext == "c3d") return ReadC3d(path, options, warnings);
  if (ext == "trc") return ReadTrc(path, options, warnings);
  if (ext == "csv") return ReadCsv(path, options, warnings);
  internal::Fail(path, "extension",
                 fmt::format("'{}' is not .c3d, .trc or .csv", path.extension().string()));
}

void WriteRecording(const Recording& recording, const std::filesystem::path& path) {
  const std::string ext = Extension(path);
  if (ext == "c3d") return WriteC3d(recording, path);
  if (ext == "trc") return WriteTrc(recording, path);
  if (ext == "csv") return WriteCsv(recording, path);
  internal::Fail(path, "extension",
                 fmt::format("'{}' is not .c3d, .trc or .csv", path.extension().string()));
}

RecordingInventory TakeInventory(const Recording& r, std::vector<std::string> warnings) {
  RecordingInventory inv;
  for (const PointType type : AllPointTypes()) {
    inv.point_counts[static_cast<std::size_t>(type)] = r.CountPoints(type);
  }
  inv.markers = r.CountPoints(PointType::kMarker);
  inv.frames = r.frames();
  inv.first_frame = r.first_frame();
  inv.rate = r.rate();
  inv.duration_seconds = r.rate() > 0.0 ? static_cast<double>(r.frames()) / r.rate() : 0.0;
  inv.units = r.units();
  inv.format = r.format();
  for (int m = 0; m < r.markers(); ++m) {
    const std::string& label = r.labels()[static_cast<std::size_t>(m)];
    if (r.is_marker(m)) {
      inv.labels.push_back(label);
      inv.observed_samples.push_back(r.ObservedCount(m));
    } else {
      inv.model_outputs.push_back({label, r.type(m), r.type_units(r.type(m)), r.ObservedCount(m)});
    }
  }
  for (const Gap& g : FindGaps(r)) {
    inv.gaps.push_back({r.labels()[static_cast<std::size_t>(g.marker)], g.first, g.last, g.length(),
                        static_cast<double>(g.length()) / r.rate()});
  }
  inv.warnings = std::move(warnings);
  return inv;
}

nlohmann::json RecordingInventory::ToJson() const {
  nlohmann::json gap_rows = nlohmann::json::array();
  for (const GapRow& g : gaps) {
    gap_rows.push_back({{"marker", g.marker},
                        {"first_frame", g.first_frame},
                        {"last_frame", g.last_frame},
                        {"length_frames", g.length_frames},
                        {"length_seconds", g.length_seconds}});
  }
  std::int64_t observed = 0;
  for (std::int64_t n : observed_samples) observed += n;
  nlohmann::json types = nlohmann::json::object();
  for (const PointType type : AllPointTypes()) {
    types[std::string(ToString(type))] = point_counts[static_cast<std::size_t>(type)];
  }
  nlohmann::json outputs = nlohmann::json::array();
  for (const ModelOutputRow& o : model_outputs) {
    outputs.push_back({{"label", o.label},
                       {"type", ToString(o.type)},
                       {"units", o.units},
                       {"observed_samples", o.observed_samples}});
  }
  return {{"markers", markers},
          {"frames", frames},
          {"first_frame", first_frame},
          {"rate", rate},
          {"duration_seconds", duration_seconds},
          {"units", units},
          {"format",
           {{"container", format.container},
            {"processor", format.processor},
            {"storage", format.storage},
            {"scale", format.scale},
            {"analog_channels", format.analog_channels},
            {"analog_samples_per_frame", format.analog_samples_per_frame}}},
          {"labels", labels},
          {"observed_samples", observed_samples},
          {"missing_samples", frames * markers - observed},
          {"gaps", gap_rows},
          {"point_types", types},
          {"model_outputs", outputs},
          {"warnings", warnings}};
}

}  // namespace moreau::mocap
