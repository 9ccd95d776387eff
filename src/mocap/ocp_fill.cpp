#include "moreau/mocap/ocp_fill.h"

#include <fmt/format.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <numeric>

#include "mocap/ocp_prior.h"
#include "mocap/ocp_window.h"
#include "moreau/common/enum_names.h"
#include "moreau/common/error.h"
#include "moreau/common/stopwatch.h"
#include "moreau/common/summary_json.h"

namespace moreau::mocap {
namespace {

using internal::GapTrack;

constexpr EnumNames<OcpOutcome, 3> kOcpOutcomes{{
    {OcpOutcome::kSolved, "ocp"},
    {OcpOutcome::kPrior, "prior"},
    {OcpOutcome::kFallback, "fallback"},
}};

// Beyond CheckGaps: the network must carry every gap's marker.
void CheckPartners(const Recording& in, const std::vector<Gap>& gaps, const MarkerNetwork& net) {
  for (std::size_t i = 0; i < gaps.size(); ++i) {
    const Gap& g = gaps[i];
    if (net.springs_of[static_cast<std::size_t>(g.marker)].empty()) {
      throw InputError(
          fmt::format("gaps[{}]: marker '{}' has no partners: no marker is seen with it in "
                      "network.min_common_frames frames, so the network cannot carry it",
                      i, in.labels()[static_cast<std::size_t>(g.marker)]));
    }
  }
}

// Per gap: the tracks of the candidates that fill it (finite at every gap frame) and their
// indices in `candidates`.
struct GapCandidates {
  std::vector<GapTrack> tracks;
  std::vector<std::size_t> index;
};

std::vector<GapCandidates> CandidateTracks(const Recording& in, const std::vector<Gap>& gaps,
                                           const std::vector<CandidateFill>& candidates) {
  std::vector<GapCandidates> out(gaps.size());
  for (std::size_t i = 0; i < gaps.size(); ++i) {
    const Gap& g = gaps[i];
    for (std::size_t c = 0; c < candidates.size(); ++c) {
      GapTrack t(g.length(), 3);
      bool finite = true;
      for (std::int64_t f = g.first; f <= g.last && finite; ++f) {
        const auto p = candidates[c].recording->point(f, g.marker);
        finite = p.allFinite();
        t.row(f - g.first) = p.transpose();
      }
      if (!finite) continue;
      out[i].tracks.push_back(std::move(t));
      out[i].index.push_back(c);
    }
    if (out[i].tracks.empty()) {
      throw InputError(fmt::format("gaps[{}]: no candidate fills marker '{}' at frames {}..{}", i,
                                   in.labels()[static_cast<std::size_t>(g.marker)], g.first,
                                   g.last));
    }
  }
  return out;
}

// Groups of gaps solved together: padded windows overlapping in time and the same marker or a
// spring between the markers.
std::vector<std::vector<std::size_t>> GroupGaps(const std::vector<Gap>& gaps,
                                                const MarkerNetwork& net, std::int64_t padding) {
  std::vector<std::size_t> parent(gaps.size());
  std::iota(parent.begin(), parent.end(), 0);
  auto root = [&](std::size_t i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  };
  auto joined = [&](int a, int b) {
    if (a == b) return true;
    for (int s : net.springs_of[static_cast<std::size_t>(a)]) {
      if (net.Partner(s, a) == b) return true;
    }
    return false;
  };
  for (std::size_t i = 0; i < gaps.size(); ++i) {
    for (std::size_t j = i + 1; j < gaps.size(); ++j) {
      const bool overlap = gaps[i].first - padding <= gaps[j].last + padding &&
                           gaps[j].first - padding <= gaps[i].last + padding;
      if (overlap && joined(gaps[i].marker, gaps[j].marker)) parent[root(i)] = root(j);
    }
  }
  std::vector<std::vector<std::size_t>> groups;
  std::vector<long> group_of(gaps.size(), -1);
  for (std::size_t i = 0; i < gaps.size(); ++i) {
    const std::size_t r = root(i);
    if (group_of[r] < 0) {
      group_of[r] = static_cast<long>(groups.size());
      groups.emplace_back();
    }
    groups[static_cast<std::size_t>(group_of[r])].push_back(i);
  }
  return groups;
}

}  // namespace

std::string_view ToString(OcpOutcome outcome) { return EnumName(kOcpOutcomes, outcome); }

OcpOutcome ParseOcpOutcome(std::string_view name) {
  return ParseEnumName(kOcpOutcomes, name, "ocp outcome");
}

const FieldList<OcpFillOptions>& OcpFillOptions::Fields() {
  using O = OcpFillOptions;
  static const FieldList<O> list = [] {
    FieldList<O> t;
    t.Mount("network", &O::network, MarkerNetworkOptions::Fields())
        .Number("padding_seconds", &O::padding_seconds, Range::NonNegative(), "s",
                "observed frames tracked on each side of a gap")
        .Integer("min_padding_frames", &O::min_padding_frames, Range::AtLeast(1), "frames",
                 "at least this many padding frames")
        .Integer("anchor_springs", &O::anchor_springs, Range::NonNegative(), "",
                 "per free node, springs to anchors: the most rigid ones (0: all)")
        .Number("observed_weight", &O::observed_weight, Range::Positive(), "per frame",
                "μ_x w on observed samples")
        .Number("prior_weight", &O::prior_weight, Range::NonNegative(), "per frame",
                "w on the prior inside a gap (0: no prior)")
        .Number("gamma", &O::gamma, Range::Positive(), "per frame",
                "target γ of the regularised Hamiltonian")
        .Number("gamma_start", &O::gamma_start, Range::Positive(), "per frame",
                "first solve at this γ (≥ gamma), then continuation")
        .Number("max_step_frames", &O::max_step_frames, Range::Positive(), "frames",
                "time step Δt ≤ this, and √k Δt ≤ 0.5, c Δt ≤ 1 for the fastest rates")
        .Number("stiffness_start", &O::stiffness_start, Range::LeftOpen(0, 1), "",
                "retry: continuation in κ, ξ from this scale")
        .Number("retry_gamma_start", &O::retry_gamma_start, Range::Positive(), "per frame",
                "retry: continuation in γ from here (≥ gamma_start)")
        .Integer("retry_anchor_springs", &O::retry_anchor_springs, Range::NonNegative(), "",
                 "last attempt: only this many springs to anchors per free marker (0: none)")
        .Number("guard_ratio", &O::guard_ratio, Range::AtLeast(1), "",
                "keep a solved fill only if its disagreement ≤ guard_ratio E_prior + 1")
        .Choices("candidates", &O::candidates, FillMethodNameTable(), 1,
                 "baseline fills averaged into the prior")
        .Number("weight_exponent", &O::weight_exponent, Range::NonNegative(), "",
                "p of the candidate weights 1 / (E_c + 10⁻³)^p (0: plain average)")
        .Flag("prior_bounds", &O::prior_bounds,
              "rest-length bounds centred on the prior (false: the recording's)")
        .Flag("optimal_control", &O::optimal_control,
              "solve the optimal control (false: the prior alone, much faster)")
        .Mount("newton", &O::newton, control::NewtonOptions::Fields())
        .Rule(
            "gamma_start",
            [](const O& o) { return o.gamma_start >= o.gamma ? std::string() : "must be ≥ gamma"; })
        .Rule("retry_gamma_start", [](const O& o) {
          return o.retry_gamma_start >= o.gamma_start ? std::string() : "must be ≥ gamma_start";
        });
    return t;
  }();
  return list;
}

void OcpFillOptions::Validate() const { Fields().Validate(*this); }

nlohmann::json OcpFillOptions::ToJson() const {
  nlohmann::json names = nlohmann::json::array();
  for (FillMethod m : candidates) names.push_back(std::string(ToString(m)));
  return {{"network", network.ToJson()},
          {"padding_seconds", padding_seconds},
          {"min_padding_frames", min_padding_frames},
          {"anchor_springs", anchor_springs},
          {"observed_weight", observed_weight},
          {"prior_weight", prior_weight},
          {"gamma", gamma},
          {"gamma_start", gamma_start},
          {"max_step_frames", max_step_frames},
          {"stiffness_start", stiffness_start},
          {"retry_gamma_start", retry_gamma_start},
          {"retry_anchor_springs", retry_anchor_springs},
          {"guard_ratio", guard_ratio},
          {"candidates", names},
          {"weight_exponent", weight_exponent},
          {"prior_bounds", prior_bounds},
          {"optimal_control", optimal_control},
          {"newton",
           {{"max_iterations", newton.max_iterations},
            {"residual_tolerance", newton.residual_tolerance}}}};
}

nlohmann::json OcpGapReport::ToJson() const {
  return {{"marker", label},
          {"first", first},
          {"last", last},
          {"window", window},
          {"window_first", window_first},
          {"window_last", window_last},
          {"free_nodes", free_nodes},
          {"anchors", anchors},
          {"springs", springs},
          {"steps", steps},
          {"newton_iterations", newton_iterations},
          {"residual", residual},
          {"disagreement", disagreement},
          {"seconds", seconds},
          {"termination", std::string(ToString(termination))},
          {"status", std::string(ToString(outcome))},
          {"fallback_method",
           outcome == OcpOutcome::kFallback ? std::string(ToString(OcpOutcome::kPrior)) : ""},
          {"message", message},
          {"candidate_weights", candidate_weights}};
}

nlohmann::json OcpFillSummary::ToJson(const Recording& recording) const {
  nlohmann::json j = SummaryJson(termination, message, total_seconds);
  j["windows"] = windows;
  j["fallbacks"] = fallbacks;
  j["network_seconds"] = network_seconds;
  j["prior_seconds"] = prior_seconds;
  j["solve_seconds"] = solve_seconds;
  j["candidates"] = methods;
  j["network"] = network.ToJson(recording);
  nlohmann::json list = nlohmann::json::array();
  for (const OcpGapReport& g : gaps) list.push_back(g.ToJson());
  j["gaps"] = list;
  j["settings"] = settings.ToJson();
  return j;
}

namespace {

// The prior of one gap: candidates averaged with weights 1 / (E_c + ε)^p, E_c the candidate's
// distance disagreement (Tits et al. 2018), and the prior's own disagreement.
struct GapPrior {
  GapTrack track;
  std::vector<double> weights;  // per candidate of the gap
  double disagreement = 0.0;    // E of the prior
};

GapPrior MakePrior(const Recording& in, const MarkerNetwork& net, const Gap& gap,
                   const GapCandidates& candidates, std::size_t count, double exponent) {
  GapPrior prior;
  prior.weights.assign(count, 0.0);
  std::vector<double> w;
  for (const GapTrack& t : candidates.tracks) {
    w.push_back(std::pow(internal::DistanceDisagreement(in, net, gap, t) + 1e-3, -exponent));
  }
  const double total = std::accumulate(w.begin(), w.end(), 0.0);
  prior.track = GapTrack::Zero(gap.length(), 3);
  for (std::size_t c = 0; c < w.size(); ++c) {
    prior.weights[candidates.index[c]] = w[c] / total;
    prior.track += (w[c] / total) * candidates.tracks[c];
  }
  prior.disagreement = internal::DistanceDisagreement(in, net, gap, prior.track);
  return prior;
}

void SetTrack(Recording& rec, const Gap& gap, const GapTrack& track) {
  for (std::int64_t f = gap.first; f <= gap.last; ++f) {
    rec.SetPoint(f, gap.marker, track.row(f - gap.first).transpose());
  }
}

void CheckCandidates(const Recording& in, const std::vector<CandidateFill>& candidates) {
  if (candidates.empty()) throw InputError("candidates: at least one candidate fill is needed");
  for (std::size_t c = 0; c < candidates.size(); ++c) {
    const Recording* r = candidates[c].recording;
    if (r == nullptr || r->markers() != in.markers() || r->frames() != in.frames()) {
      throw InputError(
          fmt::format("candidates[{}] ('{}'): must be a recording of {} markers and "
                      "{} frames",
                      c, candidates[c].method, in.markers(), in.frames()));
    }
  }
}

std::int64_t PaddingFrames(const Recording& in, const OcpFillOptions& options) {
  const auto padding = std::max<std::int64_t>(options.min_padding_frames,
                                              std::llround(options.padding_seconds * in.rate()));
  if (padding >= in.frames()) {
    throw InputError("padding_seconds",
                     fmt::format("the window padding of {} frames is not shorter than the "
                                 "recording ({} frames)",
                                 padding, in.frames()));
  }
  return padding;
}

internal::OcpWindow MakeWindow(const std::vector<Gap>& gaps, const std::vector<std::size_t>& group,
                               std::int64_t padding, std::int64_t frames) {
  internal::OcpWindow win;
  win.first = frames;
  for (std::size_t i : group) {
    win.first = std::min(win.first, std::max<std::int64_t>(gaps[i].first - padding, 0));
    win.last = std::max(win.last, std::min(gaps[i].last + padding, frames - 1));
    if (std::find(win.free.begin(), win.free.end(), gaps[i].marker) == win.free.end()) {
      win.free.push_back(gaps[i].marker);
    }
  }
  return win;
}

// Everything a gap's report and its fill need from its window.
struct WindowOutcome {
  std::size_t index = 0;
  const internal::OcpWindow* window = nullptr;
  const internal::OcpWindowResult* result = nullptr;
  double seconds = 0.0;
};

void ReportWindow(const Recording& in, const Gap& g, const WindowOutcome& w, OcpGapReport& rep) {
  const internal::OcpWindowResult& r = *w.result;
  rep.marker = g.marker;
  rep.label = in.labels()[static_cast<std::size_t>(g.marker)];
  rep.first = g.first;
  rep.last = g.last;
  rep.window = static_cast<int>(w.index);
  rep.window_first = w.window->first;
  rep.window_last = w.window->last;
  rep.free_nodes = static_cast<int>(w.window->free.size());
  rep.anchors = r.anchors;
  rep.springs = r.springs;
  rep.steps = r.steps;
  rep.newton_iterations = r.newton_iterations;
  rep.residual = r.residual;
  rep.seconds = w.seconds;
  rep.termination = r.termination;
  rep.message = r.message;
}

// Writes the solved fill of gap g, or the prior when the window failed or the solved fill
// disagrees with the distance distributions much more than the prior (the guard, after Tits et
// al.). Returns true when the solved fill was used.
bool WriteGap(const Recording& in, const MarkerNetwork& net, const Gap& g, const WindowOutcome& w,
              const GapPrior& prior, const OcpFillOptions& options, OcpGapReport& rep,
              Recording& out) {
  rep.candidate_weights = prior.weights;
  rep.disagreement = prior.disagreement;
  if (!options.optimal_control) {
    rep.outcome = OcpOutcome::kPrior;
    SetTrack(out, g, prior.track);
    return true;
  }
  bool use = IsSuccess(w.result->termination);
  if (use) {
    const auto& free = w.window->free;
    const auto j = std::find(free.begin(), free.end(), g.marker) - free.begin();
    const GapTrack track =
        w.result->positions.block(g.first - w.window->first, 3 * j, g.length(), 3);
    rep.disagreement = internal::DistanceDisagreement(in, net, g, track);
    use = rep.disagreement <= options.guard_ratio * prior.disagreement + 1.0;
    if (use) {
      SetTrack(out, g, track);
    } else {
      rep.message = fmt::format(
          "the optimal-control fill disagrees with the distance distributions ({:.3g}) more "
          "than the prior ({:.3g})",
          rep.disagreement, prior.disagreement);
    }
  }
  rep.outcome = use ? OcpOutcome::kSolved : OcpOutcome::kFallback;
  if (!use) SetTrack(out, g, prior.track);
  return use;
}

}  // namespace

OcpFillSummary FillGapsOcp(const Recording& in, const std::vector<Gap>& gaps,
                           const std::vector<CandidateFill>& candidates,
                           const OcpFillOptions& options, Recording* out) {
  const Stopwatch total;
  options.Validate();
  MOREAU_ASSERT(out != nullptr);
  CheckGaps(in, gaps);
  CheckCandidates(in, candidates);
  const std::int64_t padding = PaddingFrames(in, options);
  OcpFillSummary summary;
  summary.settings = options;
  Stopwatch phase;
  summary.network = BuildMarkerNetwork(in, options.network);
  const MarkerNetwork& net = summary.network;
  summary.network_seconds = phase.Seconds();
  CheckPartners(in, gaps, net);
  for (const auto& c : candidates) summary.methods.push_back(c.method);

  phase.Restart();
  const auto tracks = CandidateTracks(in, gaps, candidates);
  std::vector<GapPrior> priors;
  Recording base = in;
  for (std::size_t i = 0; i < gaps.size(); ++i) {
    priors.push_back(
        MakePrior(in, net, gaps[i], tracks[i], candidates.size(), options.weight_exponent));
    SetTrack(base, gaps[i], priors.back().track);
  }
  summary.prior_seconds = phase.Seconds();

  phase.Restart();
  const auto groups = GroupGaps(gaps, net, padding);
  summary.windows = static_cast<int>(groups.size());
  summary.gaps.resize(gaps.size());
  *out = in;
  std::vector<internal::OcpWindowResult> results(groups.size());
  std::vector<internal::OcpWindow> windows(groups.size());
  std::vector<double> seconds(groups.size());
  // Windows in parallel only at the top level (inside EvaluateFillMethods' trials they run on
  // the trial's thread); each writes its own slot, so the result never depends on the threads.
#pragma omp parallel for schedule(dynamic) if (omp_get_level() == 0)
  for (std::size_t w = 0; w < groups.size(); ++w) {
    const Stopwatch clock;
    windows[w] = MakeWindow(gaps, groups[w], padding, in.frames());
    if (options.optimal_control) {
      results[w] = internal::SolveOcpWindow(in, base, net, windows[w], options);
    } else {
      results[w].message = "ocp.optimal_control is false: the prior is used";
    }
    seconds[w] = clock.Seconds();
  }
  for (std::size_t w = 0; w < groups.size(); ++w) {
    const WindowOutcome outcome{w, &windows[w], &results[w], seconds[w]};
    for (std::size_t i : groups[w]) {
      ReportWindow(in, gaps[i], outcome, summary.gaps[i]);
      if (!WriteGap(in, net, gaps[i], outcome, priors[i], options, summary.gaps[i], *out)) {
        ++summary.fallbacks;
      }
    }
  }
  summary.solve_seconds = phase.Seconds();
  if (summary.fallbacks > 0) {
    summary.termination = Termination::kDiverged;
    summary.message = fmt::format(
        "{} of {} gaps filled by their prior after the optimal control failed or "
        "disagreed with the distance distributions (see gaps[].message)",
        summary.fallbacks, gaps.size());
  }
  summary.total_seconds = total.Seconds();
  return summary;
}

}  // namespace moreau::mocap
