#include "moreau/particles/room.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

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
        .Number("door_length", &Room::door_length, Range::NonNegative(), "length",
                "passage beyond the door (a bottleneck); 0: none")
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
  std::vector<SegmentObstacle> walls = {{{0.0, 0.0}, {W, 0.0}},
                                        {{0.0, H}, {W, H}},
                                        {{0.0, 0.0}, {0.0, H}},
                                        {{W, 0.0}, {W, door_lo()}},
                                        {{W, door_hi()}, {W, H}}};
  if (door_length > 0.0) {
    walls.push_back({{W, door_lo()}, {W + door_length, door_lo()}});
    walls.push_back({{W, door_hi()}, {W + door_length, door_hi()}});
  }
  return walls;
}

SelfPropulsion Room::WalkToTheDoor(double speed, double clearance) const {
  if (!(clearance >= 0.0) || !std::isfinite(clearance)) {
    throw InputError(
        fmt::format("room: the door's clearance must be finite and ≥ 0 (got {})", clearance));
  }
  // The opening a body's centre can pass through: each post's end moved in by the clearance,
  // or the door's middle when the door is narrower than twice the clearance.
  const double c = std::min(clearance, 0.5 * door_width);
  SelfPropulsion p;
  p.speed = speed;
  p.target = {width, door_lo() + c, 0.0};
  p.target_end = Vec3{width, door_hi() - c, 0.0};
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
    : door_line_(room.width + room.door_length),
      left_(static_cast<std::size_t>(count), 0),
      per_exit_(1, 0) {}

EvacuationCount::EvacuationCount(const CrowdGeometry& geometry, int count)
    : geometry_(geometry),
      walkable_(geometry.walkable),
      left_(static_cast<std::size_t>(count), 0),
      per_exit_(geometry.exits.size(), 0) {}

int EvacuationCount::Leaving(double x, double y) const {
  if (geometry_) {
    if (walkable_.Contains(x, y)) return 0;
    return static_cast<int>(1 + geometry_->NearestExit(x, y));
  }
  return x > door_line_ ? 1 : 0;
}

void EvacuationCount::Count(std::size_t id, int leaving) {
  if (leaving == 0) return;
  left_[id] = leaving;
  ++per_exit_[static_cast<std::size_t>(leaving - 1)];
  ++out_;
}

void EvacuationCount::Mark(std::size_t id, double x, double y) {
  if (!left_[id]) Count(id, Leaving(x, y));
}

int EvacuationCount::Update(std::span<const double> positions) {
  for (std::size_t i = 0; i < left_.size(); ++i) Mark(i, positions[2 * i], positions[2 * i + 1]);
  return out_;
}

int EvacuationCount::Update(std::span<const int> ids, std::span<const double> positions,
                            int threads) {
  const auto n = static_cast<std::int64_t>(ids.size());
  // Below a few thousand people a team costs more than the tests it would share.
  if (threads <= 1 || n < 4096) {
    for (std::int64_t s = 0; s < n; ++s) {
      Mark(static_cast<std::size_t>(ids[s]), positions[2 * s], positions[2 * s + 1]);
    }
    return out_;
  }
  // The tests in parallel (they only read), the counting after them in slot order: the same
  // ids, exits and totals as the loop above.
  leaving_.resize(ids.size());
#pragma omp parallel for num_threads(threads) schedule(static)
  for (std::int64_t s = 0; s < n; ++s) {
    leaving_[s] = left_[static_cast<std::size_t>(ids[s])]
                      ? 0
                      : Leaving(positions[2 * s], positions[2 * s + 1]);
  }
  for (std::int64_t s = 0; s < n; ++s) Count(static_cast<std::size_t>(ids[s]), leaving_[s]);
  return out_;
}

std::vector<int> EvacuationCount::OutIds() const {
  std::vector<int> ids;
  for (std::size_t i = 0; i < left_.size(); ++i) {
    if (left_[i]) ids.push_back(static_cast<int>(i));
  }
  return ids;
}

std::vector<int> EvacuationCount::OutExits() const {
  std::vector<int> exits;
  for (const int c : left_) {
    if (c) exits.push_back(c - 1);
  }
  return exits;
}

void EvacuationCount::RestoreOut(std::span<const int> ids, std::span<const int> exits) {
  if (!exits.empty() && exits.size() != ids.size()) {
    throw InputError("checkpoint: the evacuated ids and their exits differ in number");
  }
  std::vector<int> left(left_.size(), 0);
  std::vector<int> per_exit(per_exit_.size(), 0);
  for (std::size_t k = 0; k < ids.size(); ++k) {
    const int id = ids[k];
    const int exit = exits.empty() ? 0 : exits[k];
    if (id < 0 || static_cast<std::size_t>(id) >= left.size() ||
        left[static_cast<std::size_t>(id)]) {
      throw InputError(fmt::format("checkpoint: evacuated id {} is out of range or repeated", id));
    }
    if (exit < 0 || static_cast<std::size_t>(exit) >= per_exit.size()) {
      throw InputError(
          fmt::format("checkpoint: exit {} of evacuated id {} is out of range", exit, id));
    }
    left[static_cast<std::size_t>(id)] = static_cast<int>(1 + exit);
    ++per_exit[static_cast<std::size_t>(exit)];
  }
  left_.swap(left);
  per_exit_.swap(per_exit);
  out_ = static_cast<int>(ids.size());
}

}  // namespace moreau::particles
