#include "mocap/ocp_window.h"

#include <fmt/format.h>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <utility>

#include "moreau/common/error.h"
#include "moreau/control/continuation.h"
#include "moreau/control/initial_guess.h"

namespace moreau::mocap::internal {
namespace {

using Track = Eigen::Matrix<double, Eigen::Dynamic, 3>;  // frames × 3, solver units

}  // namespace

// C¹ cubic Hermite interpolation of a track sampled at every frame, tangents by central
// differences (one-sided at the ends). Time t is in solver units, `frames_per_unit` frames each.
struct HermiteTrack {
  Track x, m;
  double frames_per_unit = 1.0;
  HermiteTrack(Track positions, double fpu)
      : x(std::move(positions)), m(x.rows(), 3), frames_per_unit(fpu) {
    const Eigen::Index f = x.rows();
    for (Eigen::Index k = 0; k < f; ++k) {
      const Eigen::Index lo = std::max<Eigen::Index>(k - 1, 0);
      const Eigen::Index hi = std::min<Eigen::Index>(k + 1, f - 1);
      m.row(k) = (x.row(hi) - x.row(lo)) / static_cast<double>(std::max<Eigen::Index>(hi - lo, 1));
    }
  }
  void At(double t, double* position, double* velocity) const {
    const Eigen::Index f = x.rows();
    if (f == 1) {
      for (int i = 0; i < 3; ++i) position[i] = x(0, i), velocity[i] = 0.0;
      return;
    }
    t = std::clamp(t * frames_per_unit, 0.0, static_cast<double>(f - 1));
    const Eigen::Index k = std::min<Eigen::Index>(static_cast<Eigen::Index>(t), f - 2);
    const double s = t - static_cast<double>(k), s2 = s * s, s3 = s2 * s;
    const double h00 = 2 * s3 - 3 * s2 + 1, h10 = s3 - 2 * s2 + s, h01 = -2 * s3 + 3 * s2,
                 h11 = s3 - s2;
    const double d00 = 6 * s2 - 6 * s, d10 = 3 * s2 - 4 * s + 1, d01 = -d00, d11 = 3 * s2 - 2 * s;
    for (int i = 0; i < 3; ++i) {
      position[i] = h00 * x(k, i) + h10 * m(k, i) + h01 * x(k + 1, i) + h11 * m(k + 1, i);
      velocity[i] =
          frames_per_unit * (d00 * x(k, i) + d10 * m(k, i) + d01 * x(k + 1, i) + d11 * m(k + 1, i));
    }
  }
};

struct OcpWindowModel {
  std::vector<control::NetworkNode> nodes;
  std::vector<control::NetworkSpring> springs;
  std::vector<std::shared_ptr<const HermiteTrack>> free_tracks;
  int anchors = 0;
};

namespace {

// The marker's track over the window in solver units; samples missing in `base` (gaps not asked
// for) are interpolated linearly between the window's finite samples, or held at the ends.
Track WindowTrack(const Recording& base, int marker, const OcpWindow& w,
                  const Eigen::Vector3d& origin, double scale) {
  const Eigen::Index f = w.last - w.first + 1;
  Track t(f, 3);
  std::vector<Eigen::Index> finite;
  for (Eigen::Index k = 0; k < f; ++k) {
    const auto p = base.point(w.first + k, marker);
    if (p.allFinite()) {
      t.row(k) = ((p - origin) / scale).transpose();
      finite.push_back(k);
    }
  }
  if (finite.empty()) return Track();
  std::size_t next = 0;
  for (Eigen::Index k = 0; k < f; ++k) {
    while (next < finite.size() && finite[next] < k) ++next;
    if (next < finite.size() && finite[next] == k) continue;
    if (next == 0) {
      t.row(k) = t.row(finite.front());
    } else if (next == finite.size()) {
      t.row(k) = t.row(finite.back());
    } else {
      const Eigen::Index a = finite[next - 1], b = finite[next];
      const double tau = static_cast<double>(k - a) / static_cast<double>(b - a);
      t.row(k) = (1.0 - tau) * t.row(a) + tau * t.row(b);
    }
  }
  return t;
}

// Rest-length bounds of a spring in the window, centred on the prior: the range of its length
// along `base` (observed samples and the gaps' priors) over the window frames, widened by the
// network's margin rule (network_from_recording.h) and kept inside the recording's bounds; the
// recording's bounds when the two do not overlap.
std::pair<double, double> PriorBounds(const Recording& base, const MarkerSpring& sp,
                                      const OcpWindow& w, const MarkerNetworkOptions& o) {
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (std::int64_t f = w.first; f <= w.last; ++f) {
    const double d = (base.point(f, sp.a) - base.point(f, sp.b)).norm();
    if (!std::isfinite(d)) continue;
    lo = std::min(lo, d);
    hi = std::max(hi, d);
  }
  if (!(lo <= hi)) return {sp.rest_min, sp.rest_max};
  const double margin = o.bound_margin * (hi - lo) + o.bound_floor * sp.mean;
  const double rest_min = std::max(sp.rest_min, lo - margin);
  const double rest_max = std::min(sp.rest_max, hi + margin);
  if (!(rest_min < rest_max)) return {sp.rest_min, sp.rest_max};
  return {rest_min, rest_max};
}

OcpWindowModel BuildWindowModel(const Recording& base, const MarkerNetwork& net, const OcpWindow& w,
                                const Eigen::Vector3d& origin, double scale,
                                const OcpFillOptions& o) {
  const int max_anchor_springs = o.anchor_springs;
  OcpWindowModel model;
  std::map<int, int> node_of;
  // Time unit: one frame.
  const double fpu = 1.0;
  const double kappa = net.stiffness / (base.rate() * base.rate());
  const double xi = net.damping / base.rate();
  for (int marker : w.free) {
    auto track =
        std::make_shared<const HermiteTrack>(WindowTrack(base, marker, w, origin, scale), fpu);
    control::NetworkNode node;
    node.mass = 1.0;
    track->At(0.0, node.position.data(), node.velocity.data());
    node_of[marker] = static_cast<int>(model.nodes.size());
    model.nodes.push_back(node);
    model.free_tracks.push_back(std::move(track));
  }
  for (int marker : w.free) {
    // Springs to anchors: the `anchor_springs` most rigid ones (0: all); springs between free
    // nodes are always kept (they join the window's network).
    std::vector<int> springs = net.springs_of[static_cast<std::size_t>(marker)];
    std::stable_sort(springs.begin(), springs.end(), [&](int a, int b) {
      return net.springs[static_cast<std::size_t>(a)].spread <
             net.springs[static_cast<std::size_t>(b)].spread;
    });
    int anchor_springs = 0;
    for (int s : springs) {
      const int other = net.Partner(s, marker);
      const bool other_free = std::find(w.free.begin(), w.free.end(), other) != w.free.end();
      if (other_free && other < marker) continue;  // added from the other end
      if (!other_free) {
        if (max_anchor_springs > 0 && anchor_springs >= max_anchor_springs) continue;
        ++anchor_springs;
      }
      if (!node_of.contains(other)) {
        Track t = WindowTrack(base, other, w, origin, scale);
        if (t.rows() == 0) continue;  // never seen in the window: no anchor
        auto track = std::make_shared<const HermiteTrack>(std::move(t), fpu);
        control::NetworkNode node;
        node.fixed = true;
        node.motion = [track](double time, double* x, double* v) { track->At(time, x, v); };
        node_of[other] = static_cast<int>(model.nodes.size());
        model.nodes.push_back(std::move(node));
        ++model.anchors;
      }
      const MarkerSpring& sp = net.springs[static_cast<std::size_t>(s)];
      const auto [rest_min, rest_max] = o.prior_bounds ? PriorBounds(base, sp, w, o.network)
                                                       : std::pair{sp.rest_min, sp.rest_max};
      model.springs.push_back(control::NetworkSpring{node_of[marker], node_of[other], kappa, xi,
                                                     rest_min / scale, rest_max / scale});
    }
  }
  return model;
}

// The fastest rates of the window's dynamics linearised along the prior, per frame: the largest
// eigenvalues k of the stiffness K = Σ_s κ_s b_s b_sᵀ and c of the damping C = Σ_s ξ_s b_s b_sᵀ
// over the free nodes' positions (b_s: ±u_s / √m at the spring's free ends, u_s its direction),
// the maxima over the window's frames. A node held by n springs has rates up to n times one
// spring's, so the time step follows these, not one spring's ω (docs/mocap.md, "Time step").
struct WindowRates {
  double stiffness = 0.0;  // k
  double damping = 0.0;    // c
};

WindowRates FastestRates(const OcpWindowModel& model, Eigen::Index frames) {
  const auto m = static_cast<Eigen::Index>(model.free_tracks.size());  // free nodes come first
  WindowRates rates;
  Eigen::MatrixXd k(3 * m, 3 * m), c(3 * m, 3 * m);
  std::vector<Eigen::Vector3d> x(model.nodes.size());
  Eigen::Vector3d v;
  for (Eigen::Index f = 0; f < frames; ++f) {
    for (std::size_t j = 0; j < model.nodes.size(); ++j) {
      if (static_cast<Eigen::Index>(j) < m) {
        x[j] = model.free_tracks[j]->x.row(f).transpose();
      } else {
        model.nodes[j].motion(static_cast<double>(f), x[j].data(), v.data());
      }
    }
    k.setZero();
    c.setZero();
    for (const control::NetworkSpring& sp : model.springs) {
      const Eigen::Vector3d d =
          x[static_cast<std::size_t>(sp.b)] - x[static_cast<std::size_t>(sp.a)];
      if (!(d.norm() > 0.0)) continue;
      const Eigen::Vector3d u = d.normalized();
      Eigen::VectorXd b = Eigen::VectorXd::Zero(3 * m);
      if (sp.a < m)
        b.segment<3>(3 * sp.a) -= u / std::sqrt(model.nodes[static_cast<std::size_t>(sp.a)].mass);
      if (sp.b < m)
        b.segment<3>(3 * sp.b) += u / std::sqrt(model.nodes[static_cast<std::size_t>(sp.b)].mass);
      k.noalias() += sp.stiffness * b * b.transpose();
      c.noalias() += sp.damping * b * b.transpose();
    }
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> ek(k, Eigen::EigenvaluesOnly);
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> ec(c, Eigen::EigenvaluesOnly);
    rates.stiffness = std::max(rates.stiffness, ek.eigenvalues().maxCoeff());
    rates.damping = std::max(rates.damping, ec.eigenvalues().maxCoeff());
  }
  return rates;
}

// The window's tracking problem in solver units: lengths in ℓ, time in frames (a frame split into
// `substeps` steps with √k Δt <= 0.5, c Δt <= 1 (FastestRates) and Δt <= max_step_frames, so the
// explicit step of the scheme damps every mode, and so does the costates' backward step), weights
// and γ per frame. Only
// the ratio γ / weight matters (scaling both scales the cost), and in seconds both are per-sample
// quantities times the rate, so the same γ serves every rate (docs/mocap.md).
void MakeWindowProblem(const Recording& in, const Recording& base, const OcpWindow& w,
                       const OcpFillOptions& o, const OcpWindowModel& model, bool edge_as_observed,
                       OcpWindowProblem& p) {
  const Eigen::Index frames = w.last - w.first + 1;
  const int m = static_cast<int>(w.free.size());
  const control::SpringNetwork network(3, model.nodes, model.springs);
  const WindowRates rates = FastestRates(model, frames);
  const int substeps = static_cast<int>(std::ceil(
      std::max({1.0 / o.max_step_frames, std::sqrt(rates.stiffness) / 0.5, rates.damping / 1.0}) -
      1e-9));
  const double horizon = static_cast<double>(frames - 1);
  Eigen::MatrixXd ref(frames, 3 * m), weights(frames, m);
  // edge_as_observed: the frames of a gap that no observation of its marker follows (or
  // precedes) in the window, at an edge of the take, track the prior with the observations'
  // weight if that is lower (the last attempt of SolveOcpWindow).
  const double edge_weight =
      edge_as_observed ? std::min(o.prior_weight, o.observed_weight) : o.prior_weight;
  for (int j = 0; j < m; ++j) {
    const int marker = w.free[static_cast<std::size_t>(j)];
    ref.middleCols(3 * j, 3) = model.free_tracks[static_cast<std::size_t>(j)]->x;
    Eigen::Index first_seen = frames, last_seen = -1;
    for (Eigen::Index k = 0; k < frames; ++k) {
      if (!in.observed(w.first + k, marker)) continue;
      first_seen = std::min(first_seen, k);
      last_seen = k;
    }
    for (Eigen::Index k = 0; k < frames; ++k) {
      const bool seen = in.observed(w.first + k, marker);
      const bool prior = base.point(w.first + k, marker).allFinite();
      const bool edge = k < first_seen || k > last_seen;
      weights(k, j) =
          seen ? o.observed_weight : (prior ? (edge ? edge_weight : o.prior_weight) : 0.0);
    }
  }
  control::ReferenceFunction reference = control::SampledReference(
      network, horizon, std::move(ref), Eigen::MatrixXd(), std::move(weights), "ocp.reference");
  p.target = std::make_unique<control::TrackingProblem>(network, horizon, std::move(reference),
                                                        control::CostWeights{}, o.gamma);
  p.substeps = substeps;
  p.steps = static_cast<int>(frames - 1) * substeps;
}

// Warm start at (stiffness scale, γ): the prior trajectory, the controls at rest on it and the
// costates the scheme gives for them (control::FittedControlStart; docs/mocap.md, "The first
// iterate").
Eigen::VectorXd WarmStart(const OcpWindowProblem& p, double stiffness_scale, double gamma) {
  const OcpWindowModel& model = *p.model;
  const control::ProblemFamily family = [&p](double) { return *p.target; };
  const control::TrackingProblem start =
      control::ContinuationProblem(family, 1.0, stiffness_scale, gamma);
  const control::PontryaginDiscretization disc(start, p.steps);
  const auto m = static_cast<Eigen::Index>(model.free_tracks.size());
  Eigen::MatrixXd x(3 * m, p.steps + 1);
  Eigen::Vector3d v;
  for (int n = 0; n <= p.steps; ++n) {
    for (Eigen::Index j = 0; j < m; ++j) {
      model.free_tracks[static_cast<std::size_t>(j)]->At(static_cast<double>(n) / p.substeps,
                                                         x.col(n).data() + 3 * j, v.data());
    }
  }
  return control::FittedControlStart(disc, x);
}

}  // namespace

void MakeOcpWindowProblem(const Recording& in, const Recording& base, const MarkerNetwork& net,
                          const OcpWindow& w, const OcpFillOptions& o, OcpWindowProblem& p,
                          bool edge_as_observed) {
  const int m = static_cast<int>(w.free.size());
  p.scale = net.length_scale;
  p.origin = Eigen::Vector3d::Zero();
  for (int marker : w.free) p.origin += base.point(w.first, marker) / m;
  auto model =
      std::make_shared<const OcpWindowModel>(BuildWindowModel(base, net, w, p.origin, p.scale, o));
  p.model = model;
  p.anchors = model->anchors;
  p.springs = static_cast<int>(model->springs.size());
  MakeWindowProblem(in, base, w, o, *model, edge_as_observed, p);
  p.continuation = control::ContinuationOptions{};
  p.continuation.gamma_start = o.gamma_start;
  p.continuation.newton = o.newton;
  p.warm_start = WarmStart(p, 1.0, p.continuation.gamma_start);
}

control::ContinuationSummary SolveOcpWindowProblem(const OcpWindowProblem& p,
                                                   const OcpFillOptions& o, Eigen::VectorXd& y,
                                                   int& newton_iterations) {
  const control::ProblemFamily family = [&p](double) { return *p.target; };
  control::ContinuationOptions copt = p.continuation;
  Eigen::VectorXd warm = p.warm_start;
  control::ContinuationSummary cs = control::SolveWithContinuation(family, p.steps, copt, y, &warm);
  newton_iterations = cs.newton_iterations;
  if (!cs.ok()) {
    copt.stiffness_start = o.stiffness_start;
    copt.gamma_start = o.retry_gamma_start;
    copt.gamma_decrease = 0.1;
    warm = WarmStart(p, o.stiffness_start, copt.gamma_start);
    cs = control::SolveWithContinuation(family, p.steps, copt, y, &warm);
    newton_iterations += cs.newton_iterations;
  }
  return cs;
}

namespace {

// One window solved with the options' network (SolveOcpWindowProblem's two attempts).
OcpWindowResult AttemptWindow(const Recording& in, const Recording& base, const MarkerNetwork& net,
                              const OcpWindow& w, const OcpFillOptions& o,
                              bool edge_as_observed = false) {
  OcpWindowResult result;
  const Eigen::Index frames = w.last - w.first + 1;
  const int m = static_cast<int>(w.free.size());
  OcpWindowProblem p;
  try {
    MakeOcpWindowProblem(in, base, net, w, o, p, edge_as_observed);
    result.anchors = p.anchors;
    result.springs = p.springs;
    result.steps = p.steps;
    Eigen::VectorXd y;
    const control::ContinuationSummary cs =
        SolveOcpWindowProblem(p, o, y, result.newton_iterations);
    result.residual = cs.last_newton.final_residual;
    if (!cs.ok()) {
      result.termination = cs.termination;
      result.message = cs.message;
      return result;
    }
    const control::PontryaginDiscretization disc(*p.target, p.steps);
    Eigen::MatrixXd z, rho;
    disc.Unpack(y, z, rho);
    result.positions.resize(frames, 3 * m);
    for (Eigen::Index k = 0; k < frames; ++k) {
      for (int j = 0; j < m; ++j) {
        const Eigen::Vector3d x = z.col(k * p.substeps).segment<3>(6 * j);
        result.positions.block<1, 3>(k, 3 * j) = (p.origin + p.scale * x).transpose();
      }
    }
    result.termination =
        result.positions.allFinite() ? Termination::kConverged : Termination::kDiverged;
  } catch (const InputError& e) {
    result.anchors = p.anchors;
    result.springs = p.springs;
    result.steps = p.steps;
    // A degenerate window (e.g. an anchor on top of a free marker): reported, filled by fallback.
    result.termination = Termination::kDiverged;
    result.message = fmt::format("window model rejected: {}", e.what());
  }
  return result;
}

// Whether some free marker of the window has a hidden frame that no observation of it follows
// or precedes in the window (a gap at an edge of the take).
bool HasEdgeGap(const Recording& in, const OcpWindow& w) {
  for (int marker : w.free) {
    if (!in.observed(w.first, marker) || !in.observed(w.last, marker)) return true;
  }
  return false;
}

// The last attempt: the edge gaps' prior weighted like the observations (MakeWindowProblem).
OcpWindowResult EdgeAttempt(const Recording& in, const Recording& base, const MarkerNetwork& net,
                            const OcpWindow& w, const OcpFillOptions& o, OcpWindowResult failed) {
  if (!(o.prior_weight > o.observed_weight) || !HasEdgeGap(in, w)) return failed;
  OcpWindowResult edge = AttemptWindow(in, base, net, w, o, true);
  edge.newton_iterations += failed.newton_iterations;
  if (IsSuccess(edge.termination)) {
    edge.message = "the prior of the take's edge weighted like the observations";
    return edge;
  }
  failed.newton_iterations = edge.newton_iterations;
  failed.message = fmt::format("{}; the edge's prior weighted like the observations: {}",
                               failed.message, edge.message);
  return failed;
}

}  // namespace

OcpWindowResult SolveOcpWindow(const Recording& in, const Recording& base, const MarkerNetwork& net,
                               const OcpWindow& w, const OcpFillOptions& o) {
  OcpWindowResult result = AttemptWindow(in, base, net, w, o);
  const int fewer = o.retry_anchor_springs;
  if (IsSuccess(result.termination)) return result;
  if (fewer == 0 || (o.anchor_springs > 0 && o.anchor_springs <= fewer)) {
    return EdgeAttempt(in, base, net, w, o, std::move(result));
  }
  // Springs to anchors that are nearly rigid make the window's Newton system ill-conditioned
  // (docs/mocap.md, "How often the optimal control solves its window"): the next attempt keeps
  // only each free marker's `retry_anchor_springs` most rigid ones.
  OcpFillOptions retry = o;
  retry.anchor_springs = fewer;
  OcpWindowResult last = AttemptWindow(in, base, net, w, retry);
  last.newton_iterations += result.newton_iterations;
  if (IsSuccess(last.termination)) return last;
  last.message =
      fmt::format("{}; with {} anchor springs per marker: {}", result.message, fewer, last.message);
  return EdgeAttempt(in, base, net, w, o, std::move(last));
}

}  // namespace moreau::mocap::internal
