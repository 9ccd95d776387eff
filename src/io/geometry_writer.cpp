// The scene geometry as VTK XML PolyData (layout in include/moreau/io/geometry.h, docs/io.md).
#include <fmt/format.h>

#include <cstdint>
#include <string>
#include <type_traits>
#include <vector>

#include "io/io_util.h"
#include "moreau/common/error.h"
#include "moreau/io/geometry.h"

namespace moreau::io {
namespace {

// One ASCII DataArray of `values`.
template <typename T>
void AppendAscii(const char* type, const char* name, int components, const std::vector<T>& values,
                 std::string& out) {
  out += fmt::format(
      "        <DataArray type=\"{}\" Name=\"{}\" NumberOfComponents=\"{}\" format=\"ascii\">\n"
      "         ",
      type, name, components);
  for (const T& v : values) {
    if constexpr (std::is_floating_point_v<T>) {
      out += ' ';
      out += internal::FormatDouble(v);
    } else {
      out += fmt::format(" {}", v);
    }
  }
  out += "\n        </DataArray>\n";
}

// The connectivity and offsets of the cells with (polygons) or without (lines) 3+ points.
void AppendCells(const SceneGeometry& g, bool polygons, const std::vector<std::int64_t>& first,
                 std::string& out) {
  std::vector<std::int64_t> connectivity, offsets;
  for (std::size_t c = 0; c < g.cells.size(); ++c) {
    const std::size_t n = g.cells[c].points.size();
    if ((n > 2) != polygons) continue;
    for (std::size_t p = 0; p < n; ++p) {
      connectivity.push_back(first[c] + static_cast<std::int64_t>(p));
    }
    offsets.push_back(static_cast<std::int64_t>(connectivity.size()));
  }
  const char* tag = polygons ? "Polys" : "Lines";
  out += fmt::format("      <{}>\n", tag);
  AppendAscii("Int64", "connectivity", 1, connectivity, out);
  AppendAscii("Int64", "offsets", 1, offsets, out);
  out += fmt::format("      </{}>\n", tag);
}

}  // namespace

void WriteGeometryVtp(const std::filesystem::path& path, const SceneGeometry& geometry) {
  std::vector<double> points;
  std::vector<std::int64_t> first;  // per cell, its first point
  std::vector<int> kinds;           // cell data, lines first, then polygons
  std::vector<std::int64_t> indices;
  std::size_t lines = 0;
  for (const GeometryCell& cell : geometry.cells) {
    if (cell.points.size() < 2 || cell.kind < 0 ||
        static_cast<std::size_t>(cell.kind) >= geometry.kind_names.size()) {
      throw InputError(
          fmt::format("{}: a geometry cell needs 2 or more points and a kind in [0, {})",
                      path.string(), geometry.kind_names.size()));
    }
    first.push_back(static_cast<std::int64_t>(points.size() / 3));
    for (const auto& p : cell.points) points.insert(points.end(), p.begin(), p.end());
    lines += cell.points.size() == 2 ? 1 : 0;
  }
  for (const bool polygons : {false, true}) {
    for (const GeometryCell& cell : geometry.cells) {
      if ((cell.points.size() > 2) != polygons) continue;
      kinds.push_back(cell.kind);
      indices.push_back(cell.index);
    }
  }
  std::string out = "<?xml version=\"1.0\"?>\n";
  out += "<VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\"LittleEndian\">\n";
  out += "  <PolyData>\n    <FieldData>\n";
  internal::AppendStringArray({"kind_names", geometry.kind_names}, out);
  out += "    </FieldData>\n";
  out += fmt::format(
      "    <Piece NumberOfPoints=\"{}\" NumberOfVerts=\"0\" NumberOfLines=\"{}\" "
      "NumberOfStrips=\"0\" NumberOfPolys=\"{}\">\n",
      points.size() / 3, lines, geometry.cells.size() - lines);
  out += "      <CellData Scalars=\"kind\">\n";
  AppendAscii("Int32", "kind", 1, kinds, out);
  AppendAscii("Int64", "index", 1, indices, out);
  out += "      </CellData>\n      <Points>\n";
  AppendAscii("Float64", "Points", 3, points, out);
  out += "      </Points>\n";
  AppendCells(geometry, false, first, out);
  AppendCells(geometry, true, first, out);
  out += "    </Piece>\n  </PolyData>\n</VTKFile>\n";
  internal::WriteWholeFile(path, out);
}

}  // namespace moreau::io
