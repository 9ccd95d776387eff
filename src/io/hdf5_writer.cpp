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
using internal::Hdf5ErrorText;

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
  // Throws std::runtime_error naming the file and `what` when `status` < 0.
  void Check(std::int64_t status, const std::string& what) const;
  // A chunked dataset of extent 0 along every axis but the last `fixed_tail` ones; every other
  // axis is unlimited. `fill` (of `memory_type`) is what unwritten elements read as.
  Handle CreateExtensible(hid_t location, const char* name, hid_t file_type,
                          const std::vector<hsize_t>& chunk, std::size_t fixed_tail,
                          hid_t memory_type, const void* fill);
  // Sets the extent of `dataset` to `dims` and writes `data` (shape `count`) at `start`.
  void WriteBlock(const Handle& dataset, const char* name, hid_t memory_type,
                  const std::vector<hsize_t>& dims, const std::vector<hsize_t>& start,
                  const std::vector<hsize_t>& count, const void* data);
  // A virtual dataset `name` in `group` of shape `count` that shows the block of `source` (extent
  // `source_dims`) at `start`.
  void CreateView(hid_t group, const char* name, hid_t file_type, const char* source,
                  const std::vector<hsize_t>& source_dims, const std::vector<hsize_t>& start,
                  const std::vector<hsize_t>& count);
  // The group `name` (absolute path), without modification times.
  Handle CreateGroup(const std::string& name);
  void WriteAttribute(const char* name, hid_t file_type, hid_t memory_type, const void* value);
  void WriteStringAttribute(const char* name, const std::string& value);
  // The root attribute list.name: an array of fixed-length strings.
  void WriteStringList(const StringList& list);
  void CreateParticleDatasets(const ParticleFrame& frame);
  // Widens the particle axis to `count` rows (connectivity 0 … count−1 included).
  void GrowParticleAxis(std::int64_t count);
  void WriteFrameViews(std::size_t index, std::int64_t count);
  void WriteArrays(const ParticleFrame& frame);

  std::filesystem::path path_;
  std::filesystem::path xdmf_path_;
  Hdf5TrajectoryOptions options_;
  hid_t position_type_;  // file type of /positions: float64 or float32
  Handle file_;
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
                                                                       : H5T_IEEE_F64LE) {
  options_.Validate();
  if (path_.extension() == ".xdmf") {
    throw InputError(
        fmt::format("HDF5 trajectory path {} must not end in .xdmf (that name is "
                    "taken by its XDMF sidecar)",
                    path_.string()));
  }
  internal::CheckParentDirectory(path_);
  internal::ValidateLists(lists, kRootAttributes, path_);
  // The library never prints: errors are turned into exceptions below.
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  // Each frame adds a group of virtual datasets that is written once and closed: evicting the
  // metadata of closed objects keeps the writer's memory flat over a long run (the soak test).
  Handle access(H5Pcreate(H5P_FILE_ACCESS), H5Pclose);
  if (access.get() < 0 || H5Pset_evict_on_close(access.get(), true) < 0) {
    throw InputError(fmt::format("cannot create {}: {}", path_.string(), Hdf5ErrorText()));
  }
  const hid_t file = H5Fcreate(path_.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, access.get());
  if (file < 0) {
    throw InputError(fmt::format("cannot create {}: {}", path_.string(), Hdf5ErrorText()));
  }
  file_ = Handle(file, H5Fclose);
  const double no_time = kMissingValue;
  const std::int64_t no_count = 0;
  time_ = CreateExtensible(file, "time", H5T_IEEE_F64LE, {256}, 0, H5T_NATIVE_DOUBLE, &no_time);
  step_ = CreateExtensible(file, "step", H5T_STD_I64LE, {256}, 0, H5T_NATIVE_INT64, &kMissingId);
  count_ = CreateExtensible(file, "count", H5T_STD_I64LE, {256}, 0, H5T_NATIVE_INT64, &no_count);
  WriteStringAttribute("format", kFormatName);
  WriteAttribute("format_version", H5T_STD_I32LE, H5T_NATIVE_INT, &kFormatVersion);
  for (const StringList& list : lists) WriteStringList(list);
}

void Hdf5TrajectoryWriter::Check(std::int64_t status, const std::string& what) const {
  if (status < 0) {
    throw std::runtime_error(
        fmt::format("HDF5 error writing {} ({}): {}", path_.string(), what, Hdf5ErrorText()));
  }
}

