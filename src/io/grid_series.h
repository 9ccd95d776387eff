// What the grid writers share (internal): the checks of the grid and of each frame, the record
// of the frames written, and the XDMF sidecar of the HDF5 grid file (layout in docs/io.md).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "moreau/io/grid_writer.h"

namespace moreau::io::internal {

// Throws InputError "FILE: grid KEY: REASON" unless grid.Validate() passes.
void ValidateGrid(const GridSpec& grid, const std::filesystem::path& file);

// The frames a grid writer has written, and the checks of the next one against them.
struct GridSeries {
  std::vector<std::string> names;  // the fields, fixed by the first frame
  std::vector<double> times;       // one per frame written

  // Throws InputError naming `file` and the frame's step unless the frame fits: a finite time not
  // before the last one, at least one field, good names (GridArray) each once, the first frame's
  // names in its order (after the first frame), `voxels` values per field.
  void Check(const GridFrame& frame, std::int64_t voxels, const std::filesystem::path& file) const;
  // Records a frame that was written (the first one's names too).
  void Add(const GridFrame& frame);
  // The names of the frame's fields, in order.
  static std::vector<std::string> NamesOf(const GridFrame& frame);
};

// The XDMF 3 text of a temporal collection of one Uniform 3DCoRectMesh grid per frame (one layer
// of voxels over z ∈ [−h/2, h/2] in 2D) with each field a cell attribute: a plain HDF DataItem
// naming the view /xdmf/frame_FFFFFF/NAME in `h5_name` (the HDF5 file's name relative to the
// sidecar).
std::string GridXdmfText(const std::string& h5_name, const GridSpec& grid,
                         const GridSeries& series);

}  // namespace moreau::io::internal
