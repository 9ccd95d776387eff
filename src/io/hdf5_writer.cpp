// HDF5 trajectory with an XDMF 3 sidecar (layout in include/moreau/io/trajectory.h, docs/io.md).
#include <fmt/format.h>
#include <hdf5.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "io/io_util.h"
#include "moreau/common/error.h"
#include "moreau/io/trajectory.h"

namespace moreau::io {
namespace {

constexpr int kFormatVersion = 1;
constexpr char kFormatName[] = "moreau-trajectory";
// Target size of one chunk, and the most frames one chunk holds (so that short runs of few
// particles do not allocate a large first chunk).
constexpr hsize_t kChunkBytes = hsize_t{1} << 20;
constexpr hsize_t kMaxFramesPerChunk = 64;

// An HDF5 identifier closed by its own close function; move-only.
class Handle {
 public:
  using Closer = herr_t (*)(hid_t);
  Handle() = default;
  Handle(hid_t id, Closer closer) : id_(id), closer_(closer) {}
  Handle(Handle&& other) noexcept
      : id_(std::exchange(other.id_, H5I_INVALID_HID)), closer_(other.closer_) {}
  Handle& operator=(Handle&& other) noexcept {
    if (this != &other) {
      Reset();
      id_ = std::exchange(other.id_, H5I_INVALID_HID);
      closer_ = other.closer_;
    }
    return *this;
  }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  ~Handle() { Reset(); }

  hid_t get() const { return id_; }
  bool valid() const { return id_ >= 0; }
  // Closes the identifier; returns false if HDF5 reported an error.
  bool Reset() {
    if (id_ < 0) return true;
    const herr_t status = closer_(id_);
    id_ = H5I_INVALID_HID;
    return status >= 0;
  }

 private:
  hid_t id_ = H5I_INVALID_HID;
  Closer closer_ = nullptr;
};

herr_t KeepInnermostError(unsigned /*n*/, const H5E_error2_t* error, void* client_data) {
  auto* text = static_cast<std::string*>(client_data);
  if (text->empty() && error != nullptr && error->desc != nullptr) *text = error->desc;
  return 0;
}

// The description of the innermost error on HDF5's current error stack (which it clears).
std::string Hdf5ErrorText() {
  std::string text;
  const hid_t stack = H5Eget_current_stack();
  if (stack >= 0) {
    H5Ewalk2(stack, H5E_WALK_UPWARD, KeepInnermostError, &text);
    H5Eclose_stack(stack);
  }
  return text.empty() ? std::string("unknown HDF5 error") : text;
}

// Chunk shape {frames, particles} for per-frame records of `count` particles of
// `bytes_per_particle` bytes each: about kChunkBytes, whole frames while they fit.
std::array<hsize_t, 2> ChunkShape(std::int64_t count, hsize_t bytes_per_particle) {
  const hsize_t n = std::max<hsize_t>(1, static_cast<hsize_t>(count));
  const hsize_t frame_bytes = n * bytes_per_particle;
  if (frame_bytes >= kChunkBytes) {
    return {1, std::max<hsize_t>(1, kChunkBytes / bytes_per_particle)};
  }
  return {std::clamp<hsize_t>(kChunkBytes / frame_bytes, 1, kMaxFramesPerChunk), n};
}

class Hdf5TrajectoryWriter final : public TrajectoryWriter {
 public:
  explicit Hdf5TrajectoryWriter(const std::filesystem::path& path);
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
  Handle CreateExtensible(const char* name, hid_t file_type, std::vector<hsize_t> frame_shape,
                          const std::array<hsize_t, 2>& chunk);
  // Grows `dataset` to frames_ + 1 frames and writes one frame of `frame_shape` from `data`.
  void AppendFrame(const Handle& dataset, const char* name, hid_t memory_type,
                   const std::vector<hsize_t>& frame_shape, const void* data);
  void WriteAttribute(const char* name, hid_t file_type, hid_t memory_type, const void* value);
  void WriteStringAttribute(const char* name, const std::string& value);
  void CreateParticleDatasets(const ParticleFrame& frame);
  std::string XdmfText() const;

