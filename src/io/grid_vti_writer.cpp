// Fields on a uniform grid as a VTK ImageData series with a PVD index (layout in
// include/moreau/io/grid_writer.h, docs/io.md).
#include <fmt/format.h>

#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "io/grid_series.h"
#include "io/io_util.h"
#include "moreau/common/error.h"
#include "moreau/io/grid_writer.h"

namespace moreau::io {
namespace {

class VtiSeriesWriter final : public GridWriter {
 public:
  VtiSeriesWriter(std::filesystem::path dir, std::string prefix, const GridSpec& grid);
  ~VtiSeriesWriter() override {
    try {
      Close();
    } catch (...) {  // NOLINT(bugprone-empty-catch): the destructor must not throw
    }
  }
  VtiSeriesWriter(const VtiSeriesWriter&) = delete;
  VtiSeriesWriter& operator=(const VtiSeriesWriter&) = delete;

  void Write(const GridFrame& frame) override;
  void Close() override;

 private:
  // The extent of the image and its one piece: 0 … n per axis (0 … 0 in z in 2D).
  std::string Extent() const;

  std::filesystem::path dir_;
  std::string prefix_;
  std::filesystem::path pvd_path_;
  GridSpec grid_;
  internal::GridSeries series_;
  std::vector<std::pair<double, std::string>> files_;  // (time, file name) per frame
  bool closed_ = false;
  std::string text_;  // workspace reused between frames
};

VtiSeriesWriter::VtiSeriesWriter(std::filesystem::path dir, std::string prefix,
                                 const GridSpec& grid)
    : dir_(std::move(dir)), prefix_(std::move(prefix)), grid_(grid) {
  internal::ValidateGrid(grid_, dir_ / (prefix_ + ".pvd"));
  pvd_path_ = internal::StartSeriesIndex(dir_, prefix_, "VTI");
}

std::string VtiSeriesWriter::Extent() const {
  const auto [nx, ny, nz] = grid_.cells;
  return fmt::format("0 {} 0 {} 0 {}", nx, ny, grid_.dimension == 2 ? 0 : nz);
}

void VtiSeriesWriter::Write(const GridFrame& frame) {
  if (closed_) throw std::logic_error(fmt::format("{}: Write after Close", pvd_path_.string()));
  const std::string name = fmt::format("{}_{:06d}.vti", prefix_, files_.size());
  const std::filesystem::path path = dir_ / name;
  series_.Check(frame, grid_.voxel_count(), path);
  std::string& out = text_;
  out.clear();
  out += "<?xml version=\"1.0\"?>\n";
  out += fmt::format(
      "<VTKFile type=\"ImageData\" version=\"1.0\" byte_order=\"{}\" header_type=\"UInt64\">\n",
      internal::kByteOrder);
  // A 2D grid is a flat image at z = 0.
  const double z = grid_.dimension == 2 ? 0.0 : grid_.origin[2];
  const std::string h = internal::FormatDouble(grid_.spacing);
  out += fmt::format("  <ImageData WholeExtent=\"{}\" Origin=\"{} {} {}\" Spacing=\"{} {} {}\">\n",
                     Extent(), internal::FormatDouble(grid_.origin[0]),
                     internal::FormatDouble(grid_.origin[1]), internal::FormatDouble(z), h, h, h);
  out += "    <FieldData>\n";
  internal::AppendTimeAndStep(frame.time, frame.step, out);
  out += "    </FieldData>\n";
  out += fmt::format("    <Piece Extent=\"{}\">\n", Extent());
  out +=
      fmt::format("      <CellData Scalars=\"{}\">\n", internal::XmlEscape(frame.arrays[0].name));
  for (const GridArray& a : frame.arrays) {
    internal::AppendDataArray("Float64", internal::XmlEscape(a.name), 1, a.values.data(),
                              a.values.size(), out);
  }
  out += "      </CellData>\n";
  out += "    </Piece>\n";
  out += "  </ImageData>\n";
  out += "</VTKFile>\n";
  internal::WriteWholeFile(path, out);
  series_.Add(frame);
  files_.emplace_back(frame.time, name);
}

void VtiSeriesWriter::Close() {
  if (closed_) return;
  closed_ = true;
  std::string().swap(text_);
  internal::WriteWholeFile(pvd_path_, internal::PvdText(files_));
}

}  // namespace

std::unique_ptr<GridWriter> MakeVtiSeriesWriter(const std::filesystem::path& dir,
                                                const std::string& prefix, const GridSpec& grid) {
  return std::make_unique<VtiSeriesWriter>(dir, prefix, grid);
}

}  // namespace moreau::io
