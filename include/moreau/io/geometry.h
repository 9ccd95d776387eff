// The fixed scene of a run (walls, obstacles, a room's door) as a VTK PolyData file that ParaView
// opens beside the trajectory (docs/io.md). Arrays in, one file out, no physics.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace moreau::io {

// One cell of the scene: a line segment (2 points) or a closed polygon (3 or more points), in
// the plane z = 0 for a 2D run.
struct GeometryCell {
  std::vector<std::array<double, 3>> points;
  int kind = 0;            // the index of its kind in SceneGeometry::kind_names
  std::int64_t index = 0;  // which item of its kind it shows (the model's wall, obstacle, …)
};

struct SceneGeometry {
  std::vector<std::string> kind_names;  // e.g. wall, segment, sphere, door
  std::vector<GeometryCell> cells;
};

// Writes `geometry` to `path` (e.g. out/geometry.vtp), created or truncated: a VTK XML PolyData
// file (ASCII) with float64 points, the 2-point cells as Lines and the others as Polys, cell
// data "kind" (int32) and "index" (int64) and field data "kind_names" (a string array). VTK
// orders a PolyData's cells lines first, then polygons; the cell data follow that order.
// Throws InputError for a cell with fewer than 2 points or a kind outside kind_names, and
// std::runtime_error naming the file when it cannot be written.
void WriteGeometryVtp(const std::filesystem::path& path, const SceneGeometry& geometry);

}  // namespace moreau::io
