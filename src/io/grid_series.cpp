#include "io/grid_series.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <cmath>
#include <limits>

#include "io/io_util.h"
#include "io/xdmf_sidecar.h"
#include "moreau/common/error.h"

namespace moreau::io {

std::int64_t GridSpec::voxel_count() const {
  return std::int64_t{cells[0]} * cells[1] * (dimension == 3 ? cells[2] : 1);
}

void GridSpec::Validate() const {
  if (dimension != 2 && dimension != 3) {
    throw InputError("dimension", fmt::format("must be 2 or 3, got {}", dimension));
  }
  if (!(std::isfinite(spacing) && spacing > 0.0)) {
    throw InputError("spacing", fmt::format("must be finite and > 0, got {}", spacing));
  }
  constexpr char kAxes[] = "xyz";
  for (int a = 0; a < dimension; ++a) {
    if (!std::isfinite(origin[a])) {
      throw InputError("origin", fmt::format("{} must be finite, got {}", kAxes[a], origin[a]));
    }
    if (cells[a] < 1) {
      throw InputError("cells", fmt::format("n_{} must be ≥ 1, got {}", kAxes[a], cells[a]));
    }
  }
  if (dimension == 2 && cells[2] != 1) {
    throw InputError("cells", fmt::format("n_z must be 1 in 2D, got {}", cells[2]));
  }
  // HDF5 and VTK count in 64 bits, but a frame must fit in memory as one array of doubles.
  if (voxel_count() > std::numeric_limits<std::int64_t>::max() / 8) {
    throw InputError("cells", "the grid has too many voxels");
  }
}

namespace internal {
namespace {

bool IsGoodFieldName(std::string_view name) {
  if (name.empty() || name == "." || name == "..") return false;
  for (const char c : name) {
    const auto u = static_cast<unsigned char>(c);
    if (c == '/' || c == ':' || c == '\\' || u <= 0x20 || u == 0x7f) return false;
  }
  return true;
}

}  // namespace

void ValidateGrid(const GridSpec& grid, const std::filesystem::path& file) {
  try {
    grid.Validate();
  } catch (const InputError& e) {
    throw InputError(fmt::format("{}: grid {}", file.string(), e.what()));
  }
}

void GridSeries::Check(const GridFrame& frame, std::int64_t voxels,
                       const std::filesystem::path& file) const {
  const std::string where = fmt::format("{}: frame at step {}", file.string(), frame.step);
  if (!std::isfinite(frame.time)) {
    throw InputError(fmt::format("{} has a non-finite time {}", where, frame.time));
  }
  if (!times.empty() && frame.time < times.back()) {
    throw InputError(fmt::format("{} has time {} before the previous frame's {}", where, frame.time,
                                 times.back()));
  }
  if (frame.arrays.empty()) throw InputError(fmt::format("{} has no fields", where));
  for (std::size_t a = 0; a < frame.arrays.size(); ++a) {
    const GridArray& array = frame.arrays[a];
    if (!IsGoodFieldName(array.name)) {
      throw InputError(
          fmt::format("{}: field name '{}' must be non-empty, not . or .., without '/', ':', '\\', "
                      "whitespace or control characters",
                      where, array.name));
    }
    for (std::size_t b = 0; b < a; ++b) {
      if (frame.arrays[b].name == array.name) {
        throw InputError(fmt::format("{}: field name {} is used twice", where, array.name));
      }
    }
    if (static_cast<std::int64_t>(array.values.size()) != voxels) {
      throw InputError(fmt::format("{}: field {} has {} values, the grid {} voxels", where,
                                   array.name, array.values.size(), voxels));
    }
  }
  bool same = names.empty() || names.size() == frame.arrays.size();
  for (std::size_t a = 0; same && !names.empty() && a < names.size(); ++a) {
    same = names[a] == frame.arrays[a].name;
  }
  if (!same) {
    throw InputError(fmt::format("{} has other fields than the first frame ({})", where,
                                 fmt::join(names, ", ")));
  }
}

void GridSeries::Add(const GridFrame& frame) {
  if (names.empty()) names = NamesOf(frame);
  times.push_back(frame.time);
}

std::vector<std::string> GridSeries::NamesOf(const GridFrame& frame) {
  std::vector<std::string> out;
  for (const GridArray& a : frame.arrays) out.emplace_back(a.name);
  return out;
}

std::string GridXdmfText(const std::string& h5_name, const GridSpec& grid,
                         const GridSeries& series) {
  const std::string h5 = XmlEscape(h5_name);
  const double h = grid.spacing;
  const bool flat = grid.dimension == 2;
  const auto [nx, ny, nz] = grid.cells;
  // XDMF lists axes slowest first: z, y, x. A 2D grid is one layer of voxels centred on z = 0.
  const std::string points = fmt::format("{} {} {}", flat ? 2 : nz + 1, ny + 1, nx + 1);
  const std::string origin =
      fmt::format("{} {} {}", FormatDouble(flat ? -0.5 * h : grid.origin[2]),
                  FormatDouble(grid.origin[1]), FormatDouble(grid.origin[0]));
  const std::string spacing = fmt::format("{0} {0} {0}", FormatDouble(h));
  const std::string cells = fmt::format("{} {} {}", flat ? 1 : nz, ny, nx);
  std::string out;
  out += "<?xml version=\"1.0\" ?>\n";
  out += "<!DOCTYPE Xdmf SYSTEM \"Xdmf.dtd\" []>\n";
  out += "<Xdmf Version=\"3.0\" xmlns:xi=\"http://www.w3.org/2001/XInclude\">\n";
  out += "  <Domain>\n";
  out += "    <Grid Name=\"fields\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
  for (std::size_t f = 0; f < series.times.size(); ++f) {
    out += fmt::format("      <Grid Name=\"frame_{:06d}\" GridType=\"Uniform\">\n", f);
    out += fmt::format("        <Time Value=\"{}\"/>\n", FormatDouble(series.times[f]));
    out += fmt::format("        <Topology TopologyType=\"3DCoRectMesh\" Dimensions=\"{}\"/>\n",
                       points);
    out += "        <Geometry GeometryType=\"ORIGIN_DXDYDZ\">\n";
    for (const std::string* item : {&origin, &spacing}) {
      out += fmt::format(
          "          <DataItem Dimensions=\"3\" NumberType=\"Float\" Precision=\"8\" "
          "Format=\"XML\">{}</DataItem>\n",
          *item);
    }
    out += "        </Geometry>\n";
    for (const std::string& name : series.names) {
      const std::string escaped = XmlEscape(name);
      out += fmt::format(
          "        <Attribute Name=\"{}\" AttributeType=\"Scalar\" Center=\"Cell\">\n", escaped);
      out += fmt::format(
          "          <DataItem Dimensions=\"{}\" NumberType=\"Float\" Precision=\"8\" "
          "Format=\"HDF\">{}:{}/{}</DataItem>\n",
          cells, h5, XdmfFrameGroup(f), escaped);
      out += "        </Attribute>\n";
    }
    out += "      </Grid>\n";
  }
  out += "    </Grid>\n";
  out += "  </Domain>\n";
  out += "</Xdmf>\n";
  return out;
}

}  // namespace internal
}  // namespace moreau::io
