// `moreau measure TRAJECTORY.txt [--area NAME=…]… [--line NAME=…]… [--bound …] [--cutoff R]
// [--cutoff-vertices N] [--frame-rate F] [--out DIR]`: classic and Voronoi densities, Voronoi
// speeds and line flows of a text trajectory (moreau's trajectory.txt, PeTrack's, JuPedSim's;
// docs/crowds.md "Measurements"). Bad input exits with code 2, nothing written.
#include <fmt/format.h>

#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "commands.h"
#include "measure/measure_run.h"
#include "signals.h"

namespace moreau::cli {
namespace {

struct MeasureArgs {
  std::string trajectory;
  std::vector<std::string> areas, lines;
  std::string bound;
  std::optional<double> cutoff;
  int cutoff_vertices = 12;
  double frame_rate = 0.0;
  std::string out;
};

int MeasureCommand(const MeasureArgs& args) {
  MeasureSettings settings;
  settings.trajectory = args.trajectory;
  for (const std::string& a : args.areas) settings.areas.push_back(ParseArea(a));
  for (const std::string& l : args.lines) settings.lines.push_back(ParseLine(l));
  if (!args.bound.empty()) settings.bound = ParseBound(args.bound);
  settings.cutoff_radius = args.cutoff;
  settings.cutoff_vertices = args.cutoff_vertices;
  settings.frame_rate = args.frame_rate;
  settings.out = args.out;
  if (settings.out.empty()) {  // out/crowd/trajectory.txt → out/crowd_measure
    const std::filesystem::path folder = std::filesystem::path(args.trajectory).parent_path();
    settings.out =
        folder.empty()
            ? std::string("measure")
            : (folder.parent_path() / (folder.filename().string() + "_measure")).string();
  }
  fmt::print("{}", RunMeasure(settings));
  return 0;
}

}  // namespace

void AddMeasureCommand(CLI::App& app) {
  auto args = std::make_shared<MeasureArgs>();
  CLI::App* cmd = app.add_subcommand(
      "measure", "Densities, speeds and line flows of a text trajectory (id frame x y z)");
  cmd->add_option("trajectory", args->trajectory,
                  "Text trajectory: trajectory.txt of `moreau run`, PeTrack's or JuPedSim's")
      ->required();
  cmd->add_option("--area", args->areas,
                  "Measurement area NAME=x0,y0,x1,y1 (a rectangle) or NAME=x0,y0,x1,y1,x2,y2,… "
                  "(a polygon), metres (repeatable)");
  cmd->add_option("--line", args->lines,
                  "Measurement line NAME=ax,ay,bx,by: counts people passing from its left to its "
                  "right (repeatable)");
  cmd->add_option("--bound", args->bound,
                  "Walkable area bounding the Voronoi cells: x0,y0,x1,y1 or a convex polygon "
                  "(default: the positions' box grown by 1 m)");
  cmd->add_option("--cutoff", args->cutoff, "Cut each Voronoi cell by a disk of this radius (m)");
  cmd->add_option("--cutoff-vertices", args->cutoff_vertices,
                  "Vertices of the polygon that stands for the cutoff disk (default 12)");
  cmd->add_option("--frame-rate", args->frame_rate,
                  "Frames per second, for a file whose header names none");
  cmd->add_option("--out", args->out,
                  "Output folder (default: the trajectory's folder with _measure appended)");
  cmd->callback([args] {
    const int code = RunStoppable([&] { return MeasureCommand(*args); });
    if (code != 0) throw CLI::RuntimeError(code);
  });
}

}  // namespace moreau::cli
