// The runs still to hand out, shared by the worker threads of one process. Positions in the
// list come from a local counter, or under MPI from the counter all ranks share.
#pragma once

#include <cstdint>
#include <functional>
#include <mutex>
#include <vector>

#include "moreau/sweep/dispatch.h"

namespace moreau::sweep {

class RunQueue {
 public:
  // `claim` returns the next unclaimed position in `todo` (called under the queue's lock);
  // empty: a counter of this process.
  explicit RunQueue(std::vector<std::int64_t> todo, std::function<std::int64_t()> claim = {})
      : todo_(std::move(todo)), claim_(std::move(claim)) {}
  // The next run, or −1 when none is left.
  std::int64_t Pop();
  // Hands out nothing more (after an error).
  void Close();

  std::mutex finished_mutex;  // one `finished` call at a time

 private:
  std::mutex mutex_;
  std::vector<std::int64_t> todo_;
  std::function<std::int64_t()> claim_;
  std::int64_t next_ = 0;
  bool closed_ = false;
};

// `jobs` threads (the calling one when jobs ≤ 1) take runs from `queue` until it is empty; each
// entry goes to `finished` under queue.finished_mutex. Returns the entries in the order they
// were finished; rethrows the first exception of `finished` once every thread has stopped.
std::vector<nlohmann::json> RunQueueWorkers(RunQueue& queue, int jobs, const RunTask& task,
                                            const RunFinished& finished);

}  // namespace moreau::sweep
