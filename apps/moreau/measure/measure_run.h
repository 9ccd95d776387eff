// `moreau measure`: densities, speeds and line flows of a text trajectory (docs/crowds.md
// "Measurements"): the trajectory (io/text_trajectory.h) → tracks and their velocities by
// central differences → per frame the Voronoi cells and each area's measurements, per line the
// people's first crossings → measurements.csv, crossings.csv, summary.json.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "moreau/crowds/measure.h"

namespace moreau::cli {

struct NamedArea {
  std::string name;
  crowds::Polygon polygon;
};

struct NamedLine {
  std::string name;
  crowds::MeasurementLine line;
};

struct MeasureSettings {
  std::string trajectory;                // the text trajectory's path
  std::vector<NamedArea> areas;          // --area
  std::vector<NamedLine> lines;          // --line
  std::optional<crowds::Polygon> bound;  // --bound; default: the positions' box grown by 1 m
  std::optional<double> cutoff_radius;   // --cutoff
  int cutoff_vertices = 12;              // --cutoff-vertices
  double frame_rate = 0.0;               // --frame-rate: used when the file names none
  std::string out;                       // --out
};

// "NAME=x0,y0,x1,y1" (a rectangle from its corners) or "NAME=x0,y0,x1,y1,x2,y2[,…]" (a
// polygon); InputError "--area: REASON" otherwise.
NamedArea ParseArea(const std::string& spec);
// "NAME=ax,ay,bx,by": the line from a to b, counting people who pass from its left to its right.
NamedLine ParseLine(const std::string& spec);
// "x0,y0,x1,y1" (a rectangle) or a convex polygon's vertices.
crowds::Polygon ParseBound(const std::string& spec);

// Reads the trajectory, measures, writes OUT/{measurements.csv, crossings.csv, summary.json}
// (staged, published complete) and returns the lines to print. Throws InputError before
// writing anything for a bad file or setting.
std::string RunMeasure(const MeasureSettings& settings);

}  // namespace moreau::cli