Handle Hdf5TrajectoryWriter::CreateExtensible(hid_t location, const char* name, hid_t file_type,
                                              const std::vector<hsize_t>& chunk,
                                              std::size_t fixed_tail, hid_t memory_type,
                                              const void* fill) {
  const std::size_t rank = chunk.size();
  std::vector<hsize_t> dims(rank, 0), max_dims(rank, H5S_UNLIMITED);
  for (std::size_t a = rank - fixed_tail; a < rank; ++a) dims[a] = max_dims[a] = chunk[a];
  const std::string what = fmt::format("creating /{}", name);
  Handle space(H5Screate_simple(static_cast<int>(rank), dims.data(), max_dims.data()), H5Sclose);
  Check(space.get(), what);
  Handle properties(H5Pcreate(H5P_DATASET_CREATE), H5Pclose);
  Check(properties.get(), what);
  Check(H5Pset_chunk(properties.get(), static_cast<int>(rank), chunk.data()), what);
  Check(H5Pset_fill_value(properties.get(), memory_type, fill), what);
  if (options_.compression > 0) {
    // Shuffling groups the bytes of equal significance, which deflate then compresses far better.
    Check(H5Pset_shuffle(properties.get()), what);
    Check(H5Pset_deflate(properties.get(), static_cast<unsigned>(options_.compression)), what);
  }
  // No modification times in the file: the same run gives the same bytes.
  Check(H5Pset_obj_track_times(properties.get(), false), what);
  Handle dataset(H5Dcreate2(location, name, file_type, space.get(), H5P_DEFAULT, properties.get(),
                            H5P_DEFAULT),
                 H5Dclose);
  Check(dataset.get(), what);
  return dataset;
}

void Hdf5TrajectoryWriter::WriteBlock(const Handle& dataset, const char* name, hid_t memory_type,
                                      const std::vector<hsize_t>& dims,
                                      const std::vector<hsize_t>& start,
                                      const std::vector<hsize_t>& count, const void* data) {
  const std::string what = fmt::format("writing /{}", name);
  Check(H5Dset_extent(dataset.get(), dims.data()), what);
  hsize_t elements = 1;
  for (const hsize_t extent : count) elements *= extent;
  if (elements == 0) return;
  Handle file_space(H5Dget_space(dataset.get()), H5Sclose);
  Check(file_space.get(), what);
  Check(H5Sselect_hyperslab(file_space.get(), H5S_SELECT_SET, start.data(), nullptr, count.data(),
                            nullptr),
        what);
  Handle memory_space(H5Screate_simple(static_cast<int>(count.size()), count.data(), nullptr),
                      H5Sclose);
  Check(memory_space.get(), what);
  Check(
      H5Dwrite(dataset.get(), memory_type, memory_space.get(), file_space.get(), H5P_DEFAULT, data),
      what);
}

void Hdf5TrajectoryWriter::CreateView(hid_t group, const char* name, hid_t file_type,
                                      const char* source, const std::vector<hsize_t>& source_dims,
                                      const std::vector<hsize_t>& start,
                                      const std::vector<hsize_t>& count) {
  const std::string what = fmt::format("view of /{}", source);
  Handle source_space(
      H5Screate_simple(static_cast<int>(source_dims.size()), source_dims.data(), nullptr),
      H5Sclose);
  Check(source_space.get(), what);
  Check(H5Sselect_hyperslab(source_space.get(), H5S_SELECT_SET, start.data(), nullptr, count.data(),
                            nullptr),
        what);
  // The view drops the axes of extent 1 at the front of the block (the frame axis).
  const std::vector<hsize_t> shape(count.size() > 1 ? count.begin() + 1 : count.begin(),
                                   count.end());
  Handle view_space(H5Screate_simple(static_cast<int>(shape.size()), shape.data(), nullptr),
                    H5Sclose);
  Check(view_space.get(), what);
  Handle properties(H5Pcreate(H5P_DATASET_CREATE), H5Pclose);
  Check(properties.get(), what);
  Check(H5Pset_obj_track_times(properties.get(), false), what);
  // "." is this file, so the views move with it.
  Check(H5Pset_virtual(properties.get(), view_space.get(), ".", source, source_space.get()), what);
  Handle view(H5Dcreate2(group, name, file_type, view_space.get(), H5P_DEFAULT, properties.get(),
                         H5P_DEFAULT),
              H5Dclose);
  Check(view.get(), what);
}

Handle Hdf5TrajectoryWriter::CreateGroup(const std::string& name) {
  const std::string what = "creating " + name;
  Handle properties(H5Pcreate(H5P_GROUP_CREATE), H5Pclose);
  Check(properties.get(), what);
  Check(H5Pset_obj_track_times(properties.get(), false), what);  // same run, same bytes
  Handle group(H5Gcreate2(file_.get(), name.c_str(), H5P_DEFAULT, properties.get(), H5P_DEFAULT),
               H5Gclose);
  Check(group.get(), what);
  return group;
}

