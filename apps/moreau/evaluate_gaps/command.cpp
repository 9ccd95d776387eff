// `moreau evaluate-gaps IN [--gap-seconds 0.1,0.2,0.5,1.0] [--trials N] [--seed S]
// [--methods linear,spline,…] [--markers-per-gap K] [--placement interior|start|end|any]
// [--scenario FILE] [--set key=value …] [--out DIR]`: the gap-filling
// literature's protocol on a complete recording (docs/mocap.md): evaluate_gaps_scenario →
// EvaluateFillMethods → evaluate_gaps_report.
#include <memory>

#include "commands.h"
#include "evaluate_gaps/evaluate_gaps_report.h"
#include "evaluate_gaps/evaluate_gaps_scenario.h"
#include "mocap_settings.h"

namespace moreau::cli {
namespace {

struct EvaluateGapsArgs : RecordingArgs {
  std::string gap_seconds;
  std::string trials;
  std::string seed;
  std::string methods;
  std::string markers_per_gap;
  std::string placement;

  // The dedicated flags as overrides of their keys.
  std::vector<std::string> FlagOverrides() const {
    std::vector<std::string> flags;
    if (!gap_seconds.empty()) flags.push_back("evaluation.gap_seconds=[" + gap_seconds + "]");
    if (!trials.empty()) flags.push_back("evaluation.trials=" + trials);
    if (!seed.empty()) flags.push_back("evaluation.seed=" + seed);
    if (!methods.empty()) flags.push_back("evaluation.methods=\"" + methods + "\"");
    if (!markers_per_gap.empty()) flags.push_back("evaluation.markers_per_gap=" + markers_per_gap);
    if (!placement.empty()) flags.push_back("evaluation.placement=\"" + placement + "\"");
    return flags;
  }
};

int EvaluateGapsCommand(const EvaluateGapsArgs& args) {
  Scenario scenario = args.LoadSettings(args.FlagOverrides());
  const EvaluateGapsSettings settings = ReadEvaluateGapsSettings(scenario);
  const mocap::Recording truth = ReadRecordingReportingWarnings(args.recording, settings.read);
  const mocap::EvaluationSummary summary = mocap::EvaluateFillMethods(truth, settings.evaluation);
  return ReportEvaluateGaps(settings, summary, truth, args.recording, args.OutDir("_evaluation"));
}

}  // namespace

void AddEvaluateGapsCommand(CLI::App& app) {
  auto args = std::make_shared<EvaluateGapsArgs>();
  CLI::App* cmd = AddRecordingCommand(
      app, "evaluate-gaps",
      "Compare fill methods on artificial gaps in a complete recording (seeded trials)", args.get(),
      "out/<recording name>_evaluation", [args] { return EvaluateGapsCommand(*args); });
  cmd->add_option("--gap-seconds", args->gap_seconds,
                  "Gap durations, comma separated (= --set evaluation.gap_seconds=[…]; default "
                  "0.1,0.2,0.5,1.0)");
  cmd->add_option("--trials", args->trials, "Trials per gap length (default 20)");
  cmd->add_option("--seed", args->seed, "Seed of the draws (default 1)");
  cmd->add_option("--methods", args->methods,
                  "Methods compared, comma separated (default all: " + FillMethodNames() + ")");
  cmd->add_option("--markers-per-gap", args->markers_per_gap,
                  "Markers hidden together in each trial, the drawn one and its most rigid "
                  "neighbours (default 1)");
  cmd->add_option("--placement", args->placement,
                  "Where gaps lie: interior, start, end or any (default interior)");
}

}  // namespace moreau::cli
