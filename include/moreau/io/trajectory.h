// Trajectory writers for particle simulations: an HDF5 file with an XDMF sidecar, or a series of
// VTU files with a PVD index. Both open in ParaView; docs/io.md describes the layouts.
//
// A writer is created for one run, receives frames in time order through Write() and finishes its
// files in Close(). The library never prints: every failure is an exception whose one-line message
// names the file.
//
//   InputError          bad output path (missing directory, file that cannot be created), or a
//                       frame that does not fit the run (dimension not 2 or 3, null arrays, the
//                       dimension changing in an HDF5 trajectory, time going backwards)
//   std::runtime_error  a write that fails part-way (disk full, HDF5 error)
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace moreau::io {

// One extra per-particle array of a frame (an agent's type, generation, polarity, …): N·c values,
// particle-major, float64 or int64. Make one with Float64 or Int64.
struct PointArray {
  enum class Type { kFloat64, kInt64 };
  std::string_view name;  // not empty, no '/', unique in the frame, not "radius" or "id"
  Type type = Type::kFloat64;
  int components = 1;          // c: 1 (a scalar) or 3 (a vector; z = 0 in 2D)
  const void* data = nullptr;  // N·c values of `type` (may be null when N = 0)

  static PointArray Float64(std::string_view name, const double* values, int components = 1) {
    return {name, Type::kFloat64, components, values};
  }
  static PointArray Int64(std::string_view name, const std::int64_t* values, int components = 1) {
    return {name, Type::kInt64, components, values};
  }
};

// A named list of strings a writer records once per file (the agent types' names, say):
// an HDF5 root attribute (an array of strings), a string array in every VTU frame's FieldData.
struct StringList {
  std::string name;  // not empty, no '/', not one of the root attributes the writer sets itself
  std::vector<std::string> values;
};

// One frame of N particles in dimension k ∈ {2, 3}. The writer copies what it needs during
// Write(); the arrays are not retained.
struct ParticleFrame {
  std::int64_t step = 0;              // time-step index of the frame
  double time = 0.0;                  // simulated time t
  int dimension = 2;                  // k
  const double* positions = nullptr;  // N·k, particle-major: x0, y0[, z0], x1, …
  const std::int64_t* ids = nullptr;  // N stable particle ids
  const double* radii = nullptr;      // N radii
  std::int64_t count = 0;             // N ≥ 0 (the arrays may be null when N = 0)
  // Extra per-particle arrays; the first frame fixes their names, types and components, and
  // every later frame must give the same (InputError otherwise).
  std::span<const PointArray> arrays = {};
};

class TrajectoryWriter {
 public:
  virtual ~TrajectoryWriter() = default;

  // Appends one frame. Frames come in time order (time non-decreasing). Throws InputError for a
  // frame that does not fit (see above), std::runtime_error when writing fails, and
  // std::logic_error after Close().
  virtual void Write(const ParticleFrame& frame) = 0;

  // Finishes the files (index/sidecar written, handles closed). Idempotent; the destructor calls
  // it too but swallows errors, so call it explicitly to see them.
  virtual void Close() = 0;
};

// How /positions is stored in an HDF5 trajectory: float64, or float32 (a relative rounding of
// at most 2^−24 ≈ 6·10^−8 per coordinate, half the bytes). Frames are given in double either way.
enum class TrajectoryPrecision { kDouble, kSingle };
// "double", "single"; Parse throws InputError for other names.
std::string_view TrajectoryPrecisionName(TrajectoryPrecision precision);
TrajectoryPrecision ParseTrajectoryPrecision(std::string_view name);

// Storage settings of an HDF5 trajectory. Readers need nothing extra: the type and the filters are
// recorded in the file (h5py, ParaView and the XDMF sidecar read every combination).
struct Hdf5TrajectoryOptions {
  // float64 or float32 /positions (and its per-frame views); the other datasets keep their types.
  TrajectoryPrecision precision = TrajectoryPrecision::kDouble;
  // Deflate level 0 … 9 of every dataset, after the byte-shuffle filter; 0 stores raw chunks.
  int compression = 0;

  // Throws InputError "compression must be in 0 … 9 (…), got 12" (the field, the reason, the
  // value), or when compression > 0 and the HDF5 library lacks the deflate filter.
  void Validate() const;
};

// HDF5 trajectory at `path` (e.g. out/trajectory.h5), created (truncated) now, plus an XDMF 3
// sidecar next to it with the extension replaced by .xdmf (out/trajectory.xdmf), written at
// Close(). Format version 2; F frames, N_f particles in frame f, R = max_f N_f rows, dimension k
// (fixed by the first frame; another k throws InputError). Datasets, all chunked and extensible:
//   /time (F) float64, /step (F) int64, /count (F) int64 = N_f,
//   /positions (F×R×k) float64 (float32 with single precision), /ids (F×R) int64,
//   /radii (F×R) float64: frame f in rows
//     0 … N_f−1; rows N_f … R−1 read as NaN (positions, radii) and −1 (ids);
//   /connectivity (R) int64 = 0, 1, …, R−1;
//   /point_data/NAME (F×R, or F×R×3 for a vector) float64 or int64: each extra array of the
//     frames (PointArray), rows past N_f reading as NaN or −1;
//   /xdmf/frame_FFFFFF/{positions, radii, ids, connectivity}: virtual datasets (HDF5 ≥ 1.10)
//     showing frame f's N_f rows, the items the sidecar names (absent when N_f = 0), and
//     /xdmf/frame_FFFFFF/point_data/NAME for each extra array (a node attribute in the sidecar);
// root attributes: format = "moreau-trajectory", format_version = 2, dimension = k, count = R,
// and each of `lists` as an array of strings.
// With a fixed N the arrays are F×N×k, F×N as in format version 1.
// The file is flushed after every frame, so it stays readable up to the last frame written even
// if the run stops without Close().
// With options.precision = kSingle, /positions and its views are float32 (the sidecar declares
// Precision="4"); with options.compression > 0 every dataset is shuffled and deflated.
// Throws InputError if the options are invalid, if the parent directory does not exist, if `path`
// ends in .xdmf, if the file cannot be created, or for a bad or repeated list name.
std::unique_ptr<TrajectoryWriter> MakeHdf5Writer(const std::filesystem::path& path,
                                                 const Hdf5TrajectoryOptions& options = {},
                                                 const std::vector<StringList>& lists = {});

// VTU series in the existing directory `dir`: frame i is written at once to
// DIR/PREFIX_iiiiii.vtu (six digits or more), an UnstructuredGrid of N VTK_VERTEX cells with
// 3-component float64 points (z = 0 in 2D) and point data "radius" (float64), "id" (int64) and
// each extra array of the frame (PointArray), arrays inline as base64 binary with UInt64 headers;
// field data TimeValue, step and each of `lists` (a string array); DIR/PREFIX.pvd lists the
// files with their times (created empty now, completed at Close()). N may change between frames.
// Throws InputError if `dir` is not an existing directory, if `prefix` is empty or contains a
// path separator, if DIR/PREFIX.pvd cannot be created, or for a bad or repeated list name.
std::unique_ptr<TrajectoryWriter> MakeVtuSeriesWriter(const std::filesystem::path& dir,
                                                      const std::string& prefix,
                                                      const std::vector<StringList>& lists = {});

}  // namespace moreau::io
