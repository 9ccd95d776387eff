// The gap-filling windows of a real recording as the optimal-control fill builds them (benchmark
// only; docs/benchmarks.md, "IPOPT on a gap-filling window").
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "mocap/ocp_window.h"
#include "moreau/mocap/gap_fill.h"

namespace moreau::bench {

// A recording's gaps set up for the fill's windows: `base` is `in` with every gap that the fill
// solves set to its prior (FillGaps, gap_fill.h, with method ocp and the optimal control off),
// `windows`
// the fill's windows of those gaps (its grouping and padding), in the fill's order.
struct FillWindows {
  mocap::Recording in;
  mocap::Recording base;
  mocap::MarkerNetwork network;
  std::vector<mocap::internal::OcpWindow> windows;
  int gaps = 0;  // gaps the fill solves
};

// Reads `path` and finds its gaps (FindGaps), with `options` (options.method is not read: ocp).
FillWindows MakeFillWindows(const std::filesystem::path& path,
                            const mocap::GapFillOptions& options);

// "frames a…b, free A, B" in the recording's labels.
std::string Describe(const FillWindows& fill, std::size_t window);

}  // namespace moreau::bench
