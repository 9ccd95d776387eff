#include "moreau/mocap/complete_part.h"

#include <algorithm>

#include "moreau/common/error.h"

namespace moreau::mocap {
namespace {

// missing[m][f]: missing samples of marker m in frames [0, f) (markers only; others empty).
std::vector<std::vector<std::int64_t>> MissingPrefix(const Recording& in) {
  std::vector<std::vector<std::int64_t>> missing(static_cast<std::size_t>(in.markers()));
  for (int m = 0; m < in.markers(); ++m) {
    if (!in.is_marker(m)) continue;
    auto& prefix = missing[static_cast<std::size_t>(m)];
    prefix.assign(static_cast<std::size_t>(in.frames()) + 1, 0);
    for (std::int64_t f = 0; f < in.frames(); ++f) {
      prefix[static_cast<std::size_t>(f) + 1] =
          prefix[static_cast<std::size_t>(f)] + (in.observed(f, m) ? 0 : 1);
    }
  }
  return missing;
}

}  // namespace

nlohmann::json CompletePart::ToJson(const Recording& in) const {
  nlohmann::json kept = nlohmann::json::array();
  nlohmann::json dropped = nlohmann::json::array();
  for (int m = 0; m < in.markers(); ++m) {
    if (!in.is_marker(m)) continue;
    const bool keep = std::find(markers.begin(), markers.end(), m) != markers.end();
    (keep ? kept : dropped).push_back(in.labels()[static_cast<std::size_t>(m)]);
  }
  return {{"first_frame", first}, {"frames", frames}, {"markers", kept}, {"dropped", dropped}};
}

CompletePart FindCompletePart(const Recording& in, std::int64_t min_frames) {
  MOREAU_ASSERT(min_frames >= 1);
  const std::int64_t total = in.frames();
  const std::int64_t step = std::max<std::int64_t>(1, (total + 99) / 100);
  std::vector<std::int64_t> ends;  // candidate range ends (exclusive), the grid and the last
  for (std::int64_t e = step; e < total; e += step) ends.push_back(e);
  ends.push_back(total);
  const auto missing = MissingPrefix(in);
  CompletePart best;
  std::int64_t best_samples = 0;
  for (std::int64_t a = 0; a + min_frames <= total; a += step) {
    for (std::int64_t b : ends) {
      if (b - a < min_frames) continue;
      std::int64_t complete = 0;
      for (const auto& prefix : missing) {
        if (!prefix.empty() &&
            prefix[static_cast<std::size_t>(b)] == prefix[static_cast<std::size_t>(a)]) {
          ++complete;
        }
      }
      if (complete * (b - a) > best_samples) {  // strict: ties keep the earlier, shorter-first
        best_samples = complete * (b - a);
        best.first = a;
        best.frames = b - a;
      }
    }
  }
  for (int m = 0; m < in.markers() && best_samples > 0; ++m) {
    const auto& prefix = missing[static_cast<std::size_t>(m)];
    if (!prefix.empty() && prefix[static_cast<std::size_t>(best.first + best.frames)] ==
                               prefix[static_cast<std::size_t>(best.first)]) {
      best.markers.push_back(m);
    }
  }
  return best;
}

Recording ExtractPart(const Recording& in, const CompletePart& part) {
  std::vector<std::string> labels;
  for (int m : part.markers) labels.push_back(in.labels()[static_cast<std::size_t>(m)]);
  Recording out(labels, part.frames, in.rate(), in.units());
  out.set_first_frame(in.first_frame() + part.first);
  out.format() = in.format();
  for (std::size_t k = 0; k < part.markers.size(); ++k) {
    const int m = part.markers[k];
    out.descriptions()[k] = in.descriptions()[static_cast<std::size_t>(m)];
    for (std::int64_t f = 0; f < part.frames; ++f) {
      out.SetPoint(f, static_cast<int>(k), in.point(part.first + f, m));
    }
  }
  return out;
}

}  // namespace moreau::mocap
