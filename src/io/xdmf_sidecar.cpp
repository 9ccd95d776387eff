#include "io/xdmf_sidecar.h"

#include <fmt/format.h>

#include "io/io_util.h"

namespace moreau::io::internal {
namespace {

// A plain HDF DataItem for dataset `dataset` of the frame's group.
// `bytes`: the Precision attribute (8 or 4).
std::string HdfItem(const std::string& dimensions, const char* number_type, const std::string& h5,
                    const std::string& group, const char* dataset, int bytes = 8) {
  return fmt::format(
      "          <DataItem Dimensions=\"{}\" NumberType=\"{}\" Precision=\"{}\" "
      "Format=\"HDF\">{}:{}/{}</DataItem>\n",
      dimensions, number_type, bytes, h5, group, dataset);
}

void AppendFrameGrid(std::string& out, const std::string& h5, int k, int position_bytes,
                     std::size_t index, const XdmfFrame& frame,
                     const std::vector<ArraySpec>& arrays) {
  const std::string group = XdmfFrameGroup(index);
  const std::string n = std::to_string(frame.count);
  out += fmt::format("      <Grid Name=\"frame_{:06d}\" GridType=\"Uniform\">\n", index);
  out += fmt::format("        <Time Value=\"{}\"/>\n", FormatDouble(frame.time));
  out += fmt::format(
      "        <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"{}\" "
      "NodesPerElement=\"1\">\n",
      n);
  out += HdfItem(n, "Int", h5, group, "connectivity");
  out += "        </Topology>\n";
  out += fmt::format("        <Geometry GeometryType=\"{}\">\n", k == 2 ? "XY" : "XYZ");
  out += HdfItem(fmt::format("{} {}", n, k), "Float", h5, group, "positions", position_bytes);
  out += "        </Geometry>\n";
  out += "        <Attribute Name=\"radius\" AttributeType=\"Scalar\" Center=\"Node\">\n";
  out += HdfItem(n, "Float", h5, group, "radii");
  out += "        </Attribute>\n";
  out += "        <Attribute Name=\"id\" AttributeType=\"Scalar\" Center=\"Node\">\n";
  out += HdfItem(n, "Int", h5, group, "ids");
  out += "        </Attribute>\n";
  for (const ArraySpec& a : arrays) {
    const std::string name = XmlEscape(a.name);
    const bool vector = a.components > 1;
    out += fmt::format("        <Attribute Name=\"{}\" AttributeType=\"{}\" Center=\"Node\">\n",
                       name, vector ? "Vector" : "Scalar");
    out += HdfItem(vector ? n + " 3" : n, a.type == PointArray::Type::kInt64 ? "Int" : "Float", h5,
                   group, ("point_data/" + name).c_str());
    out += "        </Attribute>\n";
  }
  out += "      </Grid>\n";
}

}  // namespace

std::string XdmfFrameGroup(std::size_t index) { return fmt::format("/xdmf/frame_{:06d}", index); }

std::string XdmfSidecarText(const std::string& h5_name, int dimension, int position_bytes,
                            const std::vector<XdmfFrame>& frames,
                            const std::vector<ArraySpec>& arrays) {
  const std::string h5 = XmlEscape(h5_name);
  std::string out;
  out += "<?xml version=\"1.0\" ?>\n";
  out += "<!DOCTYPE Xdmf SYSTEM \"Xdmf.dtd\" []>\n";
  out += "<Xdmf Version=\"3.0\" xmlns:xi=\"http://www.w3.org/2001/XInclude\">\n";
  out += "  <Domain>\n";
  out += "    <Grid Name=\"trajectory\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
  for (std::size_t f = 0; f < frames.size(); ++f) {
    if (frames[f].count > 0)
      AppendFrameGrid(out, h5, dimension, position_bytes, f, frames[f], arrays);
  }
  out += "    </Grid>\n";
  out += "  </Domain>\n";
  out += "</Xdmf>\n";
  return out;
}

}  // namespace moreau::io::internal
