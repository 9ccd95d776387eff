#include "mocap_settings.h"

#include <cstdio>
#include <filesystem>

namespace moreau::cli {

FieldTable<mocap::ReadOptions> ReadFields() {
  using O = mocap::ReadOptions;
  FieldTable<O> t;
  t.Flag("read.zero_is_missing", &O::zero_is_missing, "a sample at exactly (0, 0, 0) is missing")
      .Flag("read.allow_truncated", &O::allow_truncated,
            "read the frames present in a file shorter than it declares")
      .Text("read.units_if_unstated", &O::units_if_unstated,
            "units of a file that does not state them (CSV): mm, cm or m")
      .Check("read", [](const O& o) { o.Validate(); });
  return t;
}

namespace {

FieldTable<mocap::InterpolationFillOptions> InterpolationFields() {
  using O = mocap::InterpolationFillOptions;
  FieldTable<O> t;
  t.Integer("samples_per_side", &O::samples_per_side, Range::AtLeast(2),
            "spline, pchip: observed samples used on each side of the gap");
  return t;
}

FieldTable<mocap::RigidFillOptions> RigidFields() {
  using O = mocap::RigidFillOptions;
  FieldTable<O> t;
  t.Integer("donors", &O::donors, Range::AtLeast(3), "markers carried rigidly with the gapped one")
      .Integer("min_common_frames", &O::min_common_frames, Range::AtLeast(2),
               "frames seen with the gapped marker to judge a donor");
  return t;
}

FieldTable<mocap::PcaFillOptions> PcaFields() {
  using O = mocap::PcaFillOptions;
  FieldTable<O> t;
  t.Number("explained_fraction", &O::explained_fraction, Range::LeftOpen(0, 1),
           "keep the fewest components whose singular values reach this fraction")
      .Number("weight_scale_m", &O::weight_scale_m, Range::Positive(),
              "σ of the distance weights exp(−d²/2σ²), metres")
      .Number("missing_marker_weight", &O::missing_marker_weight, Range::LeftOpen(0, 1),
              "weight of the gapped marker's coordinates")
      .Number("distal_threshold", &O::distal_threshold, Range::Positive(),
              "leave out incomplete markers farther than this × the mean distance")
      .Integer("min_complete_frames", &O::min_complete_frames, Range::AtLeast(2),
               "frames where every used marker is observed")
      .Integer("max_iterations", &O::max_iterations, Range::AtLeast(1), "reconstruction iterations")
      .Number("tolerance", &O::tolerance, Range::Positive(),
              "stop when the largest change is ≤ this (standard deviations)");
  return t;
}

}  // namespace

FieldTable<mocap::FillOptions> FillOptionFields() {
  using O = mocap::FillOptions;
  FieldTable<O> t;
  t.Number("fill.max_gap_seconds", &O::max_gap_seconds, Range::NonNegative(),
           "leave longer gaps missing (too_long); 0: no limit")
      .Mount("interpolation", &O::interpolation, InterpolationFields())
      .Mount("rigid", &O::rigid, RigidFields())
      .Mount("pca", &O::pca, PcaFields());
  return t;
}

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
    const int code = run();
    if (code != 0) throw CLI::RuntimeError(code);
  });
  return cmd;
}

mocap::Recording ReadRecordingReportingWarnings(const std::string& path,
                                                const mocap::ReadOptions& options,
                                                std::vector<std::string>* warnings) {
  std::vector<std::string> local;
  std::vector<std::string>* out = warnings != nullptr ? warnings : &local;
  mocap::Recording recording = mocap::ReadRecording(path, options, out);
  for (const std::string& w : *out) std::fprintf(stderr, "moreau: warning: %s\n", w.c_str());
  return recording;
}

}  // namespace moreau::cli
