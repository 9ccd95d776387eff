#include "moreau/mocap/recording.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "moreau/common/error.h"

namespace moreau::mocap {

double MetresPerUnit(std::string_view units) {
  if (units == "mm") return 1e-3;
  if (units == "cm") return 1e-2;
  if (units == "m") return 1.0;
  throw InputError(fmt::format("units must be mm, cm or m (got '{}')", units));
}

std::string_view ToString(PointType type) {
  static constexpr std::array<std::string_view, kPointTypeCount> kNames = {
      "marker", "angle", "force", "moment", "power", "scalar", "reaction"};
  return kNames.at(static_cast<std::size_t>(type));
}

std::array<PointType, kPointTypeCount> AllPointTypes() {
  return {PointType::kMarker, PointType::kAngle,  PointType::kForce,   PointType::kMoment,
          PointType::kPower,  PointType::kScalar, PointType::kReaction};
}

bool IsLengthUnit(std::string_view units) { return units == "mm" || units == "cm" || units == "m"; }

Recording::Recording(std::vector<std::string> labels, std::int64_t frames, double rate,
                     std::string units)
    : labels_(std::move(labels)), frames_(frames), rate_(rate), units_(std::move(units)) {
  if (frames < 0) throw InputError(fmt::format("frames must be ≥ 0 (got {})", frames));
  if (!(rate > 0.0) || !std::isfinite(rate)) {
    throw InputError(fmt::format("rate must be > 0 (got {})", rate));
  }
  (void)MetresPerUnit(units_);
  descriptions_.assign(labels_.size(), "");
  types_.assign(labels_.size(), PointType::kMarker);
  const auto samples = static_cast<std::size_t>(frames) * labels_.size();
  positions_.assign(3 * samples, std::numeric_limits<double>::quiet_NaN());
  observed_.assign(samples, 0);
}

void Recording::SetPoint(std::int64_t frame, int marker, const Eigen::Vector3d& p) {
  if (!p.allFinite()) {
    throw InputError(fmt::format("position of marker {} at frame {} is not finite", marker, frame));
  }
  const std::size_t i = Index(frame, marker);
  for (int c = 0; c < 3; ++c) positions_[3 * i + static_cast<std::size_t>(c)] = p[c];
  observed_[i] = 1;
}

void Recording::ClearPoint(std::int64_t frame, int marker) {
  const std::size_t i = Index(frame, marker);
  for (int c = 0; c < 3; ++c) {
    positions_[3 * i + static_cast<std::size_t>(c)] = std::numeric_limits<double>::quiet_NaN();
  }
  observed_[i] = 0;
}

int Recording::FindMarker(std::string_view label) const {
  for (std::size_t m = 0; m < labels_.size(); ++m) {
    if (labels_[m] == label) return static_cast<int>(m);
  }
  return -1;
}

int Recording::CountPoints(PointType type) const {
  return static_cast<int>(std::count(types_.begin(), types_.end(), type));
}

const std::string& Recording::type_units(PointType type) const {
  return type == PointType::kMarker ? units_ : type_units_[static_cast<std::size_t>(type)];
}

void Recording::set_type_units(PointType type, std::string units) {
  if (type == PointType::kMarker) {
    throw InputError("the units of markers are the recording's units; set them by ConvertUnits");
  }
  type_units_[static_cast<std::size_t>(type)] = std::move(units);
}

void Recording::ConvertUnits(std::string_view units) {
  const double factor = MetresPerUnit(units_) / MetresPerUnit(units);
  if (factor != 1.0) {
    for (std::size_t i = 0; i < positions_.size(); ++i) {
      const std::size_t point = (i / 3) % labels_.size();
      if (types_[point] == PointType::kMarker) positions_[i] *= factor;  // NaN stays NaN
    }
  }
  units_ = std::string(units);
}

std::int64_t Recording::ObservedCount(int marker) const {
  std::int64_t n = 0;
  for (std::int64_t f = 0; f < frames_; ++f) n += observed_[Index(f, marker)];
  return n;
}

std::vector<Gap> FindGaps(const Recording& recording) {
  std::vector<Gap> gaps;
  for (int m = 0; m < recording.markers(); ++m) {
    if (!recording.is_marker(m)) continue;
    std::int64_t f = 0;
    while (f < recording.frames()) {
      if (recording.observed(f, m)) {
        ++f;
        continue;
      }
      Gap gap{m, f, f};
      while (gap.last + 1 < recording.frames() && !recording.observed(gap.last + 1, m)) ++gap.last;
      gaps.push_back(gap);
      f = gap.last + 1;
    }
  }
  return gaps;
}

void CheckGaps(const Recording& recording, const std::vector<Gap>& gaps) {
  for (std::size_t i = 0; i < gaps.size(); ++i) {
    const Gap& gap = gaps[i];
    const auto where = [&] {
      return fmt::format("gaps[{}] (marker {}, frames {}…{})", i, gap.marker, gap.first, gap.last);
    };
    if (gap.marker < 0 || gap.marker >= recording.markers()) {
      throw InputError(fmt::format("{}: marker out of range (the recording has {} markers)",
                                   where(), recording.markers()));
    }
    if (!recording.is_marker(gap.marker)) {
      throw InputError(fmt::format("{}: point '{}' is a model output ({}), not a marker", where(),
                                   recording.labels()[static_cast<std::size_t>(gap.marker)],
                                   ToString(recording.type(gap.marker))));
    }
    if (gap.first < 0 || gap.last < gap.first || gap.last >= recording.frames()) {
      throw InputError(
          fmt::format("{}: frames outside 0…{} or first > last", where(), recording.frames() - 1));
    }
    for (std::int64_t f = gap.first; f <= gap.last; ++f) {
      if (recording.observed(f, gap.marker)) {
        throw InputError(fmt::format("{}: frame {} is observed, not missing", where(), f));
      }
    }
  }
}

}  // namespace moreau::mocap
