// A crowd room with a door and the count of people who left it (examples/crowd.toml): the
// Maury–Venel evacuation set-up as particle-core data, lengths in the scenario's unit (metres).
//
// The room is [0, width] × [0, height] in the plane (dimension 2); its walls are line segments
// (particles stay at distance ≥ r_i from them) with a door of width door_width centred on the
// right wall x = width, spanning y ∈ [door_lo, door_hi]. With door_length L > 0 the door is a
// passage (a bottleneck) of that width between two walls from x = width to x = width + L.
#pragma once

#include <optional>
#include <span>
#include <vector>

#include "moreau/common/field_list.h"
#include "moreau/particles/forces.h"
#include "moreau/particles/geometry.h"
#include "moreau/particles/model.h"

namespace moreau::particles {

struct Room {
  double width = 15.0;       // > 0
  double height = 15.0;      // > 0
  double door_width = 1.2;   // in (0, height)
  double door_length = 0.0;  // ≥ 0: the passage's length; 0: a door in the wall

  static const FieldList<Room>& Fields();  // width, height, door_width, door_length
  // Throws InputError(key, reason): ("width", "must be > 0 (got 0)"), ("door_width", "must be
  // smaller than the room height (got 16 ≥ 15)").
  void Validate() const;
  double door_lo() const { return 0.5 * (height - door_width); }
  double door_hi() const { return 0.5 * (height + door_width); }

  // The five wall segments, in this order: bottom, top, left, right below the door, right above
  // the door; with a passage, then its lower and its upper wall.
  std::vector<SegmentObstacle> Walls() const;
  // Walking at `speed` toward the nearest point of the door's opening shrunk by `clearance` at
  // each post, y ∈ [door_lo + clearance, door_hi − clearance] (the door's middle when the door
  // is narrower than 2 clearance); once through it (x > width), along +e_0, away from the room.
  // With a clearance of a body's radius, someone beside the door heads for a point their body
  // passes, never at a post's end: a wall's repulsion or contact there, exactly opposite to the
  // desired direction, would hold them still. Throws InputError for a clearance < 0 or not
  // finite.
  SelfPropulsion WalkToTheDoor(double speed, double clearance = 0.0) const;
};

// Validates the room and appends its walls to model->segments. Throws InputError for a model
// that is not two-dimensional ("room: a room needs dimension 2 (got 3)").
void AddRoom(const Room& room, ParticleModel* model);

// People out of the room: a person counts as out from the first time their centre passes the
// door line x = width + door_length (noise may carry them back over it for a moment; they stay
// counted). For a CrowdGeometry: from the first time their centre is outside the walkable
// polygon, counted at the exit nearest to it then.
class EvacuationCount {
 public:
  EvacuationCount(const Room& room, int count);
  EvacuationCount(const CrowdGeometry& geometry, int count);
  // positions: size 2·count, particle-id order. Returns the number out so far.
  int Update(std::span<const double> positions);
  // The same from positions in any slot order: slot s holds particle ids[s] at
  // positions[2s], positions[2s + 1] (Engine::Stored(), no copy). The count does not depend on
  // the order. On `threads` OpenMP threads (the inside tests, every person's at every call, split
  // between them) the count is the same as on one.
  int Update(std::span<const int> ids, std::span<const double> positions, int threads = 1);
  int out() const { return out_; }
  // The number of exits (1 for a room) and the people out through each.
  std::size_t exits() const { return per_exit_.size(); }
  const std::vector<int>& OutPerExit() const { return per_exit_; }
  // The ids counted out so far, ascending (a checkpoint), their exits in the same order, and
  // their restore on a count of the same room and count (exits: empty for a room): InputError
  // "checkpoint: …" for an id out of range or given twice, or an exit out of range.
  std::vector<int> OutIds() const;
  std::vector<int> OutExits() const;
  void RestoreOut(std::span<const int> ids, std::span<const int> exits = {});

 private:
  // 0 when (x, y) is inside, else 1 + the exit it left by.
  int Leaving(double x, double y) const;
  // Counts particle id out by exit leaving − 1 (nothing for leaving = 0).
  void Count(std::size_t id, int leaving);
  // Counts particle id at (x, y) if it is out.
  void Mark(std::size_t id, double x, double y);
  double door_line_ = 0.0;
  std::optional<CrowdGeometry> geometry_;
  PolygonStrips walkable_;  // geometry_->walkable's inside test
  std::vector<int> left_;   // per id: 0 in, 1 + exit out
  std::vector<int> per_exit_;
  std::vector<int> leaving_;  // per slot, Update's parallel pass
  int out_ = 0;
};

}  // namespace moreau::particles
