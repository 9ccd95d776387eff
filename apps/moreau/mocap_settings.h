// What the motion-capture commands (inspect, fill-gaps, evaluate-gaps) share: their arguments,
// the method names and the default method. Their keys (read.*, fill.*, interpolation.*, rigid.*,
// pca.*, ocp.*) are the library's field lists (ReadOptions, GapFillOptions), mounted by each
// command's scenario.
#pragma once

#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include <CLI/CLI.hpp>

#include "field_table.h"
#include "moreau/mocap/gap_fill.h"
#include "moreau/mocap/recording.h"
#include "moreau/mocap/recording_io.h"
#include "scenario.h"

namespace moreau::cli {

// The method fill-gaps uses when none is named (fill.method): the winner of the committed
// evaluation, position first, then acceleration, then time (docs/mocap.md, "Which method is the
// default"; tests/docs/test_mocap_ranking.py checks it against docs/results/mocap/ranking/).
inline constexpr mocap::GapFillMethod kDefaultFillMethod = mocap::GapFillMethod::kOcp;

// "linear, spline, pchip, rigid, pca, average, ocp".
std::string FillMethodNames();

// The arguments of fill-gaps and evaluate-gaps: IN [--scenario FILE] [--set key=value …]
// [--out DIR]. Dedicated flags (--method, --trials, …) become overrides after the --set ones.
struct RecordingArgs {
  std::string recording;
  std::string scenario;  // optional TOML file with the same keys as --set
  std::vector<std::string> overrides;
  std::string out;

  // --out, or out/<recording file stem><suffix>.
  std::string OutDir(std::string_view suffix) const;
  // The scenario file (or the command line alone) with the overrides and `flag_overrides`.
  Scenario LoadSettings(const std::vector<std::string>& flag_overrides) const;
};

// Adds subcommand NAME with the recording arguments bound to *args; `run` returns the exit code.
CLI::App* AddRecordingCommand(CLI::App& app, const std::string& name,
                              const std::string& description, RecordingArgs* args,
                              const std::string& default_out, std::function<int()> run);

// Reads a recording (format by extension); the reader's warnings go to stderr, one line each.
// A truncated file's error names how the command reads it anyway: `allow_truncated`, the
// library's option, as the command spells it (inspect: "--allow-truncated").
mocap::Recording ReadRecordingReportingWarnings(
    const std::string& path, const mocap::ReadOptions& options,
    std::vector<std::string>* warnings = nullptr,
    const std::string& allow_truncated = "--set read.allow_truncated=true");

}  // namespace moreau::cli