void Hdf5TrajectoryWriter::WriteAttribute(const char* name, hid_t file_type, hid_t memory_type,
                                          const void* value) {
  const std::string what = fmt::format("attribute {}", name);
  const htri_t exists = H5Aexists(file_.get(), name);
  Check(exists, what);
  Handle attribute;
  if (exists > 0) {
    attribute = Handle(H5Aopen(file_.get(), name, H5P_DEFAULT), H5Aclose);
  } else {
    Handle space(H5Screate(H5S_SCALAR), H5Sclose);
    Check(space.get(), what);
    attribute = Handle(
        H5Acreate2(file_.get(), name, file_type, space.get(), H5P_DEFAULT, H5P_DEFAULT), H5Aclose);
  }
  Check(attribute.get(), what);
  Check(H5Awrite(attribute.get(), memory_type, value), what);
}

void Hdf5TrajectoryWriter::WriteStringAttribute(const char* name, const std::string& value) {
  const std::string what = fmt::format("attribute {}", name);
  Handle type(H5Tcopy(H5T_C_S1), H5Tclose);
  Check(type.get(), what);
  Check(H5Tset_size(type.get(), value.size() + 1), what);
  Check(H5Tset_strpad(type.get(), H5T_STR_NULLTERM), what);
  WriteAttribute(name, type.get(), type.get(), value.c_str());
}

void Hdf5TrajectoryWriter::WriteStringList(const StringList& list) {
  const std::string what = fmt::format("attribute {}", list.name);
  std::size_t width = 1;
  for (const std::string& v : list.values) width = std::max(width, v.size() + 1);
  std::vector<char> text(width * list.values.size(), '\0');
  for (std::size_t i = 0; i < list.values.size(); ++i) {
    std::copy(list.values[i].begin(), list.values[i].end(), text.begin() + i * width);
  }
  Handle type(H5Tcopy(H5T_C_S1), H5Tclose);
  Check(type.get(), what);
  Check(H5Tset_size(type.get(), width), what);
  Check(H5Tset_strpad(type.get(), H5T_STR_NULLTERM), what);
  const hsize_t n = list.values.size();
  Handle space(H5Screate_simple(1, &n, nullptr), H5Sclose);
  Check(space.get(), what);
  Handle attribute(
      H5Acreate2(file_.get(), list.name.c_str(), type.get(), space.get(), H5P_DEFAULT, H5P_DEFAULT),
      H5Aclose);
  Check(attribute.get(), what);
  Check(H5Awrite(attribute.get(), type.get(), text.data()), what);
}

void Hdf5TrajectoryWriter::CreateParticleDatasets(const ParticleFrame& frame) {
  const auto k = static_cast<hsize_t>(frame.dimension);
  const auto [frames_xk, rows_xk] = ChunkShape(frame.count, H5Tget_size(position_type_) * k);
  const auto [frames_x1, rows_x1] = ChunkShape(frame.count, 8);
  const hid_t file = file_.get();
  positions_ = CreateExtensible(file, "positions", position_type_, {frames_xk, rows_xk, k}, 1,
                                H5T_NATIVE_DOUBLE, &kMissingValue);
  ids_ = CreateExtensible(file, "ids", H5T_STD_I64LE, {frames_x1, rows_x1}, 0, H5T_NATIVE_INT64,
                          &kMissingId);
  radii_ = CreateExtensible(file, "radii", H5T_IEEE_F64LE, {frames_x1, rows_x1}, 0,
                            H5T_NATIVE_DOUBLE, &kMissingValue);
  connectivity_ = CreateExtensible(file, "connectivity", H5T_STD_I64LE, {4096}, 0, H5T_NATIVE_INT64,
                                   &kMissingId);
  specs_ = internal::SpecsOf(frame.arrays);
  if (!specs_.empty()) CreateGroup("/point_data");
  for (const internal::ArraySpec& a : specs_) {
    const bool integer = a.type == PointArray::Type::kInt64;
    const auto c = static_cast<hsize_t>(a.components);
    const auto [frames_a, rows_a] = ChunkShape(frame.count, 8 * c);
    std::vector<hsize_t> chunk{frames_a, rows_a};
    if (c > 1) chunk.push_back(c);
    arrays_.push_back(CreateExtensible(
        file, ("point_data/" + a.name).c_str(), integer ? H5T_STD_I64LE : H5T_IEEE_F64LE, chunk,
        c > 1 ? 1 : 0, integer ? H5T_NATIVE_INT64 : H5T_NATIVE_DOUBLE,
        integer ? static_cast<const void*>(&kMissingId) : &kMissingValue));
  }
  CreateGroup("/xdmf");
  WriteAttribute("dimension", H5T_STD_I32LE, H5T_NATIVE_INT, &frame.dimension);
  WriteAttribute("count", H5T_STD_I64LE, H5T_NATIVE_INT64, &rows_);
  dimension_ = frame.dimension;
  has_particle_datasets_ = true;
}

