// Checkpoints: a run stopped at some step, saved, restored into a fresh engine and continued gives
// the same bits as the run that never stopped (noise on, any thread count, both sweep orders).
#include "moreau/particles/checkpoint.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "moreau/common/random.h"
#include "particles/test_util.h"

namespace moreau::particles {
namespace {

using testing::ExpectInputError;

struct Case {
  ParticleModel model;
  Forces forces;
  std::vector<double> x0;
};

// 2D: 200 disks in a box periodic in x with walls in y, drifting down with noise.
Case Disks2d() {
  Case c;
  ParticleModel& m = c.model;
  SplitMix64 rng(11);
  for (int i = 0; i < 200; ++i) m.radius.push_back(0.25 + 0.1 * rng.Uniform01());
  m.periodic = {true, false, false};
  m.AddBoxWalls({0, 0, 0}, {14, 14, 0});  // walls in y only
  m.domain_lo = {0, 0, 0};
  m.domain_hi = {14, 14, 0};
  c.x0 = RandomSequentialAddition(m, {0, 0, 0}, {14, 14, 0}, 4);
  c.forces.constant_force = {0.3, -1.0, 0.0};
  c.forces.diffusion = 0.05;
  return c;
}

// 3D, open space: a spreading cloud (the cell grid's fit follows it) in a trap, with noise.
Case Cloud3d() {
  Case c;
  ParticleModel& m = c.model;
  m.dimension = 3;
  m.radius.assign(200, 0.3);
  m.domain_lo = {0, 0, 0};
  m.domain_hi = {8, 8, 8};
  c.x0 = RandomSequentialAddition(m, {0, 0, 0}, {8, 8, 8}, 9);
  c.forces.diffusion = 0.4;
  return c;
}

// Runs `total` steps uninterrupted and, on other engines, `stop` steps, a save (through the
// temporary file `file` when given), a restore into a new engine with `resume_threads`, the rest.
void ExpectResumeBitIdentical(const Case& c, EngineOptions o, int stop, int total,
                              int resume_threads, const char* file = nullptr) {
  const double T = total * o.h;
  Engine whole(c.model, c.forces, o, c.x0);
  ASSERT_TRUE(whole.Run(T).ok());

  Engine first(c.model, c.forces, o, c.x0);
  ASSERT_TRUE(first.Run(stop * o.h).ok());
  EngineState state = first.SaveState();
  if (file != nullptr) {
    const std::filesystem::path path = std::filesystem::temp_directory_path() / file;
    WriteCheckpoint(path, state, {{"note", "test"}});
    nlohmann::json run;
    state = ReadCheckpoint(path, &run);
    std::filesystem::remove(path);
    EXPECT_EQ(run.at("note"), "test");
  }
  EngineOptions o2 = o;
  o2.threads = resume_threads;
  Engine second(c.model, c.forces, o2, c.x0);
  second.RestoreState(state);
  EXPECT_EQ(second.step(), stop);
  int observed = 0;
  const EngineSummary s = second.Continue(T, [&](const Engine&) {
    ++observed;
    return true;
  });
  ASSERT_TRUE(s.ok()) << s.message;
  EXPECT_EQ(observed, total - stop);
  EXPECT_EQ(second.step(), total);
  EXPECT_TRUE(second.Positions() == whole.Positions());
  const EngineStats a = whole.summary().stats, b = s.stats;
  EXPECT_EQ(a.neighbour_list_builds, b.neighbour_list_builds);
  EXPECT_EQ(a.verlet_retries, b.verlet_retries);
  EXPECT_EQ(a.projections, b.projections);
  EXPECT_EQ(a.constraint_evaluations, b.constraint_evaluations);
  EXPECT_EQ(a.shortest_rebuild_interval, b.shortest_rebuild_interval);
  EXPECT_EQ(a.max_overlap, b.max_overlap);
}

TEST(ParticleCheckpoint, ResumedRunIsBitIdenticalColoured2d) {
  EngineOptions o;
  o.h = 0.01;
  o.block_cells = 2;
  o.threads = 1;
  const Case c = Disks2d();
  ExpectResumeBitIdentical(c, o, 23, 50, 1);
  ExpectResumeBitIdentical(c, o, 23, 50, 2);
  o.threads = 2;
  ExpectResumeBitIdentical(c, o, 31, 50, 1);
}

TEST(ParticleCheckpoint, ResumedRunIsBitIdenticalLexicographicAndThroughAFile) {
  EngineOptions o;
  o.h = 0.01;
  o.order = SweepOrder::kLexicographic;
  const Case c = Disks2d();
  ExpectResumeBitIdentical(c, o, 30, 60, 1, "moreau_checkpoint_test.ckpt");
}

TEST(ParticleCheckpoint, ResumedRunIsBitIdenticalWhileTheGridFollowsASpreadingCloud3d) {
  EngineOptions o;
  o.h = 0.02;
  o.threads = 2;
  o.block_cells = 2;
  const Case c = Cloud3d();
  ExpectResumeBitIdentical(c, o, 37, 60, 1, "moreau_checkpoint_test3d.ckpt");
}

TEST(ParticleCheckpoint, CorruptTruncatedOrForeignCheckpointsAreRefused) {
  const Case c = Disks2d();
  EngineOptions o;
  o.h = 0.01;
  Engine e(c.model, c.forces, o, c.x0);
  ASSERT_TRUE(e.Run(5 * o.h).ok());
  const std::filesystem::path path =
      std::filesystem::temp_directory_path() / "moreau_checkpoint_corrupt.ckpt";
  WriteCheckpoint(path, e.SaveState(), nlohmann::json::object());
  std::string bytes;
  {
    std::ifstream in(path, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  const auto write = [&](const std::string& b) {
    std::ofstream(path, std::ios::binary | std::ios::trunc) << b;
  };
  nlohmann::json run;
  std::string flipped = bytes;
  flipped[bytes.size() / 2] = static_cast<char>(flipped[bytes.size() / 2] ^ 0x10);
  write(flipped);
  ExpectInputError([&] { ReadCheckpoint(path, &run); }, "corrupt");
  write(bytes.substr(0, bytes.size() - 7));
  ExpectInputError([&] { ReadCheckpoint(path, &run); }, "corrupt");
  write("not a checkpoint at all, just some text");
  ExpectInputError([&] { ReadCheckpoint(path, &run); }, "not a moreau checkpoint");
  std::filesystem::remove(path);
  ExpectInputError([&] { ReadCheckpoint(path, &run); }, "cannot be opened");

  // A state of another run (fewer particles, ids not a permutation) does not fit.
  Case small = c;
  small.model.radius.resize(50);
  small.x0.resize(100);
  Engine other(small.model, small.forces, o, small.x0);
  ExpectInputError([&] { other.RestoreState(e.SaveState()); }, "200 particles in 2D");
  EngineState bad = e.SaveState();
  bad.slot_ids[0] = bad.slot_ids[1];
  Engine fresh(c.model, c.forces, o, c.x0);
  ExpectInputError([&] { fresh.RestoreState(bad); }, "permutation");
}

}  // namespace
}  // namespace moreau::particles
