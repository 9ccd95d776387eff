// HDF5 trajectory with an XDMF 3 sidecar (layout in include/moreau/io/trajectory.h, docs/io.md).
#include <fmt/format.h>
#include <hdf5.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "io/hdf5_file.h"
#include "io/hdf5_handle.h"
#include "io/io_util.h"
#include "io/xdmf_sidecar.h"
#include "moreau/common/error.h"
#include "moreau/io/trajectory.h"

namespace moreau::io {
namespace {

constexpr int kFormatVersion = 2;
constexpr char kFormatName[] = "moreau-trajectory";
// Target size of one chunk, the most frames one chunk holds (so that short runs of few particles
// do not allocate a large first chunk), and the fewest particles one chunk spans (so that a count
// growing from a few particles does not make one chunk per particle).
constexpr hsize_t kChunkBytes = hsize_t{1} << 20;
constexpr hsize_t kMaxFramesPerChunk = 64;
constexpr hsize_t kMinParticlesPerChunk = 64;
// Rows past a frame's count read as these.
constexpr double kMissingValue = std::numeric_limits<double>::quiet_NaN();
constexpr std::int64_t kMissingId = -1;
// Root attributes the writer sets itself (a string list may not take these names).
constexpr std::string_view kRootAttributes[] = {"format", "format_version", "dimension", "count"};

using internal::Handle;

// Chunk shape {frames, particles} for per-frame records of `count` particles (at least
// kMinParticlesPerChunk) of `bytes_per_particle` bytes each: about kChunkBytes, whole frames while
// they fit.
std::array<hsize_t, 2> ChunkShape(std::int64_t count, hsize_t bytes_per_particle) {
  const hsize_t n = std::max<hsize_t>(kMinParticlesPerChunk, static_cast<hsize_t>(count));
  const hsize_t frame_bytes = n * bytes_per_particle;
  if (frame_bytes >= kChunkBytes) {
    return {1, std::max<hsize_t>(1, kChunkBytes / bytes_per_particle)};
  }
  return {std::clamp<hsize_t>(kChunkBytes / frame_bytes, 1, kMaxFramesPerChunk), n};
}

// Checks what must hold before the file is created (InputError) and returns `path`.
const std::filesystem::path& CheckedPath(const std::filesystem::path& path,
                                         const Hdf5TrajectoryOptions& options,
                                         const std::vector<StringList>& lists) {
  options.Validate();
  if (path.extension() == ".xdmf") {
    throw InputError(
        fmt::format("HDF5 trajectory path {} must not end in .xdmf (that name is "
                    "taken by its XDMF sidecar)",
                    path.string()));
  }
  internal::CheckParentDirectory(path);
  internal::ValidateLists(lists, kRootAttributes, path);
  return path;
}

class Hdf5TrajectoryWriter final : public TrajectoryWriter {
 public:
  Hdf5TrajectoryWriter(const std::filesystem::path& path, const Hdf5TrajectoryOptions& options,
                       const std::vector<StringList>& lists);
  ~Hdf5TrajectoryWriter() override {
    try {
      Close();
    } catch (...) {  // NOLINT(bugprone-empty-catch): the destructor must not throw
    }
  }
  Hdf5TrajectoryWriter(const Hdf5TrajectoryWriter&) = delete;
  Hdf5TrajectoryWriter& operator=(const Hdf5TrajectoryWriter&) = delete;

  void Write(const ParticleFrame& frame) override;
  void Close() override;

 private:
  void CreateParticleDatasets(const ParticleFrame& frame);
  // Widens the particle axis to `count` rows (connectivity 0 … count−1 included).
  void GrowParticleAxis(std::int64_t count);
  void WriteFrameViews(std::size_t index, std::int64_t count);
  void WriteArrays(const ParticleFrame& frame);

