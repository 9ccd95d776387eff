// The sweep journal: entries appended are read back; a line cut short by a kill is skipped; a
// folder's journals (one per MPI rank) are read together.
#include "moreau/sweep/journal.h"

#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

namespace moreau::sweep {
namespace {

namespace fs = std::filesystem;

fs::path FreshPath(const std::string& name) {
  const fs::path path = fs::temp_directory_path() / ("moreau_journal_test_" + name + ".jsonl");
  fs::remove(path);
  return path;
}

TEST(SweepJournal, AppendedEntriesReadBackByHash) {
  const fs::path path = FreshPath("append");
  EXPECT_TRUE(Journal::Read(path).empty());  // absent: nothing finished
  {
    Journal journal(path);
    journal.Append({{"hash", "aa"}, {"row", {{"status", "completed"}, {"x", 0.1}}}});
    journal.Append({{"hash", "bb"}, {"row", {{"status", "input_error"}}}});
  }
  {
    Journal reopened(path);  // appends, keeps what is there
    reopened.Append({{"hash", "cc"}, {"row", {{"x", 3}}}});
  }
  const auto entries = Journal::Read(path);
  ASSERT_EQ(entries.size(), 3U);
  EXPECT_EQ(entries.at("aa")["row"]["x"].get<double>(), 0.1);
  EXPECT_EQ(entries.at("bb")["row"]["status"], "input_error");
  EXPECT_EQ(entries.at("cc")["row"]["x"], 3);
  fs::remove(path);
}

TEST(SweepJournal, LineCutShortIsSkippedAndEndedOnRestartForeignLinesSkippedLastOfAHashWins) {
  const fs::path path = FreshPath("cut");
  {
    Journal journal(path);
    journal.Append({{"hash", "aa"}, {"row", {{"x", 1}}}});
    journal.Append({{"hash", "aa"}, {"row", {{"x", 2}}}});
  }
  {
    std::ofstream out(path, std::ios::app);
    out << "[1, 2]\n{\"row\": {}}\n{\"hash\": \"bb\", \"row\": {\"x\"";  // no newline: killed
  }
  auto entries = Journal::Read(path);
  ASSERT_EQ(entries.size(), 1U);
  EXPECT_EQ(entries.at("aa")["row"]["x"], 2);
  {
    Journal restarted(path);
    restarted.Append({{"hash", "bb"}, {"row", {{"x", 4}}}});
  }
  entries = Journal::Read(path);
  ASSERT_EQ(entries.size(), 2U);
  EXPECT_EQ(entries.at("bb")["row"]["x"], 4);
  fs::remove(path);
}

TEST(SweepJournal, FolderReadsTheJournalOfEveryRankAndNothingElse) {
  const fs::path dir = fs::temp_directory_path() / "moreau_journal_test_folder";
  fs::remove_all(dir);
  EXPECT_TRUE(Journal::ReadFolder(dir).empty());  // no folder: nothing finished
  fs::create_directories(dir);
  EXPECT_EQ(Journal::PathFor(dir, 0), dir / "journal.jsonl");
  EXPECT_EQ(Journal::PathFor(dir, 3), dir / "journal.rank3.jsonl");
  Journal(Journal::PathFor(dir, 0)).Append({{"hash", "aa"}, {"row", {{"x", 1}}}});
  Journal(Journal::PathFor(dir, 3)).Append({{"hash", "bb"}, {"row", {{"x", 2}}}});
  Journal(dir / "other.jsonl").Append({{"hash", "cc"}, {"row", {{"x", 3}}}});
  const auto entries = Journal::ReadFolder(dir);
  ASSERT_EQ(entries.size(), 2U);
  EXPECT_EQ(entries.at("aa")["row"]["x"], 1);
  EXPECT_EQ(entries.at("bb")["row"]["x"], 2);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace moreau::sweep
