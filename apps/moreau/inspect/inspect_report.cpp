#include "inspect/inspect_report.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <vector>

namespace moreau::cli {
namespace {

// "model outputs: 32 (angles 20, forces 4, moments 4, powers 4)"; nothing without any.
void PrintModelOutputCount(const mocap::RecordingInventory& inventory) {
  if (inventory.model_outputs.empty()) return;
  std::vector<std::string> parts;
  for (const mocap::PointType type : mocap::AllPointTypes()) {
    const int n = inventory.point_counts[static_cast<std::size_t>(type)];
    if (type != mocap::PointType::kMarker && n > 0) {
      parts.push_back(fmt::format("{}s {}", mocap::ToString(type), n));
    }
  }
  fmt::print("  model outputs: {} ({})\n", inventory.model_outputs.size(), fmt::join(parts, ", "));
}

// The model outputs, one line each: label, type, units, observed samples.
void PrintModelOutputs(const mocap::RecordingInventory& inventory) {
  if (inventory.model_outputs.empty()) return;
  fmt::print("  {:<24} {:>8} {:>8} {:>8}\n", "model output", "type", "units", "observed");
  for (const auto& o : inventory.model_outputs) {
    fmt::print("  {:<24} {:>8} {:>8} {:>8}\n", o.label, mocap::ToString(o.type),
               o.units.empty() ? "-" : o.units, o.observed_samples);
  }
}

}  // namespace

void PrintInventory(const std::string& file, const mocap::RecordingInventory& inventory) {
  const auto& f = inventory.format;
  fmt::print("{}\n  format: {}{}\n  markers: {}\n", file, f.container,
             f.processor.empty() ? "" : fmt::format(" ({}, {} storage)", f.processor, f.storage),
             inventory.markers);
  PrintModelOutputCount(inventory);
  fmt::print("  frames: {} (file frames {} … {}), {} Hz, {} s\n  units: {}\n  gaps: {}\n",
             inventory.frames, inventory.first_frame, inventory.first_frame + inventory.frames - 1,
             inventory.rate, inventory.duration_seconds, inventory.units, inventory.gaps.size());
  PrintModelOutputs(inventory);
  if (inventory.gaps.empty()) return;
  fmt::print("  {:<24} {:>8} {:>8} {:>8} {:>10}\n", "marker", "first", "last", "frames", "seconds");
  for (const auto& g : inventory.gaps) {
    fmt::print("  {:<24} {:>8} {:>8} {:>8} {:>10.4g}\n", g.marker, g.first_frame, g.last_frame,
               g.length_frames, g.length_seconds);
  }
}

}  // namespace moreau::cli
