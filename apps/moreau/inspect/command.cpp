// `moreau inspect RECORDING [--json] [--allow-truncated] [--keep-zero]`: what a motion-capture
// recording (C3D, TRC, CSV) holds — markers, frames, rate, units, format and the gap table
// (docs/mocap.md). Reader warnings go to stderr; bad input exits with code 2.
#include <fmt/format.h>

#include <memory>
#include <string>

#include "commands.h"
#include "inspect/inspect_report.h"
#include "mocap_settings.h"
#include "moreau/common/summary_json.h"
#include "moreau/mocap/inventory.h"

namespace moreau::cli {
namespace {

struct InspectArgs {
  std::string file;
  bool json = false;
  bool allow_truncated = false;
  bool keep_zero = false;
};

void Inspect(const InspectArgs& args) {
  mocap::ReadOptions options;
  options.allow_truncated = args.allow_truncated;
  options.zero_is_missing = !args.keep_zero;
  std::vector<std::string> warnings;
  const mocap::Recording recording = ReadRecordingReportingWarnings(args.file, options, &warnings, "--allow-truncated");
  const mocap::RecordingInventory inventory = mocap::TakeInventory(recording, warnings);
  if (args.json) {
    fmt::print("{}\n", JsonText(inventory.ToJson()));
  } else {
    PrintInventory(args.file, inventory);
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
  cmd->callback([args] { Inspect(*args); });
}

}  // namespace moreau::cli
