// The runs still to hand out, shared by the worker threads of one process (and, on MPI rank 0,
// by the thread that serves the other ranks).
#pragma once

#include <cstdint>
#include <mutex>
#include <vector>

#include "moreau/sweep/dispatch.h"

namespace moreau::sweep {

class RunQueue {
 public:
  explicit RunQueue(std::vector<std::int64_t> todo) : todo_(std::move(todo)) {}
  // The next run, or −1 when none is left.
  std::int64_t Pop();
  // Hands out nothing more (after an error).
  void Close();

  std::mutex finished_mutex;  // one `finished` call at a time

 private:
  std::mutex mutex_;
  std::vector<std::int64_t> todo_;
  std::size_t next_ = 0;
};

// `jobs` threads (the calling one when jobs ≤ 1) take runs from `queue` until it is empty; each
// entry goes to `finished` under queue.finished_mutex. Rethrows the first exception of
// `finished` once every thread has stopped.
void RunQueueWorkers(RunQueue& queue, int jobs, const RunTask& task, const RunFinished& finished);

}  // namespace moreau::sweep
