// `moreau fill-gaps IN [--gaps GAPS.csv] [--method NAME] [--scenario FILE] [--set key=value …]
// [--out DIR]`: fills the gaps of a recording (C3D, TRC, CSV) with one method, after deleting
// the samples GAPS.csv lists (docs/mocap.md): fill_gaps_scenario → fill_gaps_run →
// fill_gaps_report. Every input is read and checked before anything is written.
#include <memory>

#include "commands.h"
#include "fill_gaps/fill_gaps_report.h"
#include "fill_gaps/fill_gaps_run.h"
#include "fill_gaps/fill_gaps_scenario.h"
#include "mocap_settings.h"

namespace moreau::cli {
namespace {

struct FillGapsArgs : RecordingArgs {
  std::string gaps_file;
  std::string method;
};

int FillGapsCommand(const FillGapsArgs& args) {
  std::vector<std::string> flags;
  if (!args.method.empty()) flags.push_back("fill.method=\"" + args.method + "\"");
  Scenario scenario = args.LoadSettings(flags);
  const FillGapsSettings settings = ReadFillGapsSettings(scenario);
  const mocap::Recording recording = ReadRecordingReportingWarnings(args.recording, settings.read);
  std::vector<mocap::Gap> deletions;
  if (!args.gaps_file.empty()) deletions = ReadGapList(args.gaps_file, recording);
  const FillGapsResult result = RunFillGaps(recording, deletions, settings);
  return ReportFillGaps(settings, result, {args.recording, args.gaps_file}, args.OutDir("_filled"));
}

}  // namespace

void AddFillGapsCommand(CLI::App& app) {
  auto args = std::make_shared<FillGapsArgs>();
  CLI::App* cmd = AddRecordingCommand(
      app, "fill-gaps", "Fill the gaps of a recording (.c3d, .trc, .csv) with one method",
      args.get(), "out/<recording name>_filled", [args] { return FillGapsCommand(*args); });
  cmd->add_option("--gaps", args->gaps_file,
                  "CSV marker,first_frame,last_frame (0-based, inclusive): samples to delete "
                  "before filling");
  cmd->add_option("--method", args->method,
                  "Fill method: " + FillMethodNames() + " (= --set fill.method=NAME)");
}

}  // namespace moreau::cli
