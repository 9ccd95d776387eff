#include "moreau/mocap/network_from_recording.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "moreau/common/error.h"

namespace moreau::mocap {
namespace {

// Distance statistics of one pair over the frames where both markers are seen. Sums are
// shifted by the first distance so that the variance does not cancel.
struct PairStats {
  std::int64_t count = 0;
  double shift = 0.0, sum = 0.0, sum2 = 0.0;
  double min = std::numeric_limits<double>::infinity();
  double max = -std::numeric_limits<double>::infinity();
  void Add(double d) {
    if (count == 0) shift = d;
    ++count;
    sum += d - shift;
    sum2 += (d - shift) * (d - shift);
    min = std::min(min, d);
    max = std::max(max, d);
  }
  double Mean() const { return shift + sum / static_cast<double>(count); }
  double Spread() const {
    const double n = static_cast<double>(count);
    return std::sqrt(std::max(0.0, sum2 / n - (sum / n) * (sum / n)));
  }
};

// All pairs a < b, index a * M + b.
std::vector<PairStats> MeasurePairs(const Recording& rec) {
  const int m = rec.markers();
  std::vector<PairStats> stats(static_cast<std::size_t>(m) * static_cast<std::size_t>(m));
  std::vector<int> seen;
  for (std::int64_t f = 0; f < rec.frames(); ++f) {
    seen.clear();
    for (int k = 0; k < m; ++k) {
      if (rec.observed(f, k) && rec.is_marker(k)) seen.push_back(k);
    }
    for (std::size_t i = 0; i < seen.size(); ++i) {
      for (std::size_t j = i + 1; j < seen.size(); ++j) {
        const int a = seen[i], b = seen[j];
        const double d = (rec.point(f, a) - rec.point(f, b)).norm();
        stats[static_cast<std::size_t>(a * m + b)].Add(d);
      }
    }
  }
  return stats;
}

// Two points that coincide in some frame (a duplicated label, a model point placed on a marker):
// a spring between them has no direction there (the thesis' assumption (37)), so the automatic
// choice never joins them.
bool Coincide(const PairStats& s) { return s.min <= 1e-6 * s.Mean(); }

MarkerSpring MakeSpring(int a, int b, const PairStats& s, const MarkerNetworkOptions& o) {
  MarkerSpring sp;
  sp.a = std::min(a, b);
  sp.b = std::max(a, b);
  sp.common_frames = s.count;
  sp.mean = s.Mean();
  sp.spread = s.Spread();
  sp.min = s.min;
  sp.max = s.max;
  const double margin = o.bound_margin * (s.max - s.min) + o.bound_floor * sp.mean;
  sp.rest_min = std::max(0.0, s.min - margin);
  sp.rest_max = s.max + margin;
  return sp;
}

}  // namespace

const FieldList<MarkerNetworkOptions>& MarkerNetworkOptions::Fields() {
  using O = MarkerNetworkOptions;
  static const FieldList<O> list = [] {
    FieldList<O> t;
    t.Integer("partners", &O::partners, Range::AtLeast(1), "",
              "springs each marker chooses to its most rigid partners")
        .Integer("min_common_frames", &O::min_common_frames, Range::AtLeast(2), "frames",
                 "a pair seen together in fewer frames is never a spring")
        .Number("bound_margin", &O::bound_margin, Range::NonNegative(), "",
                "rest-length bounds widened by bound_margin (d_max − d_min)")
        .Number("bound_floor", &O::bound_floor, Range::NonNegative(), "",
                "… plus bound_floor d_mean (keeps L− < L+)")
        .Number("natural_period_seconds", &O::natural_period_seconds, Range::Positive(), "s",
                "T_n: stiffness κ = (2π / T_n)²")
        .Number("damping_ratio", &O::damping_ratio, Range::NonNegative(), "",
                "ζ: damping ξ = 2 ζ √κ (1: critical for one spring)");
    return t;
  }();
  return list;
}

void MarkerNetworkOptions::Validate() const { Fields().Validate(*this); }

nlohmann::json MarkerNetworkOptions::ToJson() const {
  nlohmann::json pairs = nlohmann::json::array();
  for (const auto& [a, b] : springs) pairs.push_back({a, b});
  return {{"partners", partners},
          {"min_common_frames", min_common_frames},
          {"bound_margin", bound_margin},
          {"bound_floor", bound_floor},
          {"natural_period_seconds", natural_period_seconds},
          {"damping_ratio", damping_ratio},
          {"springs", pairs}};
}

int MarkerNetwork::Partner(int s, int m) const {
  const MarkerSpring& sp = springs[static_cast<std::size_t>(s)];
  return sp.a == m ? sp.b : sp.a;
}

nlohmann::json MarkerNetwork::ToJson(const Recording& recording) const {
  nlohmann::json list = nlohmann::json::array();
  for (const MarkerSpring& s : springs) {
    list.push_back({{"a", recording.labels()[static_cast<std::size_t>(s.a)]},
                    {"b", recording.labels()[static_cast<std::size_t>(s.b)]},
                    {"common_frames", s.common_frames},
                    {"mean", s.mean},
                    {"spread", s.spread},
                    {"min", s.min},
                    {"max", s.max},
                    {"rest_min", s.rest_min},
                    {"rest_max", s.rest_max}});
  }
  return {{"springs", list},        {"length_scale", length_scale}, {"mass", mass},
          {"stiffness", stiffness}, {"damping", damping},           {"units", recording.units()}};
}

MarkerNetwork BuildMarkerNetwork(const Recording& rec, const MarkerNetworkOptions& o) {
  o.Validate();
  const int m = rec.markers();
  const std::vector<PairStats> stats = MeasurePairs(rec);
  auto pair = [&](int a, int b) -> const PairStats& {
    return stats[static_cast<std::size_t>(std::min(a, b) * m + std::max(a, b))];
  };
  std::vector<std::pair<int, int>> chosen;
  if (o.springs.empty()) {
    for (int a = 0; a < m; ++a) {
      std::vector<std::pair<double, int>> candidates;
      for (int b = 0; b < m; ++b) {
        if (b != a && pair(a, b).count >= o.min_common_frames && !Coincide(pair(a, b))) {
          candidates.emplace_back(pair(a, b).Spread(), b);
        }
      }
      std::sort(candidates.begin(), candidates.end());
      const std::size_t take = std::min(candidates.size(), static_cast<std::size_t>(o.partners));
      for (std::size_t i = 0; i < take; ++i) {
        chosen.emplace_back(std::min(a, candidates[i].second), std::max(a, candidates[i].second));
      }
    }
  } else {
    for (std::size_t i = 0; i < o.springs.size(); ++i) {
      const int a = rec.FindMarker(o.springs[i].first);
      const int b = rec.FindMarker(o.springs[i].second);
      const std::string key = fmt::format("network.springs[{}]", i);
      if (a < 0 || b < 0) {
        throw InputError(fmt::format("{}: unknown marker label '{}'", key,
                                     a < 0 ? o.springs[i].first : o.springs[i].second));
      }
      for (const int point : {a, b}) {
        if (!rec.is_marker(point)) {
          throw InputError(fmt::format("{}: '{}' is a model output ({}), not a marker", key,
                                       rec.labels()[static_cast<std::size_t>(point)],
                                       ToString(rec.type(point))));
        }
      }
      if (a == b)
        throw InputError(fmt::format("{}: joins marker '{}' to itself", key, o.springs[i].first));
      if (pair(a, b).count < o.min_common_frames) {
        throw InputError(fmt::format(
            "{}: '{}' and '{}' are seen together in {} frames, fewer than "
            "network.min_common_frames = {}",
            key, o.springs[i].first, o.springs[i].second, pair(a, b).count, o.min_common_frames));
      }
      chosen.emplace_back(std::min(a, b), std::max(a, b));
    }
  }
  std::sort(chosen.begin(), chosen.end());
  chosen.erase(std::unique(chosen.begin(), chosen.end()), chosen.end());

  MarkerNetwork net;
  net.springs_of.assign(static_cast<std::size_t>(m), {});
  std::vector<double> lengths;
  for (const auto& [a, b] : chosen) {
    net.springs_of[static_cast<std::size_t>(a)].push_back(static_cast<int>(net.springs.size()));
    net.springs_of[static_cast<std::size_t>(b)].push_back(static_cast<int>(net.springs.size()));
    net.springs.push_back(MakeSpring(a, b, pair(a, b), o));
    lengths.push_back(net.springs.back().mean);
  }
  if (!lengths.empty()) {
    std::nth_element(lengths.begin(),
                     lengths.begin() + static_cast<std::ptrdiff_t>(lengths.size() / 2),
                     lengths.end());
    net.length_scale = std::max(lengths[lengths.size() / 2], 1e-12);
  }
  const double omega = 2.0 * std::numbers::pi / o.natural_period_seconds;
  net.mass = 1.0;
  net.stiffness = omega * omega;
  net.damping = 2.0 * o.damping_ratio * omega;
  return net;
}

}  // namespace moreau::mocap
