// `moreau inspect RECORDING [--json] [--allow-truncated] [--keep-zero]`: what a motion-capture
// recording (C3D, TRC, CSV) holds — markers, frames, rate, units, format and the gap table
// (docs/mocap_io.md). Reader warnings go to stderr; bad input exits with code 2.
#include <fmt/format.h>

#include <cstdio>
#include <memory>
#include <string>

#include "commands.h"
#include "moreau/mocap/inventory.h"
#include "moreau/mocap/recording_io.h"

namespace moreau::cli {
namespace {

struct InspectArgs {
  std::string file;
  bool json = false;
  bool allow_truncated = false;
  bool keep_zero = false;
};

void PrintInventory(const std::string& file, const mocap::RecordingInventory& inv) {
  const auto& f = inv.format;
  fmt::print(
      "{}\n  format: {}{}\n  markers: {}\n  frames: {} (file frames {} … {}), {} Hz, {} s\n"
      "  units: {}\n  gaps: {}\n",
      file, f.container,
      f.processor.empty() ? "" : fmt::format(" ({}, {} storage)", f.processor, f.storage),
      inv.markers, inv.frames, inv.first_frame, inv.first_frame + inv.frames - 1, inv.rate,
      inv.duration_seconds, inv.units, inv.gaps.size());
  if (inv.gaps.empty()) return;
  fmt::print("  {:<24} {:>8} {:>8} {:>8} {:>10}\n", "marker", "first", "last", "frames", "seconds");
  for (const auto& g : inv.gaps) {
    fmt::print("  {:<24} {:>8} {:>8} {:>8} {:>10.4g}\n", g.marker, g.first_frame, g.last_frame,
               g.length_frames, g.length_seconds);
  }
}

}  // namespace

void AddInspectCommand(CLI::App& app) {
  auto args = std::make_shared<InspectArgs>();
  CLI::App* cmd = app.add_subcommand(
      "inspect", "Markers, frames, rate, units, format and gaps of a recording (.c3d, .trc, .csv)");
  cmd->add_option("recording", args->file, "Recording file")->required();
  cmd->add_flag("--json", args->json, "Write the inventory as JSON");
  cmd->add_flag("--allow-truncated", args->allow_truncated,
                "Read the frames present in a file shorter than it declares");
  cmd->add_flag("--keep-zero", args->keep_zero, "Read points at exactly (0, 0, 0) as data");
  cmd->callback([args] {
    mocap::ReadOptions options;
    options.allow_truncated = args->allow_truncated;
    options.zero_is_missing = !args->keep_zero;
    std::vector<std::string> warnings;
    const mocap::Recording recording = mocap::ReadRecording(args->file, options, &warnings);
    for (const auto& w : warnings) std::fprintf(stderr, "moreau: warning: %s\n", w.c_str());
    const auto inventory = mocap::TakeInventory(recording, warnings);
    if (args->json) {
      fmt::print("{}\n", inventory.ToJson().dump(2));
    } else {
      PrintInventory(args->file, inventory);
    }
  });
}

}  // namespace moreau::cli
