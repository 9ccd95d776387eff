// Fields on a uniform grid in HDF5 with an XDMF 3 sidecar (layout in
// include/moreau/io/grid_writer.h, docs/io.md).
#include <fmt/format.h>
#include <hdf5.h>

#include <algorithm>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "io/grid_series.h"
#include "io/hdf5_file.h"
#include "io/hdf5_handle.h"
#include "io/io_util.h"
#include "io/xdmf_sidecar.h"
#include "moreau/common/error.h"
#include "moreau/io/grid_writer.h"

namespace moreau::io {
namespace {

constexpr int kFieldsFormatVersion = 1;
constexpr char kFieldsFormatName[] = "moreau-fields";
// Target size of one chunk and the most frames one chunk holds.
constexpr hsize_t kFieldChunkBytes = hsize_t{1} << 20;
constexpr hsize_t kMaxFramesPerFieldChunk = 64;
constexpr double kMissingFieldValue = std::numeric_limits<double>::quiet_NaN();

using internal::Handle;

// Chunk of a F×S dataset of float64: whole frames while a frame is at most kFieldChunkBytes (as
// many as fill about kFieldChunkBytes, at most kMaxFramesPerFieldChunk), else one frame cut along
// its slowest axes to about kFieldChunkBytes.
std::vector<hsize_t> FieldChunkShape(const std::vector<hsize_t>& shape) {
  std::vector<hsize_t> chunk{1};
  chunk.insert(chunk.end(), shape.begin(), shape.end());
  hsize_t bytes = 8;
  for (const hsize_t n : shape) bytes *= n;
  if (bytes <= kFieldChunkBytes) {
    chunk[0] = std::clamp<hsize_t>(kFieldChunkBytes / bytes, 1, kMaxFramesPerFieldChunk);
    return chunk;
  }
  for (std::size_t a = 1; a < chunk.size() && bytes > kFieldChunkBytes; ++a) {
    const hsize_t slab = bytes / chunk[a];  // bytes of one index along axis a
    chunk[a] = std::max<hsize_t>(1, kFieldChunkBytes / slab);
    bytes = slab * chunk[a];
  }
  return chunk;
}

// The path of the sidecar, after the checks that come before the HDF5 file is created.
std::filesystem::path CheckedSidecar(const std::filesystem::path& path, const GridSpec& grid) {
  internal::ValidateGrid(grid, path);
  if (path.extension() == ".xdmf") {
    throw InputError(fmt::format(
        "HDF5 field path {} must not end in .xdmf (that name is taken by its XDMF sidecar)",
        path.string()));
  }
  internal::CheckParentDirectory(path);
  return std::filesystem::path(path).replace_extension(".xdmf");
}

class Hdf5GridWriter final : public GridWriter {
 public:
  Hdf5GridWriter(const std::filesystem::path& path, const GridSpec& grid);
  ~Hdf5GridWriter() override {
    try {
      Close();
    } catch (...) {  // NOLINT(bugprone-empty-catch): the destructor must not throw
    }
  }
  Hdf5GridWriter(const Hdf5GridWriter&) = delete;
  Hdf5GridWriter& operator=(const Hdf5GridWriter&) = delete;

  void Write(const GridFrame& frame) override;
  void Close() override;

 private:
  // /fields/NAME for each name (the first frame's).
  void CreateFieldDatasets(const std::vector<std::string>& names);

