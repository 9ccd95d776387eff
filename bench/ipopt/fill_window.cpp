#include "fill_window.h"

#include <fmt/format.h>

#include <algorithm>

#include "moreau/mocap/ocp_fill.h"
#include "moreau/mocap/recording_io.h"

namespace moreau::bench {

FillWindows MakeFillWindows(const std::filesystem::path& path,
                            const mocap::GapFillOptions& options) {
  FillWindows fill;
  fill.in = mocap::ReadRecording(path);
  const std::vector<mocap::Gap> gaps = mocap::FindGaps(fill.in);
  // The priors, exactly as FillGapsOcp sets them into its `base`: with the optimal control off
  // the fill writes each solved gap's prior.
  mocap::GapFillOptions prior = options;
  prior.method = mocap::GapFillMethod::kOcp;
  prior.ocp.optimal_control = false;
  const mocap::FillSummary priors = mocap::FillGaps(fill.in, gaps, prior, &fill.base);
  std::vector<mocap::Gap> solved;
  for (std::size_t i = 0; i < gaps.size(); ++i) {
    if (priors.gaps[i].filled()) solved.push_back(gaps[i]);
  }
  fill.gaps = static_cast<int>(solved.size());
  // The fill's windows: FillGapsOcp with the prior as its only candidate reports each gap's
  // window (grouping and padding are the fill's own).
  mocap::Recording out;
  const mocap::OcpFillSummary summary =
      mocap::FillGapsOcp(fill.in, solved, {{"prior", &fill.base}}, prior.ocp, &out);
  fill.network = summary.network;
  fill.windows.resize(static_cast<std::size_t>(summary.windows));
  for (std::size_t k = 0; k < solved.size(); ++k) {
    const mocap::OcpGapReport& r = summary.gaps[k];
    mocap::internal::OcpWindow& w = fill.windows[static_cast<std::size_t>(r.window)];
    w.first = r.window_first;
    w.last = r.window_last;
    if (std::find(w.free.begin(), w.free.end(), solved[k].marker) == w.free.end()) {
      w.free.push_back(solved[k].marker);
    }
  }
  return fill;
}

std::string Describe(const FillWindows& fill, std::size_t window) {
  const mocap::internal::OcpWindow& w = fill.windows[window];
  std::string labels;
  for (int m : w.free) {
    labels += (labels.empty() ? "" : ", ") + fill.in.labels()[static_cast<std::size_t>(m)];
  }
  return fmt::format("window {}: frames {}…{}, free {}", window, w.first, w.last, labels);
}

}  // namespace moreau::bench
