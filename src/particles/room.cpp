#include "moreau/particles/room.h"

#include <cmath>

#include <fmt/format.h>

#include "moreau/common/error.h"

namespace moreau::particles {

const FieldList<Room>& Room::Fields() {
  static const FieldList<Room> list = [] {
    FieldList<Room> t;
    t.Number("width", &Room::width, Range::Positive(), "length", "room width (x)")
        .Number("height", &Room::height, Range::Positive(), "length", "room height (y)")
        .Number("door_width", &Room::door_width, Range::Positive(), "length",
                "door in the right wall, centred")
        .Rule("door_width", [](const Room& r) {
          return r.door_width < r.height
                     ? std::string()
                     : fmt::format("must be smaller than the room height (got {} ≥ {})",
                                   r.door_width, r.height);
        });
    return t;
  }();
  return list;
}

void Room::Validate() const { Fields().Validate(*this); }

std::vector<SegmentObstacle> Room::Walls() const {
  const double W = width;
  const double H = height;
  return {{{0.0, 0.0}, {W, 0.0}},
          {{0.0, H}, {W, H}},
          {{0.0, 0.0}, {0.0, H}},
          {{W, 0.0}, {W, door_lo()}},
          {{W, door_hi()}, {W, H}}};
}

SelfPropulsion Room::WalkToTheDoor(double speed) const {
  SelfPropulsion p;
  p.speed = speed;
  p.target = {width, door_lo(), 0.0};
  p.target_end = Vec3{width, door_hi(), 0.0};
  p.exit_direction = Vec3{1.0, 0.0, 0.0};
  return p;
}

void AddRoom(const Room& room, ParticleModel* model) {
  try {
    room.Validate();
  } catch (const InputError& e) {
    throw e.Under("room");
  }
  if (model->dimension != 2) {
    throw InputError(fmt::format("room: a room needs dimension 2 (got {})", model->dimension));
  }
  for (const SegmentObstacle& s : room.Walls()) model->segments.push_back(s);
}

EvacuationCount::EvacuationCount(const Room& room, int count)
    : door_line_(room.width), left_(static_cast<std::size_t>(count), 0) {}

void EvacuationCount::Mark(std::size_t id, double x) {
  if (!left_[id] && x > door_line_) {
    left_[id] = 1;
    ++out_;
  }
}

int EvacuationCount::Update(std::span<const double> positions) {
  for (std::size_t i = 0; i < left_.size(); ++i) Mark(i, positions[2 * i]);
  return out_;
}

int EvacuationCount::Update(std::span<const int> ids, std::span<const double> positions) {
  for (std::size_t s = 0; s < ids.size(); ++s)
    Mark(static_cast<std::size_t>(ids[s]), positions[2 * s]);
  return out_;
}

std::vector<int> EvacuationCount::OutIds() const {
  std::vector<int> ids;
  for (std::size_t i = 0; i < left_.size(); ++i) {
    if (left_[i]) ids.push_back(static_cast<int>(i));
  }
  return ids;
}

void EvacuationCount::RestoreOut(std::span<const int> ids) {
  std::vector<char> left(left_.size(), 0);
  for (const int id : ids) {
    if (id < 0 || static_cast<std::size_t>(id) >= left.size() ||
        left[static_cast<std::size_t>(id)]) {
      throw InputError(fmt::format("checkpoint: evacuated id {} is out of range or repeated", id));
    }
    left[static_cast<std::size_t>(id)] = 1;
  }
  left_.swap(left);
  out_ = static_cast<int>(ids.size());
}

}  // namespace moreau::particles