  GridSpec grid_;
  std::filesystem::path xdmf_path_;
  internal::Hdf5File file_;
  std::vector<hsize_t> shape_;       // S: (n_y, n_x) or (n_z, n_y, n_x)
  std::vector<hsize_t> view_shape_;  // (n_z, n_y, n_x), n_z = 1 in 2D
  Handle time_, step_;
  std::vector<Handle> fields_;  // /fields/NAME, in the order of series_.names
  internal::GridSeries series_;
  bool closed_ = false;
};

Hdf5GridWriter::Hdf5GridWriter(const std::filesystem::path& path, const GridSpec& grid)
    : grid_(grid), xdmf_path_(CheckedSidecar(path, grid)), file_(path, 0) {
  const auto [nx, ny, nz] = grid_.cells;
  shape_ = {static_cast<hsize_t>(ny), static_cast<hsize_t>(nx)};
  if (grid_.dimension == 3) shape_.insert(shape_.begin(), static_cast<hsize_t>(nz));
  // The views are three-dimensional in 2D too: the XDMF 2 reader reads only n_y values of an
  // (n_y, n_x) item on a mesh of one layer of voxels.
  view_shape_ = {static_cast<hsize_t>(grid_.dimension == 3 ? nz : 1), shape_[shape_.size() - 2],
                 shape_.back()};
  const std::int64_t no_step = -1;
  const hid_t file = file_.get();
  time_ = file_.CreateExtensible(file, "time", H5T_IEEE_F64LE, {256}, 0, H5T_NATIVE_DOUBLE,
                                 &kMissingFieldValue);
  step_ = file_.CreateExtensible(file, "step", H5T_STD_I64LE, {256}, 0, H5T_NATIVE_INT64, &no_step);
  file_.WriteStringAttribute("format", kFieldsFormatName);
  file_.WriteAttribute("format_version", H5T_STD_I32LE, H5T_NATIVE_INT, &kFieldsFormatVersion);
  file_.WriteAttribute("dimension", H5T_STD_I32LE, H5T_NATIVE_INT, &grid_.dimension);
  const auto k = static_cast<hsize_t>(grid_.dimension);
  const std::int64_t cells[3] = {nx, ny, nz};
  file_.WriteAttribute("origin", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, grid_.origin.data(), k);
  file_.WriteAttribute("spacing", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, &grid_.spacing);
  file_.WriteAttribute("cells", H5T_STD_I64LE, H5T_NATIVE_INT64, cells, k);
  file_.CreateGroup("/fields");
  file_.CreateGroup("/xdmf");
}

void Hdf5GridWriter::CreateFieldDatasets(const std::vector<std::string>& names) {
  const std::vector<hsize_t> chunk = FieldChunkShape(shape_);
  for (const std::string& name : names) {
    fields_.push_back(file_.CreateExtensible(file_.get(), ("fields/" + name).c_str(),
                                             H5T_IEEE_F64LE, chunk, shape_.size(),
                                             H5T_NATIVE_DOUBLE, &kMissingFieldValue, shape_));
  }
}

void Hdf5GridWriter::Write(const GridFrame& frame) {
  if (closed_) throw std::logic_error(fmt::format("{}: Write after Close", file_.path().string()));
  series_.Check(frame, grid_.voxel_count(), file_.path());
  if (fields_.empty()) CreateFieldDatasets(internal::GridSeries::NamesOf(frame));
  const hsize_t f = series_.times.size();
  std::vector<hsize_t> dims{f + 1}, start{f}, count{1};
  dims.insert(dims.end(), shape_.begin(), shape_.end());
  start.resize(dims.size(), 0);
  count.insert(count.end(), shape_.begin(), shape_.end());
  file_.WriteBlock(time_, "time", H5T_NATIVE_DOUBLE, {f + 1}, {f}, {1}, &frame.time);
  file_.WriteBlock(step_, "step", H5T_NATIVE_INT64, {f + 1}, {f}, {1}, &frame.step);
  const std::string group_name = internal::XdmfFrameGroup(f);
  Handle group = file_.CreateGroup(group_name);
  for (std::size_t i = 0; i < fields_.size(); ++i) {
    const std::string name(frame.arrays[i].name);
    const std::string source = "fields/" + name;
    file_.WriteBlock(fields_[i], source.c_str(), H5T_NATIVE_DOUBLE, dims, start, count,
                     frame.arrays[i].values.data());
    file_.CreateView(group.get(), name.c_str(), H5T_IEEE_F64LE, ("/" + source).c_str(), dims, start,
                     count, view_shape_);
  }
  // Keep the file readable up to this frame even if the run stops without Close().
  file_.Flush();
  series_.Add(frame);
}

void Hdf5GridWriter::Close() {
  if (closed_) return;
  closed_ = true;
  // Close everything even if one close fails, then report the first failure.
  bool ok = time_.Reset();
  ok = step_.Reset() && ok;
  for (Handle& h : fields_) ok = h.Reset() && ok;
  ok = file_.Close() && ok;
  file_.Check(ok ? 0 : -1, "closing the file");
  internal::WriteWholeFile(
      xdmf_path_, internal::GridXdmfText(file_.path().filename().string(), grid_, series_));
}

}  // namespace

std::unique_ptr<GridWriter> MakeHdf5GridWriter(const std::filesystem::path& path,
                                               const GridSpec& grid) {
  return std::make_unique<Hdf5GridWriter>(path, grid);
}

}  // namespace moreau::io
