// Writers of fields on a uniform grid of cubic voxels (substrate concentrations over the
// simulation box): an HDF5 file with an XDMF sidecar, or a series of VTK image files (.vti) with a
// PVD index. Both open in ParaView beside the particle trajectory (trajectory.h) of the same run;
// docs/io.md describes the layouts.
//
// The grid is given as plain numbers: voxel (i, j, l) covers [origin + h (i, j, l),
// origin + h (i + 1, j + 1, l + 1)), and the values of a field are voxel_count numbers in the
// order i + n_x (j + n_y l), x fastest. In 2D there is one layer of voxels (n_z = 1).
//
// A writer is created for one run, receives frames in time order through Write() and finishes its
// files in Close(). The library never prints: every failure is an exception whose one-line message
// names the file.
//
//   InputError          a bad grid (dimension not 2 or 3, a non-finite origin, a spacing that is
//                       not finite and positive, fewer than one voxel along an axis, n_z ≠ 1 in
//                       2D), a bad output path, or a frame that does not fit the run (bad or
//                       repeated names, names other than the first frame's, a value count other
//                       than voxel_count, a non-finite time, time going backwards)
//   std::runtime_error  a write that fails part-way (disk full, HDF5 error)
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <string_view>

namespace moreau::io {

// The grid the fields live on, fixed for a writer's run.
struct GridSpec {
  int dimension = 2;                      // k ∈ {2, 3}
  std::array<double, 3> origin{0, 0, 0};  // the lower corner (x, y, z); z unused in 2D
  double spacing = 1.0;                   // h > 0, the voxels' edge (length)
  std::array<int, 3> cells{1, 1, 1};      // (n_x, n_y, n_z), each ≥ 1; n_z = 1 in 2D
  std::int64_t voxel_count() const;       // n_x n_y n_z
  // Throws InputError(key, reason), e.g. "spacing: must be finite and > 0, got nan".
  void Validate() const;
};

// One field of a frame: its name and its voxel_count values (index order above). The name is
// not empty, not "." or "..", and has no '/', ':', '\\', whitespace or control character (it
// names an HDF5 dataset and an XML attribute).
struct GridArray {
  std::string_view name;
  std::span<const double> values;
};

// One frame: the fields at one time. The writer copies what it needs during Write().
struct GridFrame {
  std::int64_t step = 0;  // time-step index of the frame
  double time = 0.0;      // simulated time t
  // The fields; the first frame fixes their names and order, every later frame gives the same.
  std::span<const GridArray> arrays = {};
};

class GridWriter {
 public:
  virtual ~GridWriter() = default;

  // Appends one frame. Frames come in time order (time non-decreasing). Throws InputError for a
  // frame that does not fit (see above; nothing of that frame is written), std::runtime_error
  // when writing fails, and std::logic_error after Close().
  virtual void Write(const GridFrame& frame) = 0;

  // Finishes the files (index/sidecar written, handles closed). Idempotent; the destructor calls
  // it too but swallows errors, so call it explicitly to see them.
  virtual void Close() = 0;
};

// HDF5 file at `path` (e.g. out/fields.h5), created (truncated) now, plus an XDMF 3 sidecar next
// to it with the extension replaced by .xdmf (out/fields.xdmf), written at Close(). Format
// version 1; F frames, shape S = (n_y, n_x) in 2D, (n_z, n_y, n_x) in 3D (C order: x fastest):
//   /time (F) float64, /step (F) int64;
//   /fields/NAME (F×S) float64: frame f of field NAME in [f], chunked, extensible along frames;
//   /xdmf/frame_FFFFFF/NAME (n_z×n_y×n_x, n_z = 1 in 2D): virtual datasets showing frame f of each
//     field (for the sidecar);
// root attributes: format = "moreau-fields", format_version = 1, dimension = k,
// origin (k float64), spacing (float64), cells (k int64, x first).
// The sidecar is a temporal collection of 3DCoRectMesh grids with the fields as cell data; in 2D
// the mesh has one layer of voxels spanning z ∈ [−h/2, h/2] (centred on the particles' plane
// z = 0), the one form that all three of ParaView's XDMF readers place correctly.
// The file is flushed after every frame. Values are stored bit for bit; the same frames give the
// same bytes.
// Throws InputError for a bad grid, if the parent directory does not exist, if `path` ends in
// .xdmf, or if the file cannot be created.
std::unique_ptr<GridWriter> MakeHdf5GridWriter(const std::filesystem::path& path,
                                               const GridSpec& grid);

// VTK image series in the existing directory `dir`: frame i is written at once to
// DIR/PREFIX_iiiiii.vti (six digits or more), an ImageData (origin, spacing, the whole extent
// 0 … n per axis; in 2D a flat image at z = 0, extent 0 … 0 in z) with each field as Float64 cell
// data (inline base64 binary, UInt64 headers) and field data TimeValue and step;
// DIR/PREFIX.pvd lists the files with their times (created empty now, completed at Close()).
// Throws InputError for a bad grid, if `dir` is not an existing directory, if `prefix` is empty or
// contains a path separator, or if DIR/PREFIX.pvd cannot be created.
std::unique_ptr<GridWriter> MakeVtiSeriesWriter(const std::filesystem::path& dir,
                                                const std::string& prefix, const GridSpec& grid);

}  // namespace moreau::io