void Hdf5TrajectoryWriter::GrowParticleAxis(std::int64_t count) {
  indices_.resize(static_cast<std::size_t>(count - rows_));
  for (std::size_t i = 0; i < indices_.size(); ++i) {
    indices_[i] = rows_ + static_cast<std::int64_t>(i);
  }
  const auto n = static_cast<hsize_t>(count);
  WriteBlock(connectivity_, "connectivity", H5T_NATIVE_INT64, {n}, {static_cast<hsize_t>(rows_)},
             {indices_.size()}, indices_.data());
  rows_ = count;
  WriteAttribute("count", H5T_STD_I64LE, H5T_NATIVE_INT64, &rows_);
}

void Hdf5TrajectoryWriter::WriteFrameViews(std::size_t index, std::int64_t count) {
  const std::string name = internal::XdmfFrameGroup(index);
  Handle group = CreateGroup(name);
  if (count == 0) return;
  const hsize_t frames = index + 1, f = index, rows = static_cast<hsize_t>(rows_);
  const auto n = static_cast<hsize_t>(count), k = static_cast<hsize_t>(dimension_);
  const hid_t g = group.get();
  CreateView(g, "positions", position_type_, "/positions", {frames, rows, k}, {f, 0, 0}, {1, n, k});
  CreateView(g, "radii", H5T_IEEE_F64LE, "/radii", {frames, rows}, {f, 0}, {1, n});
  CreateView(g, "ids", H5T_STD_I64LE, "/ids", {frames, rows}, {f, 0}, {1, n});
  CreateView(g, "connectivity", H5T_STD_I64LE, "/connectivity", {rows}, {0}, {n});
  if (specs_.empty()) return;
  Handle point_data = CreateGroup(name + "/point_data");
  for (const internal::ArraySpec& a : specs_) {
    const hid_t type = a.type == PointArray::Type::kInt64 ? H5T_STD_I64LE : H5T_IEEE_F64LE;
    const std::string source = "/point_data/" + a.name;
    if (a.components == 1) {
      CreateView(point_data.get(), a.name.c_str(), type, source.c_str(), {frames, rows}, {f, 0},
                 {1, n});
    } else {
      CreateView(point_data.get(), a.name.c_str(), type, source.c_str(), {frames, rows, 3},
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
      WriteBlock(arrays_[i], name.c_str(), memory, {frames, rows}, {f, 0}, {1, n}, a.data);
    } else {
      WriteBlock(arrays_[i], name.c_str(), memory, {frames, rows, 3}, {f, 0, 0}, {1, n, 3}, a.data);
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
  WriteBlock(time_, "time", H5T_NATIVE_DOUBLE, {frames}, {f}, {1}, &frame.time);
  WriteBlock(step_, "step", H5T_NATIVE_INT64, {frames}, {f}, {1}, &frame.step);
  WriteBlock(count_, "count", H5T_NATIVE_INT64, {frames}, {f}, {1}, &frame.count);
  WriteBlock(positions_, "positions", H5T_NATIVE_DOUBLE, {frames, rows, k}, {f, 0, 0}, {1, n, k},
             frame.positions);
  WriteBlock(ids_, "ids", H5T_NATIVE_INT64, {frames, rows}, {f, 0}, {1, n}, frame.ids);
  WriteBlock(radii_, "radii", H5T_NATIVE_DOUBLE, {frames, rows}, {f, 0}, {1, n}, frame.radii);
  WriteArrays(frame);
  WriteFrameViews(frames_.size(), frame.count);
  // Keep the file readable up to this frame even if the run stops without Close().
  Check(H5Fflush(file_.get(), H5F_SCOPE_LOCAL), "flush");
  frames_.push_back({frame.time, frame.count});
}

void Hdf5TrajectoryWriter::Close() {
  if (closed_) return;
  closed_ = true;
  // Close everything even if one close fails, then report the first failure.
  bool ok = true;
  for (Handle* h : {&time_, &step_, &count_, &positions_, &ids_, &radii_, &connectivity_, &file_}) {
    ok = h->Reset() && ok;
  }
  for (Handle& h : arrays_) ok = h.Reset() && ok;
  Check(ok ? 0 : -1, "closing the file");
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
