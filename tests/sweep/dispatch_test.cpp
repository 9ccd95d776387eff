// Handing out runs in one process (no MPI launcher): every run once, whatever the threads; an
// error of the finished-run callback stops the sweep and reaches the caller.
#include "moreau/sweep/dispatch.h"

#include <numeric>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

namespace moreau::sweep {
namespace {

TEST(SweepDispatch, EveryRunIsDoneOnceAndFinishedOnceForAnyNumberOfThreads) {
  const MpiSession session;  // not started by a launcher: one rank
  ASSERT_EQ(session.rank(), 0);
  ASSERT_EQ(session.size(), 1);
  std::vector<std::int64_t> todo(40);
  std::iota(todo.begin(), todo.end(), 100);
  for (const int jobs : {1, 3}) {
    std::vector<int> finished(140, 0);
    const std::vector<nlohmann::json> entries = Dispatch(
        session, todo, jobs,
        [](std::int64_t index) {
          return nlohmann::json{{"index", index}};
        },
        [&](const nlohmann::json& entry) { ++finished[entry["index"].get<std::size_t>()]; });
    for (std::size_t i = 0; i < finished.size(); ++i) {
      EXPECT_EQ(finished[i], i >= 100 ? 1 : 0) << "run " << i << ", jobs " << jobs;
    }
    // One process is rank 0: it returns every entry, each once.
    std::vector<int> returned(140, 0);
    for (const nlohmann::json& entry : entries) ++returned[entry["index"].get<std::size_t>()];
    EXPECT_EQ(returned, finished) << "jobs " << jobs;
  }
}

TEST(SweepDispatch, AnErrorWhileRecordingARunStopsTheSweepAndIsRethrown) {
  const MpiSession session;
  const std::vector<std::int64_t> todo{0, 1, 2, 3, 4, 5, 6, 7};
  for (const int jobs : {1, 2}) {
    int recorded = 0;
    EXPECT_THROW(Dispatch(
                     session, todo, jobs,
                     [](std::int64_t i) {
                       return nlohmann::json{{"i", i}};
                     },
                     [&](const nlohmann::json&) {
                       if (++recorded == 2) throw std::runtime_error("disk full");
                     }),
                 std::runtime_error);
    EXPECT_EQ(recorded, 2) << "jobs " << jobs;  // nothing recorded after the error
  }
}

}  // namespace
}  // namespace moreau::sweep
