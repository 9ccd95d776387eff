#include "moreau/mocap/gap_fill.h"

#include <fmt/format.h>

#include <optional>
#include <string>
#include <utility>

#include "mocap/fill_internal.h"
#include "moreau/common/error.h"
#include "moreau/common/stopwatch.h"

namespace moreau::mocap {
namespace {

// GapFillMethod's first values are FillMethod's, in the same order.
static_assert(static_cast<int>(GapFillMethod::kLinear) == static_cast<int>(FillMethod::kLinear));
static_assert(static_cast<int>(GapFillMethod::kSpline) == static_cast<int>(FillMethod::kSpline));
static_assert(static_cast<int>(GapFillMethod::kPchip) == static_cast<int>(FillMethod::kPchip));
static_assert(static_cast<int>(GapFillMethod::kRigid) == static_cast<int>(FillMethod::kRigid));
static_assert(static_cast<int>(GapFillMethod::kPca) == static_cast<int>(FillMethod::kPca));

constexpr std::string_view kOcpName = "ocp";
constexpr std::string_view kAverageName = "average";

// The baseline method, or none for average and ocp.
std::optional<FillMethod> BaselineMethod(GapFillMethod method) {
  if (method == GapFillMethod::kAverage || method == GapFillMethod::kOcp) return std::nullopt;
  return static_cast<FillMethod>(method);
}

// The options FillGapsOcp gets: average is the ocp layer with the optimal control off.
GapFillOptions LayerOptions(const GapFillOptions& options) {
  GapFillOptions layer = options;
  if (options.method == GapFillMethod::kAverage) layer.ocp.optimal_control = false;
  return layer;
}

// options.baseline with its method set to `method`.
FillOptions BaselineWith(const GapFillOptions& options, FillMethod method) {
  FillOptions baseline = options.baseline;
  baseline.method = method;
  return baseline;
}

// A filled gap's message: how the ocp layer filled it, and the prior's weights.
std::string DescribeOcpGap(const OcpGapReport& r, const std::vector<std::string>& methods) {
  std::string weights;
  for (std::size_t c = 0; c < methods.size(); ++c) {
    weights += fmt::format("{}{} {:.2f}", c == 0 ? "" : ", ", methods[c], r.candidate_weights[c]);
  }
  if (r.outcome == OcpOutcome::kPrior) return fmt::format("prior: {}", weights);
  if (r.outcome != OcpOutcome::kSolved) return fmt::format("prior ({}): {}", weights, r.message);
  return fmt::format(
      "optimal control: window {}…{}, {} free, {} anchors, {} springs, {} steps, {} Newton "
      "iterations, disagreement {:.3g}; prior {}",
      r.window_first, r.window_last, r.free_nodes, r.anchors, r.springs, r.steps,
      r.newton_iterations, r.disagreement, weights);
}

// The candidates of the ocp fill: the baseline fills named by options.ocp.candidates, each made
// to meet the samples around the gaps. fillable[i]: some candidate fills gap i; unfilled[i]:
// the status and message of the first candidate that did not, while none did.
struct OcpCandidates {
  std::vector<Recording> recordings;  // one per candidate
  std::vector<CandidateFill> fills;   // naming `recordings`
  std::vector<bool> fillable;
  std::vector<GapFill> unfilled;
};

OcpCandidates ComputeCandidates(const Recording& in, const std::vector<Gap>& gaps,
                                const GapFillOptions& options) {
  const std::vector<FillMethod>& methods = options.ocp.candidates;
  OcpCandidates out;
  out.recordings.resize(methods.size());
  out.fillable.assign(gaps.size(), false);
  out.unfilled.resize(gaps.size());
  for (std::size_t c = 0; c < methods.size(); ++c) {
    const std::string name(ToString(methods[c]));
    const FillSummary summary =
        FillGapsMeetingEnds(in, gaps, BaselineWith(options, methods[c]), &out.recordings[c]);
    for (std::size_t i = 0; i < gaps.size(); ++i) {
      const GapReport& gap = summary.gaps[i];
      if (gap.filled()) {
        out.fillable[i] = true;
      } else if (!out.fillable[i] && out.unfilled[i].message.empty()) {
        out.unfilled[i] = {
            gap.status, fmt::format("no candidate filled the gap; {}: {}", name, gap.message), {}};
      }
    }
    out.fills.push_back({name, &out.recordings[c]});
  }
  return out;
}

// Why the prior was kept for a gap the optimal-control layer did not solve (GapReport's
// prior_reason), or empty when it solved it.
std::string PriorReason(const OcpGapReport& r) {
  switch (r.outcome) {
    case OcpOutcome::kSolved:
      return {};
    case OcpOutcome::kPrior:
      return "optimal_control_off";
    case OcpOutcome::kFallback:
      break;
  }
  // A window that converged but whose fill was not kept was turned down by the guard.
  return IsSuccess(r.termination) ? "rejected_by_guard" : "optimal_control_failed";
}

// The ocp (or average) fill of every gap in input order; a filled gap's GapFill says what filled
// it (the optimal control, or the prior and why). The gaps some candidate fills go to FillGapsOcp
// together; the others keep the first failing candidate's status.
std::vector<GapFill> FillGapsByOcp(const Recording& in, const std::vector<Gap>& gaps,
                                   const GapFillOptions& requested) {
  const GapFillOptions options = LayerOptions(requested);
  const bool average = requested.method == GapFillMethod::kAverage;
  OcpCandidates candidates = ComputeCandidates(in, gaps, options);
  std::vector<GapFill> fills = std::move(candidates.unfilled);
  std::vector<Gap> solved;
  std::vector<std::size_t> index;
  for (std::size_t i = 0; i < gaps.size(); ++i) {
    if (candidates.fillable[i]) {
      solved.push_back(gaps[i]);
      index.push_back(i);
    }
  }
  if (solved.empty()) return fills;
  Recording out;
  const OcpFillSummary summary = [&] {
    try {
      return FillGapsOcp(in, solved, candidates.fills, options.ocp, &out);
    } catch (const InputError& e) {
      throw e.Under("ocp");  // a setting's key as GapFillOptions names it
    }
  }();
  for (std::size_t k = 0; k < solved.size(); ++k) {
    const Gap& g = solved[k];
    const OcpGapReport& report = summary.gaps[k];
    GapFill& fill = fills[index[k]];
    fill = {GapStatus::kFilled, DescribeOcpGap(report, summary.methods),
            Eigen::Matrix3Xd(3, g.length())};
    for (std::int64_t f = g.first; f <= g.last; ++f) {
      fill.points.col(f - g.first) = out.point(f, g.marker);
    }
    if (average) continue;  // kBaseline: the method itself filled it
    fill.outcome =
        report.outcome == OcpOutcome::kSolved ? GapOutcome::kOptimalControl : GapOutcome::kPrior;
    fill.prior_reason = PriorReason(report);
  }
  return fills;
}

}  // namespace

std::string_view ToString(GapFillMethod method) {
  if (method == GapFillMethod::kAverage) return kAverageName;
  const std::optional<FillMethod> baseline = BaselineMethod(method);
  return baseline ? ToString(*baseline) : kOcpName;
}

GapFillMethod ParseGapFillMethod(std::string_view name) {
  std::string known;
  for (GapFillMethod method : AllGapFillMethods()) {
    if (ToString(method) == name) return method;
    known += (known.empty() ? "" : ", ") + std::string(ToString(method));
  }
  throw InputError(fmt::format("unknown fill method '{}' (expected one of {})", name, known));
}

std::vector<GapFillMethod> AllGapFillMethods() {
  std::vector<GapFillMethod> methods;
  for (FillMethod m : AllFillMethods()) {
    // GapFillMethod lists every FillMethod before kAverage.
    MOREAU_ASSERT(static_cast<int>(m) < static_cast<int>(GapFillMethod::kAverage));
    methods.push_back(static_cast<GapFillMethod>(m));
  }
  methods.push_back(GapFillMethod::kAverage);
  methods.push_back(GapFillMethod::kOcp);
  return methods;
}

std::vector<std::pair<GapFillMethod, std::string_view>> GapFillMethodNameTable() {
  std::vector<std::pair<GapFillMethod, std::string_view>> names;
  for (GapFillMethod m : AllGapFillMethods()) names.emplace_back(m, ToString(m));
  return names;
}

const FieldList<GapFillOptions>& GapFillOptions::Fields() {
  using O = GapFillOptions;
  static const FieldList<O> list = [] {
    FieldList<O> t;
    t.Choice("method", &O::method, GapFillMethodNameTable(), "the fill method")
        .Number(
            "max_gap_seconds", [](auto& o) -> auto& { return o.baseline.max_gap_seconds; },
            Range::NonNegative(), "s", "leave longer gaps missing (too_long); 0: no limit")
        .Mount(
            "interpolation", [](auto& o) -> auto& { return o.baseline.interpolation; },
            InterpolationFillOptions::Fields())
        .Mount(
            "rigid", [](auto& o) -> auto& { return o.baseline.rigid; }, RigidFillOptions::Fields())
        .Mount(
            "pca", [](auto& o) -> auto& { return o.baseline.pca; }, PcaFillOptions::Fields())
        .Mount("ocp", &O::ocp, OcpFillOptions::Fields());
    return t;
  }();
  return list;
}

void GapFillOptions::Validate() const { Fields().Validate(*this); }

nlohmann::json GapFillOptions::ToJson() const {
  nlohmann::json j = baseline.ToJson();
  j["method"] = std::string(ToString(method));
  j["ocp"] = ocp.ToJson();
  return j;
}

FillSummary FillGaps(const Recording& in, const std::vector<Gap>& gaps,
                     const GapFillOptions& options, Recording* out) {
  const Stopwatch total;
  options.Validate();
  FillSummary summary;
  if (const std::optional<FillMethod> baseline = BaselineMethod(options.method)) {
    summary = FillGaps(in, gaps, BaselineWith(options, *baseline), out);
  } else {
    CheckGaps(in, gaps);
    std::vector<GapFill> fills = FillGapsByOcp(in, gaps, options);
    summary = internal::SummarizeFills(
        in, gaps, ToString(options.method), [&](std::size_t i) { return std::move(fills[i]); },
        out);
  }
  summary.settings = LayerOptions(options).ToJson();
  summary.total_seconds = total.Seconds();
  return summary;
}

GapFill FillGap(const Recording& in, const Gap& gap, const GapFillOptions& options) {
  if (const std::optional<FillMethod> baseline = BaselineMethod(options.method)) {
    return FillGap(in, gap, BaselineWith(options, *baseline));
  }
  return std::move(FillGapsByOcp(in, {gap}, options).front());
}

std::vector<GapFill> FillGapList(const Recording& in, const std::vector<Gap>& gaps,
                                 const GapFillOptions& options) {
  if (!BaselineMethod(options.method)) return FillGapsByOcp(in, gaps, options);
  std::vector<GapFill> fills;
  for (const Gap& gap : gaps) fills.push_back(FillGap(in, gap, options));
  return fills;
}

}  // namespace moreau::mocap
