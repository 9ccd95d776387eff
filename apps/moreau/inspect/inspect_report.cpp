#include "inspect/inspect_report.h"

#include <fmt/format.h>

namespace moreau::cli {

void PrintInventory(const std::string& file, const mocap::RecordingInventory& inventory) {
  const auto& f = inventory.format;
  fmt::print(
      "{}\n  format: {}{}\n  markers: {}\n  frames: {} (file frames {} … {}), {} Hz, {} s\n"
      "  units: {}\n  gaps: {}\n",
      file, f.container,
      f.processor.empty() ? "" : fmt::format(" ({}, {} storage)", f.processor, f.storage),
      inventory.markers, inventory.frames, inventory.first_frame,
      inventory.first_frame + inventory.frames - 1, inventory.rate, inventory.duration_seconds,
      inventory.units, inventory.gaps.size());
  if (inventory.gaps.empty()) return;
  fmt::print("  {:<24} {:>8} {:>8} {:>8} {:>10}\n", "marker", "first", "last", "frames", "seconds");
  for (const auto& g : inventory.gaps) {
    fmt::print("  {:<24} {:>8} {:>8} {:>8} {:>10.4g}\n", g.marker, g.first_frame, g.last_frame,
               g.length_frames, g.length_seconds);
  }
}

}  // namespace moreau::cli