  std::filesystem::path path_;
  std::filesystem::path xdmf_path_;
  Handle file_;
  Handle time_, step_, positions_, ids_, radii_;
  bool closed_ = false;
  bool has_particle_datasets_ = false;
  int dimension_ = 0;
  std::int64_t count_ = 0;
  std::vector<double> times_;  // one per frame written
};

Hdf5TrajectoryWriter::Hdf5TrajectoryWriter(const std::filesystem::path& path)
    : path_(path), xdmf_path_(std::filesystem::path(path).replace_extension(".xdmf")) {
  if (path_.extension() == ".xdmf") {
    throw InputError(
        fmt::format("HDF5 trajectory path {} must not end in .xdmf (that name is "
                    "taken by its XDMF sidecar)",
                    path_.string()));
  }
  internal::CheckParentDirectory(path_);
  // The library never prints: errors are turned into exceptions below.
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  const hid_t file = H5Fcreate(path_.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  if (file < 0) {
    throw InputError(fmt::format("cannot create {}: {}", path_.string(), Hdf5ErrorText()));
  }
  file_ = Handle(file, H5Fclose);
  time_ = CreateExtensible("time", H5T_IEEE_F64LE, {}, {256, 0});
  step_ = CreateExtensible("step", H5T_STD_I64LE, {}, {256, 0});
  WriteStringAttribute("format", kFormatName);
  WriteAttribute("format_version", H5T_STD_I32LE, H5T_NATIVE_INT, &kFormatVersion);
}

void Hdf5TrajectoryWriter::Check(std::int64_t status, const std::string& what) const {
  if (status < 0) {
    throw std::runtime_error(
        fmt::format("HDF5 error writing {} ({}): {}", path_.string(), what, Hdf5ErrorText()));
  }
}

Handle Hdf5TrajectoryWriter::CreateExtensible(const char* name, hid_t file_type,
                                              std::vector<hsize_t> frame_shape,
                                              const std::array<hsize_t, 2>& chunk) {
  // dims = {0 frames, frame_shape...}; a zero-sized particle axis is made extensible too, as a
  // fixed zero extent cannot hold a chunk.
  std::vector<hsize_t> dims{0}, max_dims{H5S_UNLIMITED}, chunk_dims{chunk[0]};
  for (std::size_t a = 0; a < frame_shape.size(); ++a) {
    dims.push_back(frame_shape[a]);
    max_dims.push_back(frame_shape[a] == 0 ? H5S_UNLIMITED : frame_shape[a]);
    chunk_dims.push_back(a == 0 ? chunk[1] : std::max<hsize_t>(1, frame_shape[a]));
  }
  const int rank = static_cast<int>(dims.size());
  const std::string what = fmt::format("creating /{}", name);
  Handle space(H5Screate_simple(rank, dims.data(), max_dims.data()), H5Sclose);
  Check(space.get(), what);
  Handle properties(H5Pcreate(H5P_DATASET_CREATE), H5Pclose);
  Check(properties.get(), what);
  Check(H5Pset_chunk(properties.get(), rank, chunk_dims.data()), what);
  // No modification times in the file: the same run gives the same bytes.
  Check(H5Pset_obj_track_times(properties.get(), false), what);
  Handle dataset(H5Dcreate2(file_.get(), name, file_type, space.get(), H5P_DEFAULT,
                            properties.get(), H5P_DEFAULT),
                 H5Dclose);
  Check(dataset.get(), what);
  return dataset;
}

void Hdf5TrajectoryWriter::AppendFrame(const Handle& dataset, const char* name, hid_t memory_type,
                                       const std::vector<hsize_t>& frame_shape, const void* data) {
  const std::string what = fmt::format("appending to /{}", name);
  const hsize_t frame = times_.size();
  std::vector<hsize_t> dims{frame + 1}, start{frame}, count{1};
  hsize_t elements = 1;
  for (const hsize_t extent : frame_shape) {
    dims.push_back(extent);
    start.push_back(0);
    count.push_back(extent);
    elements *= extent;
  }
  Check(H5Dset_extent(dataset.get(), dims.data()), what);
  if (elements == 0) return;
  const int rank = static_cast<int>(dims.size());
  Handle file_space(H5Dget_space(dataset.get()), H5Sclose);
  Check(file_space.get(), what);
  Check(H5Sselect_hyperslab(file_space.get(), H5S_SELECT_SET, start.data(), nullptr, count.data(),
                            nullptr),
        what);
  Handle memory_space(H5Screate_simple(rank, count.data(), nullptr), H5Sclose);
  Check(memory_space.get(), what);
  Check(
      H5Dwrite(dataset.get(), memory_type, memory_space.get(), file_space.get(), H5P_DEFAULT, data),
      what);
}

void Hdf5TrajectoryWriter::WriteAttribute(const char* name, hid_t file_type, hid_t memory_type,
                                          const void* value) {
  const std::string what = fmt::format("attribute {}", name);
  Handle space(H5Screate(H5S_SCALAR), H5Sclose);
  Check(space.get(), what);
  Handle attribute(H5Acreate2(file_.get(), name, file_type, space.get(), H5P_DEFAULT, H5P_DEFAULT),
                   H5Aclose);
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

void Hdf5TrajectoryWriter::CreateParticleDatasets(const ParticleFrame& frame) {
  const auto n = static_cast<hsize_t>(frame.count);
  const auto k = static_cast<hsize_t>(frame.dimension);
  positions_ =
      CreateExtensible("positions", H5T_IEEE_F64LE, {n, k}, ChunkShape(frame.count, 8 * k));
  ids_ = CreateExtensible("ids", H5T_STD_I64LE, {n}, ChunkShape(frame.count, 8));
  radii_ = CreateExtensible("radii", H5T_IEEE_F64LE, {n}, ChunkShape(frame.count, 8));
  WriteAttribute("dimension", H5T_STD_I32LE, H5T_NATIVE_INT, &frame.dimension);
  WriteAttribute("count", H5T_STD_I64LE, H5T_NATIVE_INT64, &frame.count);
  dimension_ = frame.dimension;
  count_ = frame.count;
  has_particle_datasets_ = true;
}

void Hdf5TrajectoryWriter::Write(const ParticleFrame& frame) {
  if (closed_) throw std::logic_error(fmt::format("{}: Write after Close", path_.string()));
  internal::ValidateFrame(frame, path_);
  if (!times_.empty() && frame.time < times_.back()) {
    throw InputError(fmt::format("{}: frame at step {} has time {} before the previous frame's {}",
                                 path_.string(), frame.step, frame.time, times_.back()));
  }
  if (!has_particle_datasets_) {
    CreateParticleDatasets(frame);
  } else if (frame.count != count_ || frame.dimension != dimension_) {
    throw InputError(fmt::format(
        "{}: frame at step {} has {} particles in dimension {}, but the trajectory was started "
        "with {} in dimension {} (an HDF5 trajectory keeps N and k fixed)",
        path_.string(), frame.step, frame.count, frame.dimension, count_, dimension_));
  }
  const auto n = static_cast<hsize_t>(count_);
  const auto k = static_cast<hsize_t>(dimension_);
  AppendFrame(time_, "time", H5T_NATIVE_DOUBLE, {}, &frame.time);
  AppendFrame(step_, "step", H5T_NATIVE_INT64, {}, &frame.step);
  AppendFrame(positions_, "positions", H5T_NATIVE_DOUBLE, {n, k}, frame.positions);
  AppendFrame(ids_, "ids", H5T_NATIVE_INT64, {n}, frame.ids);
  AppendFrame(radii_, "radii", H5T_NATIVE_DOUBLE, {n}, frame.radii);
  // Keep the file readable up to this frame even if the run stops without Close().
  Check(H5Fflush(file_.get(), H5F_SCOPE_LOCAL), "flush");
  times_.push_back(frame.time);
}

void Hdf5TrajectoryWriter::Close() {
  if (closed_) return;
  closed_ = true;
  // Close everything even if one close fails, then report the first failure.
  bool ok = true;
  for (Handle* h : {&time_, &step_, &positions_, &ids_, &radii_, &file_}) ok = h->Reset() && ok;
  Check(ok ? 0 : -1, "closing the file");
  internal::WriteWholeFile(xdmf_path_, XdmfText());
}

std::string Hdf5TrajectoryWriter::XdmfText() const {
  const std::string h5 = internal::XmlEscape(path_.filename().string());
  const std::size_t frames = times_.size();
  const std::int64_t n = count_;
  const int k = dimension_;
  std::string out;
  out += "<?xml version=\"1.0\" ?>\n";
  out += "<!DOCTYPE Xdmf SYSTEM \"Xdmf.dtd\" []>\n";
  out += "<Xdmf Version=\"3.0\" xmlns:xi=\"http://www.w3.org/2001/XInclude\">\n";
  out += "  <Domain>\n";
  out += "    <Grid Name=\"trajectory\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
  for (std::size_t f = 0; f < frames; ++f) {
    out += fmt::format("      <Grid Name=\"frame_{:06d}\" GridType=\"Uniform\">\n", f);
    out += fmt::format("        <Time Value=\"{}\"/>\n", internal::FormatDouble(times_[f]));
    out += fmt::format(
        "        <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"{}\" "
        "NodesPerElement=\"1\"/>\n",
        n);
    out += fmt::format("        <Geometry GeometryType=\"{}\">\n", k == 2 ? "XY" : "XYZ");
    out += fmt::format(
        "          <DataItem ItemType=\"HyperSlab\" Dimensions=\"{} {}\" "
        "Type=\"HyperSlab\">\n",
        n, k);
    out += fmt::format(
        "            <DataItem Dimensions=\"3 3\" NumberType=\"Int\" "
        "Format=\"XML\">{} 0 0 1 1 1 1 {} {}</DataItem>\n",
        f, n, k);
    out += fmt::format(
        "            <DataItem Dimensions=\"{} {} {}\" NumberType=\"Float\" "
        "Precision=\"8\" Format=\"HDF\">{}:/positions</DataItem>\n",
        frames, n, k, h5);
    out += "          </DataItem>\n";
    out += "        </Geometry>\n";
    const std::array<std::array<const char*, 3>, 2> attributes{
        {{"radius", "Float", "radii"}, {"id", "Int", "ids"}}};
    for (const auto& [name, number_type, dataset] : attributes) {
      out += fmt::format(
          "        <Attribute Name=\"{}\" AttributeType=\"Scalar\" "
          "Center=\"Node\">\n",
          name);
      out += fmt::format(
          "          <DataItem ItemType=\"HyperSlab\" Dimensions=\"{}\" "
          "Type=\"HyperSlab\">\n",
          n);
      out += fmt::format(
          "            <DataItem Dimensions=\"3 2\" NumberType=\"Int\" "
          "Format=\"XML\">{} 0 1 1 1 {}</DataItem>\n",
          f, n);
      out += fmt::format(
          "            <DataItem Dimensions=\"{} {}\" NumberType=\"{}\" "
          "Precision=\"8\" Format=\"HDF\">{}:/{}</DataItem>\n",
          frames, n, number_type, h5, dataset);
      out += "          </DataItem>\n";
      out += "        </Attribute>\n";
    }
    out += "      </Grid>\n";
  }
  out += "    </Grid>\n";
  out += "  </Domain>\n";
  out += "</Xdmf>\n";
  return out;
}

}  // namespace

std::unique_ptr<TrajectoryWriter> MakeHdf5Writer(const std::filesystem::path& path) {
  return std::make_unique<Hdf5TrajectoryWriter>(path);
}

}  // namespace moreau::io
