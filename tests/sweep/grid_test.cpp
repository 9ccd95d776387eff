// Parameter grids: the runs of crossed and zipped axes with seeds, their identity, bad grids.
#include "moreau/sweep/grid.h"

#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "moreau/common/error.h"

namespace moreau::sweep {
namespace {

std::vector<std::string> Values(const std::vector<Setting>& settings) {
  std::vector<std::string> values;
  for (const Setting& s : settings) values.push_back(s.value);
  return values;
}

Grid CrossedGrid() {
  Grid grid;
  grid.axes = {{"room.door_width", {"0.8", "1.2"}}, {"solver.method", {"'a'", "'b'", "'c'"}}};
  grid.seeds = {5, 6};
  return grid;
}

TEST(SweepGrid, CrossedAxesGiveEveryCombinationOnceLastAxisThenSeedFastest) {
  const Grid grid = CrossedGrid();
  ASSERT_EQ(grid.RunCount(), 12);
  EXPECT_EQ(Values(grid.Run(0)), (std::vector<std::string>{"0.8", "'a'", "5"}));
  EXPECT_EQ(Values(grid.Run(1)), (std::vector<std::string>{"0.8", "'a'", "6"}));
  EXPECT_EQ(Values(grid.Run(2)), (std::vector<std::string>{"0.8", "'b'", "5"}));
  EXPECT_EQ(Values(grid.Run(6)), (std::vector<std::string>{"1.2", "'a'", "5"}));
  EXPECT_EQ(Values(grid.Run(11)), (std::vector<std::string>{"1.2", "'c'", "6"}));
  std::set<std::vector<std::string>> seen;
  for (std::int64_t i = 0; i < grid.RunCount(); ++i) {
    const std::vector<Setting> run = grid.Run(i);
    ASSERT_EQ(run.size(), 3U);
    EXPECT_EQ(run[0].key, "room.door_width");
    EXPECT_EQ(run[1].key, "solver.method");
    EXPECT_EQ(run[2].key, "problem.seed");
    seen.insert(Values(run));
  }
  EXPECT_EQ(seen.size(), 12U);
}

TEST(SweepGrid, ZippedAxesPairTheirValues) {
  Grid grid;
  grid.combination = Combination::kZip;
  grid.axes = {{"a", {"1", "2", "3"}}, {"b", {"4", "5", "6"}}};
  ASSERT_EQ(grid.RunCount(), 3);
  for (std::int64_t i = 0; i < 3; ++i) {
    EXPECT_EQ(Values(grid.Run(i)),
              (std::vector<std::string>{std::to_string(i + 1), std::to_string(i + 4)}));
  }
}

TEST(SweepGrid, NoAxesAndNoSeedsIsOneRunWithoutSettings) {
  const Grid grid;
  EXPECT_EQ(grid.RunCount(), 1);
  EXPECT_TRUE(grid.Run(0).empty());
}

TEST(SweepGrid, ValidateRejectsBadGrids) {
  Grid empty_axis;
  empty_axis.axes = {{"a", {}}};
  EXPECT_THROW(empty_axis.Validate(), InputError);
  Grid twice;
  twice.axes = {{"a", {"1"}}, {"a", {"2"}}};
  EXPECT_THROW(twice.Validate(), InputError);
  Grid zip;
  zip.combination = Combination::kZip;
  zip.axes = {{"a", {"1", "2"}}, {"b", {"1"}}};
  EXPECT_THROW(zip.Validate(), InputError);
  Grid seed_axis;
  seed_axis.axes = {{"problem.seed", {"1"}}};
  seed_axis.seeds = {1};
  EXPECT_THROW(seed_axis.Validate(), InputError);
  Grid seeds_twice;
  seeds_twice.seeds = {3, 3};
  EXPECT_THROW(seeds_twice.Validate(), InputError);
  EXPECT_NO_THROW(CrossedGrid().Validate());
  EXPECT_THROW(ParseCombination("product"), InputError);
  EXPECT_EQ(ParseCombination(CombinationName(Combination::kZip)), Combination::kZip);
}

TEST(SweepGrid, RunHashDependsOnSettingsAndContextNotOnTheirOrder) {
  const std::vector<Setting> ab{{"a", "1"}, {"b", "2"}};
  const std::vector<Setting> ba{{"b", "2"}, {"a", "1"}};
  const std::string h = RunHash("base", ab);
  EXPECT_EQ(h.size(), 16U);
  EXPECT_EQ(h.find_first_not_of("0123456789abcdef"), std::string::npos);
  EXPECT_EQ(RunHash("base", ba), h);
  EXPECT_NE(RunHash("other base", ab), h);
  EXPECT_NE(RunHash("base", {{"a", "1"}, {"b", "3"}}), h);
  EXPECT_NE(RunHash("base", {{"a", "1"}}), h);
}

}  // namespace
}  // namespace moreau::sweep
