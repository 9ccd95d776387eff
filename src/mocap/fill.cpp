#include "moreau/mocap/fill.h"

#include <fmt/format.h>

#include <array>
#include <cmath>
#include <map>
#include <utility>

#include "mocap/fill_internal.h"
#include "moreau/common/enum_names.h"
#include "moreau/common/error.h"
#include "moreau/common/stop.h"
#include "moreau/common/stopwatch.h"
#include "moreau/common/summary_json.h"

namespace moreau::mocap {

namespace {

using GapFillFunction = GapFill (*)(const Recording&, const Gap&, const FillOptions&);

struct MethodEntry {
  FillMethod method;
  std::string_view name;
  GapFillFunction fill;
};

// The one place that lists the methods: enum, name, function.
constexpr std::array<MethodEntry, 5> kMethods{{
    {FillMethod::kLinear, "linear", &FillGapLinear},
    {FillMethod::kSpline, "spline", &FillGapSpline},
    {FillMethod::kPchip, "pchip", &FillGapPchip},
    {FillMethod::kRigid, "rigid", &FillGapRigid},
    {FillMethod::kPca, "pca", &FillGapPca},
}};

constexpr EnumNames<GapStatus, 7> kStatuses{{
    {GapStatus::kFilled, "filled"},
    {GapStatus::kSkippedEdge, "skipped_edge"},
    {GapStatus::kTooLong, "too_long"},
    {GapStatus::kTooFewSamples, "too_few_samples"},
    {GapStatus::kNoDonors, "no_donors"},
    {GapStatus::kFailed, "failed"},
    {GapStatus::kNeverObserved, "never_observed"},
}};

constexpr EnumNames<GapOutcome, 4> kOutcomes{{
    {GapOutcome::kBaseline, "baseline"},
    {GapOutcome::kOptimalControl, "optimal_control"},
    {GapOutcome::kPrior, "prior"},
    {GapOutcome::kUnfillable, "unfillable"},
}};

const MethodEntry& Entry(FillMethod method) {
  for (const auto& entry : kMethods) {
    if (entry.method == method) return entry;
  }
  MOREAU_ASSERT(false);
}

}  // namespace

std::string_view ToString(FillMethod method) { return Entry(method).name; }

FillMethod ParseFillMethod(std::string_view name) {
  std::string known;
  for (const auto& entry : kMethods) {
    if (entry.name == name) return entry.method;
    known += (known.empty() ? "" : ", ") + std::string(entry.name);
  }
  throw InputError(fmt::format("unknown fill method '{}' (expected one of {})", name, known));
}

std::vector<FillMethod> AllFillMethods() {
  std::vector<FillMethod> methods;
  for (const auto& entry : kMethods) methods.push_back(entry.method);
  return methods;
}

std::string_view ToString(GapStatus status) { return EnumName(kStatuses, status); }

GapStatus ParseGapStatus(std::string_view name) {
  return ParseEnumName(kStatuses, name, "gap status");
}

std::string_view ToString(GapOutcome outcome) { return EnumName(kOutcomes, outcome); }

const FieldList<InterpolationFillOptions>& InterpolationFillOptions::Fields() {
  using O = InterpolationFillOptions;
  static const FieldList<O> list = [] {
    FieldList<O> t;
    t.Integer("samples_per_side", &O::samples_per_side, Range::AtLeast(2), "frames",
              "spline, pchip: observed samples used on each side of the gap");
    return t;
  }();
  return list;
}

const FieldList<RigidFillOptions>& RigidFillOptions::Fields() {
  using O = RigidFillOptions;
  static const FieldList<O> list = [] {
    FieldList<O> t;
    t.Integer("donors", &O::donors, Range::AtLeast(3), "",
              "markers carried rigidly with the gapped one")
        .Integer("min_common_frames", &O::min_common_frames, Range::AtLeast(2), "frames",
                 "frames seen with the gapped marker to judge a donor");
    return t;
  }();
  return list;
}

const FieldList<PcaFillOptions>& PcaFillOptions::Fields() {
  using O = PcaFillOptions;
  static const FieldList<O> list = [] {
    FieldList<O> t;
    t.Number("explained_fraction", &O::explained_fraction, Range::LeftOpen(0, 1), "",
             "keep the fewest components whose singular values reach this fraction")
        .Number("weight_scale_m", &O::weight_scale_m, Range::Positive(), "m",
                "σ of the distance weights exp(−d²/2σ²)")
        .Number("missing_marker_weight", &O::missing_marker_weight, Range::LeftOpen(0, 1), "",
                "weight of the gapped marker's coordinates")
        .Number("distal_threshold", &O::distal_threshold, Range::Positive(), "",
                "leave out incomplete markers farther than this × the mean distance")
        .Integer("min_complete_frames", &O::min_complete_frames, Range::AtLeast(2), "frames",
                 "frames where every used marker is observed")
        .Integer("max_iterations", &O::max_iterations, Range::AtLeast(1), "",
                 "reconstruction iterations")
        .Number("tolerance", &O::tolerance, Range::Positive(), "standard deviations",
                "stop when the largest change is ≤ this");
    return t;
  }();
  return list;
}

std::vector<std::pair<FillMethod, std::string_view>> FillMethodNameTable() {
  std::vector<std::pair<FillMethod, std::string_view>> names;
  for (const auto& entry : kMethods) names.emplace_back(entry.method, entry.name);
  return names;
}

const FieldList<FillOptions>& FillOptions::Fields() {
  using O = FillOptions;
  static const FieldList<O> list = [] {
    FieldList<O> t;
    t.Choice("method", &O::method, FillMethodNameTable(), "the fill method")
        .Number("max_gap_seconds", &O::max_gap_seconds, Range::NonNegative(), "s",
                "leave longer gaps missing (too_long); 0: no limit")
        .Mount("interpolation", &O::interpolation, InterpolationFillOptions::Fields())
        .Mount("rigid", &O::rigid, RigidFillOptions::Fields())
        .Mount("pca", &O::pca, PcaFillOptions::Fields());
    return t;
  }();
  return list;
}

void FillOptions::Validate() const { Fields().Validate(*this); }

nlohmann::json FillOptions::ToJson() const { return Fields().ToJson(*this); }

GapFill FillGap(const Recording& in, const Gap& gap, const FillOptions& options) {
  if (gap.first == 0 && gap.last == in.frames() - 1) {
    return {GapStatus::kNeverObserved, "the marker is missing in every frame", {}};
  }
  const double seconds = static_cast<double>(gap.length()) / in.rate();
  if (options.max_gap_seconds > 0.0 && seconds > options.max_gap_seconds * (1.0 + 1e-12)) {
    return {GapStatus::kTooLong,
            fmt::format("gap of {} frames ({:.4g} s) exceeds max_gap_seconds = {}", gap.length(),
                        seconds, options.max_gap_seconds),
            {}};
  }
  GapFill result = Entry(options.method).fill(in, gap, options);
  if (result.status == GapStatus::kFilled) {
    MOREAU_ASSERT(result.points.cols() == gap.length());
    if (!result.points.allFinite()) {
      return {GapStatus::kFailed, "the method produced a non-finite position", {}};
    }
  } else {
    result.points.resize(3, 0);
  }
  return result;
}

GapOutcomeCounts GapOutcomeCounts::Of(const std::vector<GapReport>& gaps) {
  GapOutcomeCounts c;
  for (const GapReport& gap : gaps) {
    ++c.gaps;
    switch (gap.outcome) {
      case GapOutcome::kBaseline:
        ++c.baseline;
        break;
      case GapOutcome::kOptimalControl:
        ++c.optimal_control;
        break;
      case GapOutcome::kPrior:
        ++c.prior;
        ++c.prior_by_reason[gap.prior_reason];
        break;
      case GapOutcome::kUnfillable:
        ++c.unfillable;
        ++c.unfillable_by_status[std::string(ToString(gap.status))];
        break;
    }
  }
  return c;
}

nlohmann::json GapOutcomeCounts::ToJson() const {
  return {{"gaps", gaps},
          {"optimal_control", optimal_control},
          {"prior", prior},
          {"baseline", baseline},
          {"unfillable", unfillable},
          {"prior_by_reason", prior_by_reason},
          {"unfillable_by_status", unfillable_by_status}};
}

namespace {

// " (a 2, b 1)" from {a: 2, b: 1}.
std::string CountsInBrackets(const std::map<std::string, std::int64_t>& counts) {
  std::string text;
  for (const auto& [name, count] : counts) {
    text += fmt::format("{}{} {}", text.empty() ? " (" : ", ", name, count);
  }
  return text.empty() ? text : text + ")";
}

}  // namespace

std::string GapOutcomeCounts::Describe(std::string_view method) const {
  std::string text = fmt::format("{} gaps", gaps);
  auto add = [&text, first = true](std::int64_t count, const std::string& what) mutable {
    if (count == 0) return;
    text += fmt::format("{}{} {}", first ? ": " : ", ", count, what);
    first = false;
  };
  add(optimal_control, "solved by the optimal control");
  add(prior, "kept the prior" + CountsInBrackets(prior_by_reason));
  add(baseline, fmt::format("filled by {}", method));
  add(unfillable, "unfillable" + CountsInBrackets(unfillable_by_status));
  return text;
}

nlohmann::json FillSummary::ToJson() const {
  nlohmann::json j = SummaryJson(termination, message, total_seconds);
  j["gaps_filled"] = gaps_filled;
  j["gaps_unfilled"] = static_cast<std::int64_t>(gaps.size()) - gaps_filled;
  j["samples_filled"] = samples_filled;
  j["outcomes"] = GapOutcomeCounts::Of(gaps).ToJson();
  nlohmann::json rows = nlohmann::json::array();
  for (const GapReport& gap : gaps) {
    rows.push_back({{"marker", gap.marker},
                    {"label", gap.label},
                    {"first", gap.first},
                    {"last", gap.last},
                    {"frames", gap.last - gap.first + 1},
                    {"method", method},
                    {"status", std::string(ToString(gap.status))},
                    {"outcome", std::string(ToString(gap.outcome))},
                    {"prior_reason", gap.prior_reason.empty() ? nlohmann::json()
                                                              : nlohmann::json(gap.prior_reason)},
                    {"message", gap.message},
                    {"seconds", gap.seconds}});
  }
  j["gaps"] = std::move(rows);
  j["settings"] = settings;
  return j;
}

namespace internal {

FillSummary SummarizeFills(const Recording& in, const std::vector<Gap>& gaps,
                           std::string_view method,
                           const std::function<GapFill(std::size_t)>& fill_gap, Recording* out) {
  MOREAU_ASSERT(out != nullptr);
  FillSummary summary;
  summary.method = method;
  Recording result = in;
  for (std::size_t i = 0; i < gaps.size(); ++i) {
    const Gap& gap = gaps[i];
    const Stopwatch watch;
    GapFill fill = fill_gap(i);
    GapReport report;
    report.marker = gap.marker;
    report.label = in.labels()[static_cast<std::size_t>(gap.marker)];
    report.first = gap.first;
    report.last = gap.last;
    report.status = fill.status;
    report.message = std::move(fill.message);
    report.outcome = fill.status == GapStatus::kFilled ? fill.outcome : GapOutcome::kUnfillable;
    report.prior_reason = std::move(fill.prior_reason);
    if (fill.status == GapStatus::kFilled) {
      for (std::int64_t f = gap.first; f <= gap.last; ++f) {
        result.SetPoint(f, gap.marker, fill.points.col(f - gap.first));
      }
      ++summary.gaps_filled;
      summary.samples_filled += gap.length();
    }
    report.seconds = watch.Seconds();
    summary.gaps.push_back(std::move(report));
  }
  summary.message = GapOutcomeCounts::Of(summary.gaps).Describe(method);
  *out = std::move(result);
  return summary;
}

}  // namespace internal

namespace {

// FillGaps with fill_gap(gap) per gap.
template <typename FillOneGap>
FillSummary FillEachGap(const Recording& in, const std::vector<Gap>& gaps,
                        const FillOptions& options, FillOneGap fill_gap, Recording* out) {
  const Stopwatch total;
  options.Validate();
  CheckGaps(in, gaps);
  FillSummary summary = internal::SummarizeFills(
      in, gaps, ToString(options.method),
      [&](std::size_t i) {
        if (StopRequested()) {
          throw Interrupted(
              fmt::format("stopped on request before gap {} of {}", i + 1, gaps.size()));
        }
        return fill_gap(gaps[i]);
      },
      out);
  summary.settings = options.ToJson();
  summary.total_seconds = total.Seconds();
  return summary;
}

// The fill of `gap` made to meet the observed samples that bound it (FillGapsMeetingEnds): the
// samples at first − 1 and last + 1 (those inside the recording) are hidden in `work` while the
// widened gap is filled, then restored. The fill's errors at those frames are removed: blended
// linearly across a gap with both, the one error everywhere in a gap at the recording's start or
// end.
GapFill FillGapMeetingEnds(Recording& work, const Gap& gap, const FillOptions& options) {
  const bool left = gap.first > 0, right = gap.last + 1 < work.frames();
  if (!left && !right) return FillGap(work, gap, options);
  const std::int64_t a = left ? gap.first - 1 : gap.first;
  const std::int64_t b = right ? gap.last + 1 : gap.last;
  const Eigen::Vector3d xa = work.point(a, gap.marker), xb = work.point(b, gap.marker);
  if (left) work.ClearPoint(a, gap.marker);
  if (right) work.ClearPoint(b, gap.marker);
  GapFill wide = FillGap(work, Gap{gap.marker, a, b}, options);
  if (left) work.SetPoint(a, gap.marker, xa);
  if (right) work.SetPoint(b, gap.marker, xb);
  if (wide.status != GapStatus::kFilled) return FillGap(work, gap, options);
  const Eigen::Vector3d ea = xa - wide.points.col(0), eb = xb - wide.points.col(b - a);
  GapFill fill{GapStatus::kFilled, std::move(wide.message), Eigen::Matrix3Xd(3, gap.length())};
  for (std::int64_t f = gap.first; f <= gap.last; ++f) {
    const double w = static_cast<double>(f - a) / static_cast<double>(b - a);
    const Eigen::Vector3d error = !left    ? eb
                                  : !right ? ea
                                           : Eigen::Vector3d((1.0 - w) * ea + w * eb);
    fill.points.col(f - gap.first) = wide.points.col(f - a) + error;
  }
  return fill;
}

}  // namespace

FillSummary FillGaps(const Recording& in, const std::vector<Gap>& gaps, const FillOptions& options,
                     Recording* out) {
  return FillEachGap(
      in, gaps, options, [&](const Gap& gap) { return FillGap(in, gap, options); }, out);
}

FillSummary FillGapsMeetingEnds(const Recording& in, const std::vector<Gap>& gaps,
                                const FillOptions& options, Recording* out) {
  Recording work = in;  // FillGapMeetingEnds hides samples in it, then restores them
  return FillEachGap(
      in, gaps, options, [&](const Gap& gap) { return FillGapMeetingEnds(work, gap, options); },
      out);
}

}  // namespace moreau::mocap
