// A motion-capture recording: M labelled points sampled at F frames, with holes.
//
// Points. Most points are markers (positions in `units`); a C3D file may also store model outputs
// as points: joint angles, forces, moments, powers, scalars and ground reactions, named in its
// POINT:ANGLES, FORCES, MOMENTS, POWERS, SCALARS and REACTIONS lists. Each point has a PointType
// (markers unless set otherwise); marker work (gaps, fills, springs, donors, evaluation) uses
// markers only and carries the other points through unchanged. markers() counts every point, so
// that an index is a point index; CountPoints(PointType::kMarker) counts the markers.
//
// Positions are stored frame-major: marker m at frame f is the three doubles at
// (f·M + m)·3 … (f·M + m)·3 + 2, in the recording's units (`units`). A sample is either observed
// (observed(f, m) is true and the position is finite) or missing (observed is false; the stored
// position is NaN so that it can never be mistaken for data). Frames are 0-based here; the C3D
// frame number of frame f is first_frame + f.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

namespace moreau::mocap {

// What a point of a recording is. Only markers are positions in the recording's units.
enum class PointType { kMarker, kAngle, kForce, kMoment, kPower, kScalar, kReaction };
inline constexpr int kPointTypeCount = 7;

// "marker", "angle", "force", "moment", "power", "scalar", "reaction".
std::string_view ToString(PointType type);
// Every type, in the order above.
std::array<PointType, kPointTypeCount> AllPointTypes();

// Where a recording came from, as far as its file says (for `moreau inspect` and round trips).
struct SourceFormat {
  std::string container = "memory";  // "c3d", "trc", "csv" or "memory"
  std::string processor;             // C3D: "intel", "dec" or "mips"; empty otherwise
  std::string storage;               // C3D: "integer" (scaled 16-bit) or "float"
  double scale = -1.0;               // C3D POINT:SCALE (negative: float storage)
  int analog_channels = 0;           // C3D ANALOG:USED
  int analog_samples_per_frame = 0;  // C3D analog samples per video frame
};

class Recording {
 public:
  Recording() = default;
  // An all-missing recording of `frames` frames and the given marker labels.
  Recording(std::vector<std::string> labels, std::int64_t frames, double rate,
            std::string units = "mm");

  int markers() const { return static_cast<int>(labels_.size()); }
  std::int64_t frames() const { return frames_; }
  double rate() const { return rate_; }                // frames per second, > 0
  const std::string& units() const { return units_; }  // "mm", "cm" or "m"
  const std::vector<std::string>& labels() const { return labels_; }
  std::vector<std::string>& descriptions() { return descriptions_; }
  const std::vector<std::string>& descriptions() const { return descriptions_; }
  std::int64_t first_frame() const { return first_frame_; }
  void set_first_frame(std::int64_t first) { first_frame_ = first; }
  // The type of point `point` (kMarker unless set).
  PointType type(int point) const { return types_[static_cast<std::size_t>(point)]; }
  bool is_marker(int point) const { return type(point) == PointType::kMarker; }
  void set_type(int point, PointType type) { types_.at(static_cast<std::size_t>(point)) = type; }
  const std::vector<PointType>& types() const { return types_; }
  // The number of points of this type.
  int CountPoints(PointType type) const;
  // The units of the points of a type as the file states them ("deg", "N", "Nmm", …): units()
  // for markers, empty when not stated.
  const std::string& type_units(PointType type) const;
  void set_type_units(PointType type, std::string units);
  SourceFormat& format() { return format_; }
  const SourceFormat& format() const { return format_; }

  bool observed(std::int64_t frame, int marker) const {
    return observed_[Index(frame, marker)] != 0;
  }
  // The position of `marker` at `frame` (NaN when missing).
  Eigen::Map<const Eigen::Vector3d> point(std::int64_t frame, int marker) const {
    return Eigen::Map<const Eigen::Vector3d>(&positions_[3 * Index(frame, marker)]);
  }
  // Marks the sample observed at p (all finite; throws InputError otherwise).
  void SetPoint(std::int64_t frame, int marker, const Eigen::Vector3d& p);
  // Marks the sample missing (position NaN).
  void ClearPoint(std::int64_t frame, int marker);

  // Index of the marker with this label, or -1.
  int FindMarker(std::string_view label) const;
  // Converts the markers' positions and units() to "mm", "cm" or "m" (InputError for another
  // unit); the other points are left as they are.
  void ConvertUnits(std::string_view units);
  // Number of observed samples of one marker.
  std::int64_t ObservedCount(int marker) const;

  // Raw storage (frame-major, see above).
  std::span<const double> positions() const { return positions_; }
  std::span<const std::uint8_t> observed_mask() const { return observed_; }

 private:
  std::size_t Index(std::int64_t frame, int marker) const {
    return static_cast<std::size_t>(frame) * labels_.size() + static_cast<std::size_t>(marker);
  }

  std::vector<std::string> labels_;
  std::vector<std::string> descriptions_;
  std::int64_t frames_ = 0;
  double rate_ = 0.0;
  std::string units_ = "mm";
  std::vector<PointType> types_;
  std::array<std::string, kPointTypeCount> type_units_;  // by PointType; [kMarker] unused
  std::int64_t first_frame_ = 1;
  SourceFormat format_;
  std::vector<double> positions_;       // frames · markers · 3
  std::vector<std::uint8_t> observed_;  // frames · markers
};

// Metres per unit for the length units a Recording holds ("mm", "cm", "m"); InputError otherwise.
double MetresPerUnit(std::string_view units);
// True for "mm", "cm" and "m".
bool IsLengthUnit(std::string_view units);

// A run of consecutive missing frames of one marker: frames first … last (0-based, inclusive),
// with an observed sample (or the recording's end) on each side.
struct Gap {
  int marker = 0;
  std::int64_t first = 0;
  std::int64_t last = 0;
  std::int64_t length() const { return last - first + 1; }
};

// Every gap of every marker (points of other types have none), ordered by marker, then first
// frame. A marker never observed gives one gap over the whole recording.
std::vector<Gap> FindGaps(const Recording& recording);

// The one check of a list of gaps against `recording`, shared by every fill: throws InputError
// "gaps[i] (marker m, frames first…last): why" when a gap's marker is not one of the
// recording's markers (an index out of range or a point of another type), its frames are not
// inside the recording or first > last, or one of its samples is observed.
void CheckGaps(const Recording& recording, const std::vector<Gap>& gaps);

}  // namespace moreau::mocap