  std::filesystem::path path_;
  std::filesystem::path xdmf_path_;
  Hdf5TrajectoryOptions options_;
  hid_t position_type_;  // file type of /positions: float64 or float32
  internal::Hdf5File file_;
  Handle time_, step_, count_, positions_, ids_, radii_, connectivity_;
  std::vector<internal::ArraySpec> specs_;  // the extra arrays, fixed by the first frame
  std::vector<Handle> arrays_;              // /point_data/NAME, one per spec
  bool closed_ = false;
  bool has_particle_datasets_ = false;
  int dimension_ = 0;
  std::int64_t rows_ = 0;                    // extent of the particle axis: the largest N so far
  std::vector<internal::XdmfFrame> frames_;  // one per frame written
  std::vector<std::int64_t> indices_;        // workspace: connectivity values
};

Hdf5TrajectoryWriter::Hdf5TrajectoryWriter(const std::filesystem::path& path,
                                           const Hdf5TrajectoryOptions& options,
                                           const std::vector<StringList>& lists)
    : path_(path),
      xdmf_path_(std::filesystem::path(path).replace_extension(".xdmf")),
      options_(options),
      position_type_(options.precision == TrajectoryPrecision::kSingle ? H5T_IEEE_F32LE
                                                                       : H5T_IEEE_F64LE),
      file_(CheckedPath(path, options, lists), options.compression) {
  const hid_t file = file_.get();
  const double no_time = kMissingValue;
  const std::int64_t no_count = 0;
  time_ =
      file_.CreateExtensible(file, "time", H5T_IEEE_F64LE, {256}, 0, H5T_NATIVE_DOUBLE, &no_time);
  step_ =
      file_.CreateExtensible(file, "step", H5T_STD_I64LE, {256}, 0, H5T_NATIVE_INT64, &kMissingId);
  count_ =
      file_.CreateExtensible(file, "count", H5T_STD_I64LE, {256}, 0, H5T_NATIVE_INT64, &no_count);
  file_.WriteStringAttribute("format", kFormatName);
  file_.WriteAttribute("format_version", H5T_STD_I32LE, H5T_NATIVE_INT, &kFormatVersion);
  for (const StringList& list : lists) file_.WriteStringList(list);
}

void Hdf5TrajectoryWriter::CreateParticleDatasets(const ParticleFrame& frame) {
  const auto k = static_cast<hsize_t>(frame.dimension);
  const auto [frames_xk, rows_xk] = ChunkShape(frame.count, H5Tget_size(position_type_) * k);
  const auto [frames_x1, rows_x1] = ChunkShape(frame.count, 8);
  const hid_t file = file_.get();
  positions_ = file_.CreateExtensible(file, "positions", position_type_, {frames_xk, rows_xk, k}, 1,
                                      H5T_NATIVE_DOUBLE, &kMissingValue);
  ids_ = file_.CreateExtensible(file, "ids", H5T_STD_I64LE, {frames_x1, rows_x1}, 0,
                                H5T_NATIVE_INT64, &kMissingId);
  radii_ = file_.CreateExtensible(file, "radii", H5T_IEEE_F64LE, {frames_x1, rows_x1}, 0,
                                  H5T_NATIVE_DOUBLE, &kMissingValue);
  connectivity_ = file_.CreateExtensible(file, "connectivity", H5T_STD_I64LE, {4096}, 0,
                                         H5T_NATIVE_INT64, &kMissingId);
  specs_ = internal::SpecsOf(frame.arrays);
  if (!specs_.empty()) file_.CreateGroup("/point_data");
  for (const internal::ArraySpec& a : specs_) {
    const bool integer = a.type == PointArray::Type::kInt64;
    const auto c = static_cast<hsize_t>(a.components);
    const auto [frames_a, rows_a] = ChunkShape(frame.count, 8 * c);
    std::vector<hsize_t> chunk{frames_a, rows_a};
    if (c > 1) chunk.push_back(c);
    arrays_.push_back(file_.CreateExtensible(
        file, ("point_data/" + a.name).c_str(), integer ? H5T_STD_I64LE : H5T_IEEE_F64LE, chunk,
        c > 1 ? 1 : 0, integer ? H5T_NATIVE_INT64 : H5T_NATIVE_DOUBLE,
        integer ? static_cast<const void*>(&kMissingId) : &kMissingValue));
  }
  file_.CreateGroup("/xdmf");
  file_.WriteAttribute("dimension", H5T_STD_I32LE, H5T_NATIVE_INT, &frame.dimension);
  file_.WriteAttribute("count", H5T_STD_I64LE, H5T_NATIVE_INT64, &rows_);
  dimension_ = frame.dimension;
  has_particle_datasets_ = true;
}

void Hdf5TrajectoryWriter::GrowParticleAxis(std::int64_t count) {
  indices_.resize(static_cast<std::size_t>(count - rows_));
  for (std::size_t i = 0; i < indices_.size(); ++i) {
    indices_[i] = rows_ + static_cast<std::int64_t>(i);
  }
  const auto n = static_cast<hsize_t>(count);
  file_.WriteBlock(connectivity_, "connectivity", H5T_NATIVE_INT64, {n},
                   {static_cast<hsize_t>(rows_)}, {indices_.size()}, indices_.data());
  rows_ = count;
  file_.WriteAttribute("count", H5T_STD_I64LE, H5T_NATIVE_INT64, &rows_);
}

void Hdf5TrajectoryWriter::WriteFrameViews(std::size_t index, std::int64_t count) {
  const std::string name = internal::XdmfFrameGroup(index);
  Handle group = file_.CreateGroup(name);
  if (count == 0) return;
  const hsize_t frames = index + 1, f = index, rows = static_cast<hsize_t>(rows_);
  const auto n = static_cast<hsize_t>(count), k = static_cast<hsize_t>(dimension_);
  const hid_t g = group.get();
  file_.CreateView(g, "positions", position_type_, "/positions", {frames, rows, k}, {f, 0, 0},
                   {1, n, k});
  file_.CreateView(g, "radii", H5T_IEEE_F64LE, "/radii", {frames, rows}, {f, 0}, {1, n});
  file_.CreateView(g, "ids", H5T_STD_I64LE, "/ids", {frames, rows}, {f, 0}, {1, n});
  file_.CreateView(g, "connectivity", H5T_STD_I64LE, "/connectivity", {rows}, {0}, {n});
  if (specs_.empty()) return;
  Handle point_data = file_.CreateGroup(name + "/point_data");
  for (const internal::ArraySpec& a : specs_) {
    const hid_t type = a.type == PointArray::Type::kInt64 ? H5T_STD_I64LE : H5T_IEEE_F64LE;
    const std::string source = "/point_data/" + a.name;
    if (a.components == 1) {
      file_.CreateView(point_data.get(), a.name.c_str(), type, source.c_str(), {frames, rows},
                       {f, 0}, {1, n});
    } else {
      file_.CreateView(point_data.get(), a.name.c_str(), type, source.c_str(), {frames, rows, 3},
                       {f, 0, 0}, {1, n, 3});
    }
  }
}

void Hdf5TrajectoryWriter::WriteArrays(const ParticleFrame& frame) {
  const hsize_t f = frames_.size(), frames = f + 1, rows = static_cast<hsize_t>(rows_);
  const auto n = static_cast<hsize_t>(frame.count);
  for (std::size_t i = 0; i < specs_.size(); ++i) {
    const PointArray& a = frame.arrays[i];
    const hid_t memory = a.type == PointArray::Type::kInt64 ? H5T_NATIVE_INT64 : H5T_NATIVE_DOUBLE;
    const std::string name = "point_data/" + specs_[i].name;
    if (a.components == 1) {
      file_.WriteBlock(arrays_[i], name.c_str(), memory, {frames, rows}, {f, 0}, {1, n}, a.data);
    } else {
      file_.WriteBlock(arrays_[i], name.c_str(), memory, {frames, rows, 3}, {f, 0, 0}, {1, n, 3},
                       a.data);
    }
  }
}

void Hdf5TrajectoryWriter::Write(const ParticleFrame& frame) {
  if (closed_) throw std::logic_error(fmt::format("{}: Write after Close", path_.string()));
  internal::ValidateFrame(frame, path_);
  if (!frames_.empty() && frame.time < frames_.back().time) {
    throw InputError(fmt::format("{}: frame at step {} has time {} before the previous frame's {}",
                                 path_.string(), frame.step, frame.time, frames_.back().time));
  }
  if (!has_particle_datasets_) {
    CreateParticleDatasets(frame);
  } else if (frame.dimension != dimension_) {
    throw InputError(fmt::format(
        "{}: frame at step {} has dimension {}, but the trajectory was started in dimension {} "
        "(an HDF5 trajectory keeps k fixed)",
        path_.string(), frame.step, frame.dimension, dimension_));
  } else {
    internal::CheckSameArrays(specs_, frame, path_);
  }
  if (frame.count > rows_) GrowParticleAxis(frame.count);
  const hsize_t f = frames_.size(), frames = f + 1, rows = static_cast<hsize_t>(rows_);
  const auto n = static_cast<hsize_t>(frame.count), k = static_cast<hsize_t>(dimension_);
  file_.WriteBlock(time_, "time", H5T_NATIVE_DOUBLE, {frames}, {f}, {1}, &frame.time);
  file_.WriteBlock(step_, "step", H5T_NATIVE_INT64, {frames}, {f}, {1}, &frame.step);
  file_.WriteBlock(count_, "count", H5T_NATIVE_INT64, {frames}, {f}, {1}, &frame.count);
  file_.WriteBlock(positions_, "positions", H5T_NATIVE_DOUBLE, {frames, rows, k}, {f, 0, 0},
                   {1, n, k}, frame.positions);
  file_.WriteBlock(ids_, "ids", H5T_NATIVE_INT64, {frames, rows}, {f, 0}, {1, n}, frame.ids);
  file_.WriteBlock(radii_, "radii", H5T_NATIVE_DOUBLE, {frames, rows}, {f, 0}, {1, n}, frame.radii);
  WriteArrays(frame);
  WriteFrameViews(frames_.size(), frame.count);
  // Keep the file readable up to this frame even if the run stops without Close().
  file_.Flush();
  frames_.push_back({frame.time, frame.count});
}

void Hdf5TrajectoryWriter::Close() {
  if (closed_) return;
  closed_ = true;
  // Close everything even if one close fails, then report the first failure.
  bool ok = true;
  for (Handle* h : {&time_, &step_, &count_, &positions_, &ids_, &radii_, &connectivity_}) {
    ok = h->Reset() && ok;
  }
  for (Handle& h : arrays_) ok = h.Reset() && ok;
  ok = file_.Close() && ok;
  file_.Check(ok ? 0 : -1, "closing the file");
  internal::WriteWholeFile(
      xdmf_path_,
      internal::XdmfSidecarText(path_.filename().string(), dimension_,
                                static_cast<int>(H5Tget_size(position_type_)), frames_, specs_));
}

}  // namespace

std::string_view TrajectoryPrecisionName(TrajectoryPrecision precision) {
  return precision == TrajectoryPrecision::kSingle ? "single" : "double";
}

TrajectoryPrecision ParseTrajectoryPrecision(std::string_view name) {
  if (name == "double") return TrajectoryPrecision::kDouble;
  if (name == "single") return TrajectoryPrecision::kSingle;
  throw InputError(fmt::format("unknown precision '{}' (expected double or single)", name));
}

void Hdf5TrajectoryOptions::Validate() const {
  if (compression < 0 || compression > 9) {
    throw InputError(
        fmt::format("compression must be in 0 … 9 (a deflate level; 0 stores raw chunks), got {}",
                    compression));
  }
  if (compression > 0 && H5Zfilter_avail(H5Z_FILTER_DEFLATE) <= 0) {
    throw InputError("compression needs HDF5's deflate filter, which this HDF5 library lacks");
  }
}

std::unique_ptr<TrajectoryWriter> MakeHdf5Writer(const std::filesystem::path& path,
                                                 const Hdf5TrajectoryOptions& options,
                                                 const std::vector<StringList>& lists) {
  return std::make_unique<Hdf5TrajectoryWriter>(path, options, lists);
}

}  // namespace moreau::io
