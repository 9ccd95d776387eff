#include "mocap_settings.h"

#include <cstdio>
#include <filesystem>

#include "signals.h"

namespace moreau::cli {

std::string FillMethodNames() {
  std::string names;
  for (mocap::GapFillMethod m : mocap::AllGapFillMethods()) {
    names += (names.empty() ? "" : ", ") + std::string(mocap::ToString(m));
  }
  return names;
}

std::string RecordingArgs::OutDir(std::string_view suffix) const {
  if (!out.empty()) return out;
  const std::string stem = std::filesystem::path(recording).stem().string();
  return (std::filesystem::path("out") / (stem + std::string(suffix))).string();
}

Scenario RecordingArgs::LoadSettings(const std::vector<std::string>& flag_overrides) const {
  std::vector<std::string> all = overrides;
  all.insert(all.end(), flag_overrides.begin(), flag_overrides.end());
  return scenario.empty() ? Scenario::FromCommandLine(all) : Scenario::Load(scenario, all);
}

CLI::App* AddRecordingCommand(CLI::App& app, const std::string& name,
                              const std::string& description, RecordingArgs* args,
                              const std::string& default_out, std::function<int()> run) {
  CLI::App* cmd = app.add_subcommand(name, description);
  cmd->add_option("recording", args->recording, "Recording (.c3d, .trc, .csv)")->required();
  cmd->add_option("--scenario", args->scenario, "Settings file (TOML, the keys of --set)");
  cmd->add_option("--set", args->overrides, "Set a value: key=value (repeatable)");
  cmd->add_option("--out", args->out, "Output folder (default " + default_out + ")");
  cmd->callback([run = std::move(run)] {
    const int code = RunStoppable(run);
    if (code != 0) throw CLI::RuntimeError(code);
  });
  return cmd;
}

mocap::Recording ReadRecordingReportingWarnings(const std::string& path,
                                                const mocap::ReadOptions& options,
                                                std::vector<std::string>* warnings,
                                                const std::string& allow_truncated) {
  std::vector<std::string> local;
  std::vector<std::string>* out = warnings != nullptr ? warnings : &local;
  mocap::Recording recording;
  try {
    recording = mocap::ReadRecording(path, options, out);
  } catch (const InputError& e) {
    std::string message = e.what();
    constexpr std::string_view kOption = "; allow_truncated reads";
    if (const std::size_t at = message.find(kOption); at != std::string::npos) {
      message.replace(at + 2, kOption.size() - 2 - 6, allow_truncated);
      throw InputError(message);
    }
    throw;
  }
  for (const std::string& w : *out) std::fprintf(stderr, "moreau: warning: %s\n", w.c_str());
  return recording;
}

}  // namespace moreau::cli
