#include "mocap/ocp_method.h"

#include <fmt/format.h>

#include <string>
#include <utility>

#include "moreau/mocap/ocp_fill.h"

namespace moreau::mocap {
namespace internal {
namespace {

std::string Describe(const OcpGapReport& r, const std::vector<std::string>& methods) {
  std::string weights;
  for (std::size_t c = 0; c < methods.size(); ++c) {
    weights += fmt::format("{}{} {:.2f}", c == 0 ? "" : ", ", methods[c], r.candidate_weights[c]);
  }
  if (r.status != "ocp") {
    return fmt::format("prior ({}): {}", weights, r.message);
  }
  return fmt::format(
      "optimal control: window {}…{}, {} free, {} anchors, {} springs, {} steps, {} Newton "
      "iterations, disagreement {:.3g}; prior {}",
      r.window_first, r.window_last, r.free_nodes, r.anchors, r.springs, r.steps,
      r.newton_iterations, r.disagreement, weights);
}

}  // namespace

std::vector<GapFill> FillGapsByOcp(const Recording& in, const std::vector<Gap>& gaps,
                                   const FillOptions& options) {
  std::vector<GapFill> fills(gaps.size());
  std::vector<bool> fillable(gaps.size(), false);
  std::vector<Recording> filled;
  filled.reserve(options.ocp.candidates.size());
  std::vector<CandidateFill> candidates;
  for (const std::string& name : options.ocp.candidates) {
    FillOptions baseline = options;
    baseline.method = ParseFillMethod(name);
    Recording& rec = filled.emplace_back(in);
    for (std::size_t i = 0; i < gaps.size(); ++i) {
      GapFill fill = FillGap(in, gaps[i], baseline);
      if (fill.status == GapStatus::kFilled) {
        for (std::int64_t f = gaps[i].first; f <= gaps[i].last; ++f) {
          rec.SetPoint(f, gaps[i].marker, fill.points.col(f - gaps[i].first));
        }
        fillable[i] = true;
      } else if (!fillable[i] && fills[i].message.empty()) {
        fills[i] = {fill.status, fmt::format("no candidate filled the gap; {}: {}", name,
                                             fill.message),
                    {}};
      }
    }
    candidates.push_back({name, &rec});
  }
  std::vector<Gap> solved;
  std::vector<std::size_t> index;
  for (std::size_t i = 0; i < gaps.size(); ++i) {
    if (fillable[i]) {
      solved.push_back(gaps[i]);
      index.push_back(i);
    }
  }
  if (solved.empty()) return fills;
  Recording out;
  const OcpFillSummary summary = FillGapsOcp(in, solved, options.ocp, &out, candidates);
  for (std::size_t k = 0; k < solved.size(); ++k) {
    const Gap& g = solved[k];
    GapFill& fill = fills[index[k]];
    fill = {GapStatus::kFilled, Describe(summary.gaps[k], summary.methods),
            Eigen::Matrix3Xd(3, g.length())};
    for (std::int64_t f = g.first; f <= g.last; ++f) fill.points.col(f - g.first) = out.point(f, g.marker);
  }
  return fills;
}

}  // namespace internal

GapFill FillGapOcp(const Recording& in, const Gap& gap, const FillOptions& options) {
  return internal::FillGapsByOcp(in, {gap}, options).front();
}

}  // namespace moreau::mocap
