#include "moreau/common/memory.h"

#include <gtest/gtest.h>

#include "moreau/common/error.h"

namespace moreau {
namespace {

TEST(FormatBytes, ChoosesABinaryUnitWithThreeSignificantDigits) {
  EXPECT_EQ(FormatBytes(0.0), "0 B");
  EXPECT_EQ(FormatBytes(812.0), "812 B");
  EXPECT_EQ(FormatBytes(1536.0), "1.50 KiB");
  EXPECT_EQ(FormatBytes(120.0 * 1024 * 1024), "120 MiB");
  EXPECT_EQ(FormatBytes(1.5 * 1024 * 1024 * 1024), "1.50 GiB");
  EXPECT_EQ(FormatBytes(20.0 * 1024 * 1024 * 1024 * 1024), "20.0 TiB");
}

TEST(MemoryFiles, ParsesMemAvailableAndCgroupValues) {
  const char* meminfo =
      "MemTotal:       16384000 kB\nMemFree:          100000 kB\nMemAvailable:    2048 kB\n";
  EXPECT_EQ(ParseMemAvailable(meminfo), std::int64_t{2048} * 1024);
  EXPECT_EQ(ParseMemAvailable("MemTotal: 5 kB\n"), std::nullopt);
  EXPECT_EQ(ParseCgroupBytes("1073741824\n"), std::int64_t{1} << 30);
  EXPECT_EQ(ParseCgroupBytes("max\n"), std::nullopt);
  EXPECT_EQ(ParseCgroupBytes(""), std::nullopt);
}

TEST(CheckMemory, NamesBothAmountsInReadableUnitsAndTheLimit) {
  try {
    CheckMemory("3 things", 3.0 * 1024 * 1024, 1024 * 1024);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_STREQ(
        e.what(),
        "3 things need about 3.00 MiB, more than the 1.00 MiB available (the memory limit)");
  }
  EXPECT_NO_THROW(CheckMemory("1 thing", 1024.0, 1024));
}

TEST(AvailableMemory, IsPositiveAndNamesItsSource) {
  // The limits themselves (ulimit -v, cgroup) are tested end to end in
  // tests/cli/test_limits_cli.py.
  const MemoryLimit limit = AvailableMemory();
  EXPECT_GT(limit.bytes, 0);
  EXPECT_FALSE(limit.source.empty());
}

}  // namespace
}  // namespace moreau
