// The room's walk to the door (room.h Room::WalkToTheDoor): the target is the door's opening
// shrunk by the clearance at each post, and a person of the collision-free model beside the door,
// on the line of a post's end, leaves through it instead of stopping before that end.
#include <gtest/gtest.h>

#include <vector>

#include "moreau/particles/engine.h"
#include "moreau/particles/room.h"
#include "test_util.h"

namespace moreau::particles {
namespace {

Room EightMetreRoom(double door_width) {
  Room room;
  room.width = 8.0;
  room.height = 8.0;
  room.door_width = door_width;
  return room;
}

TEST(RoomDoor, TargetIsTheOpeningShrunkByTheClearance) {
  const Room room = EightMetreRoom(0.8);  // door y ∈ [3.6, 4.4]
  const SelfPropulsion plain = room.WalkToTheDoor(1.34);
  EXPECT_EQ(plain.target, (Vec3{8.0, 3.6, 0.0}));
  EXPECT_EQ(*plain.target_end, (Vec3{8.0, 4.4, 0.0}));
  const SelfPropulsion shrunk = room.WalkToTheDoor(1.34, 0.15);
  EXPECT_DOUBLE_EQ(shrunk.target[1], 3.75);
  EXPECT_DOUBLE_EQ((*shrunk.target_end)[1], 4.25);
  EXPECT_EQ(shrunk.target[0], 8.0);
  EXPECT_EQ((*shrunk.target_end)[0], 8.0);
  EXPECT_EQ(*shrunk.exit_direction, (Vec3{1.0, 0.0, 0.0}));
  EXPECT_EQ(shrunk.speed, 1.34);
  // A door narrower than twice the clearance: its middle, a point.
  const SelfPropulsion narrow = room.WalkToTheDoor(1.34, 0.5);
  EXPECT_DOUBLE_EQ(narrow.target[1], 4.0);
  EXPECT_DOUBLE_EQ((*narrow.target_end)[1], 4.0);
  testing::ExpectInputError([&] { (void)room.WalkToTheDoor(1.34, -0.1); }, "clearance");
}

// One person of radius ℓ/2 at (7, 3.5), 0.1 m below the line y = 3.6 of the lower post's end,
// walks in the collision-free model without noise. Aimed at the post's end (the door's nearest
// point), they would stop 0.17–0.19 m before it, the post's repulsion exactly opposite to the
// desired direction; aimed at the opening shrunk by ℓ/2 they pass the door line x = 8 within
// 1.5 s (1.1 m at 1.34 m/s takes 0.8 s) and keep walking away.
TEST(RoomDoor, PersonBesideTheDoorOnAPostsLineLeaves) {
  const Room room = EightMetreRoom(0.8);
  ParticleModel model;
  model.radius = {0.15};
  AddRoom(room, &model);
  Forces forces;
  const CollisionFreeSpeed walk;  // ℓ = 0.3 m
  forces.propulsion = room.WalkToTheDoor(1.34, 0.5 * walk.length);
  forces.walking.collision_free = walk;
  EngineOptions options;
  options.h = 0.01;
  const std::vector<double> start = {7.0, 3.5};
  Engine engine(model, forces, options, start);
  EvacuationCount out(room, 1);
  const EngineSummary summary = engine.Run(1.5, [&](const Engine& e) {
    out.Update(e.Positions());
    return true;
  });
  ASSERT_TRUE(summary.ok()) << summary.message;
  EXPECT_EQ(out.out(), 1);
  const std::vector<double> x = engine.Positions();
  EXPECT_GT(x[0], 8.0);
  // Through the opening, clear of both posts.
  EXPECT_GT(x[1], room.door_lo() + 0.15);
  EXPECT_LT(x[1], room.door_hi() - 0.15);
}

}  // namespace
}  // namespace moreau::particles
