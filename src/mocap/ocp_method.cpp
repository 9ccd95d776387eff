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
  if (r.status == "prior") return fmt::format("prior: {}", weights);
  if (r.status != "ocp") return fmt::format("prior ({}): {}", weights, r.message);
  return fmt::format(
      "optimal control: window {}…{}, {} free, {} anchors, {} springs, {} steps, {} Newton "
      "iterations, disagreement {:.3g}; prior {}",
      r.window_first, r.window_last, r.free_nodes, r.anchors, r.springs, r.steps,
      r.newton_iterations, r.disagreement, weights);
}

// The candidate `method` for `gap`, made to meet the observed samples that bound the gap: the gap
// widened by one frame on each side (those samples hidden in `work`, a copy of the input that is
// restored before returning) is filled, and the fill's errors at the two bounding frames are
// blended linearly across the gap and removed. A method that does not reproduce the samples
// around a gap (pca) would otherwise jump there.
GapFill BoundedCandidate(Recording& work, const Gap& gap, const FillOptions& options) {
  const std::int64_t a = gap.first - 1, b = gap.last + 1;
  if (a < 0 || b >= work.frames()) return FillGap(work, gap, options);
  const Eigen::Vector3d xa = work.point(a, gap.marker), xb = work.point(b, gap.marker);
  work.ClearPoint(a, gap.marker);
  work.ClearPoint(b, gap.marker);
  GapFill wide = FillGap(work, Gap{gap.marker, a, b}, options);
  work.SetPoint(a, gap.marker, xa);
  work.SetPoint(b, gap.marker, xb);
  if (wide.status != GapStatus::kFilled) return FillGap(work, gap, options);
  const Eigen::Vector3d ea = xa - wide.points.col(0), eb = xb - wide.points.col(b - a);
  GapFill fill{GapStatus::kFilled, std::move(wide.message), Eigen::Matrix3Xd(3, gap.length())};
  for (std::int64_t f = gap.first; f <= gap.last; ++f) {
    const double w = static_cast<double>(f - a) / static_cast<double>(b - a);
    fill.points.col(f - gap.first) = wide.points.col(f - a) + (1.0 - w) * ea + w * eb;
  }
  return fill;
}

}  // namespace

std::vector<GapFill> FillGapsByOcp(const Recording& in, const std::vector<Gap>& gaps,
                                   const FillOptions& options) {
  std::vector<GapFill> fills(gaps.size());
  std::vector<bool> fillable(gaps.size(), false);
  std::vector<Recording> filled;
  filled.reserve(options.ocp.candidates.size());
  std::vector<CandidateFill> candidates;
  Recording work = in;
  for (const std::string& name : options.ocp.candidates) {
    FillOptions baseline = options;
    baseline.method = ParseFillMethod(name);
    Recording& rec = filled.emplace_back(in);
    for (std::size_t i = 0; i < gaps.size(); ++i) {
      GapFill fill = BoundedCandidate(work, gaps[i], baseline);
      if (fill.status == GapStatus::kFilled) {
        for (std::int64_t f = gaps[i].first; f <= gaps[i].last; ++f) {
          rec.SetPoint(f, gaps[i].marker, fill.points.col(f - gaps[i].first));
        }
        fillable[i] = true;
      } else if (!fillable[i] && fills[i].message.empty()) {
        fills[i] = {fill.status,
                    fmt::format("no candidate filled the gap; {}: {}", name, fill.message),
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
    for (std::int64_t f = g.first; f <= g.last; ++f)
      fill.points.col(f - g.first) = out.point(f, g.marker);
  }
  return fills;
}

}  // namespace internal

GapFill FillGapOcp(const Recording& in, const Gap& gap, const FillOptions& options) {
  return internal::FillGapsByOcp(in, {gap}, options).front();
}

}  // namespace moreau::mocap
