// The XDMF sidecar of an HDF5 trajectory (internal; layout in docs/io.md).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "io/io_util.h"

namespace moreau::io::internal {

// One frame as the sidecar lists it.
struct XdmfFrame {
  double time = 0.0;       // simulated time t
  std::int64_t count = 0;  // N of the frame
};

// The group of frame `index` in the HDF5 file: "/xdmf/frame_000012" (six digits or more).
std::string XdmfFrameGroup(std::size_t index);

// The XDMF text of a temporal collection of one Uniform grid per frame, dimension k ∈ {2, 3}:
// Polyvertex topology with explicit connectivity, XY or XYZ geometry, node attributes radius and
// id, each a plain HDF DataItem naming a dataset of the frame's group in `h5_name` (the HDF5
// file's name relative to the sidecar). No HyperSlab items: ParaView 5.11's XDMF 3 readers crash
// on them, while plain items open in the XDMF 2 and both XDMF 3 readers. Frames with N = 0 are
// left out (the XDMF 2 reader crashes on every form of empty grid tried); the grid of frame f
// keeps the name frame_FFFFFF.
// `position_bytes` (8 or 4) is the Precision of the positions' items. Each of `arrays` is one
// more node attribute (Scalar, or Vector of 3 components) on the frame group's point_data/NAME.
std::string XdmfSidecarText(const std::string& h5_name, int dimension, int position_bytes,
                            const std::vector<XdmfFrame>& frames,
                            const std::vector<ArraySpec>& arrays = {});

}  // namespace moreau::io::internal
