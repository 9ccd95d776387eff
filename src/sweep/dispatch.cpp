#include "moreau/sweep/dispatch.h"

#include <cstdlib>
#include <exception>
#include <mutex>
#include <thread>

#include <fmt/format.h>

#include "moreau/common/error.h"
#include "moreau/common/stop.h"
#include "sweep/run_queue.h"

namespace moreau::sweep {

std::vector<nlohmann::json> RunQueueWorkers(RunQueue& queue, int jobs, const RunTask& task,
                                            const RunFinished& finished) {
  std::vector<nlohmann::json> entries;
  std::exception_ptr error;
  const auto work = [&] {
    for (std::int64_t index = queue.Pop(); index >= 0; index = queue.Pop()) {
      nlohmann::json entry = task(index);
      const std::lock_guard lock(queue.finished_mutex);
      if (error) return;
      try {
        finished(entry);
        entries.push_back(std::move(entry));
      } catch (...) {
        error = std::current_exception();
        queue.Close();
        return;
      }
    }
  };
  if (jobs <= 1) {
    work();
  } else {
    std::vector<std::jthread> threads;
    for (int j = 0; j < jobs; ++j) threads.emplace_back(work);
  }
  if (error) std::rethrow_exception(error);
  return entries;
}

std::int64_t RunQueue::Pop() {
  const std::lock_guard lock(mutex_);
  if (closed_ || StopRequested()) return -1;  // after a stop request no run starts
  const std::int64_t position = claim_ ? claim_() : next_++;
  if (position >= static_cast<std::int64_t>(todo_.size())) {
    closed_ = true;  // every later claim would be past the end too
    return -1;
  }
  return todo_[static_cast<std::size_t>(position)];
}

void RunQueue::Close() {
  const std::lock_guard lock(mutex_);
  closed_ = true;
}

void CheckJobs(int jobs) {
  if (jobs < 1 || jobs > kMaxJobs) {
    throw InputError("--jobs", fmt::format("must be between 1 and {} (got {})", kMaxJobs, jobs));
  }
}

#ifndef MOREAU_WITH_MPI
MpiSession::MpiSession() {
  // Started as one of several ranks, every copy would do every run: refuse.
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE"}) {
    const char* size = std::getenv(name);
    if (size != nullptr && std::atoi(size) > 1) {
      throw InputError(
          fmt::format("{} = {}: this moreau was built without MPI (CMake option "
                      "MOREAU_MPI=OFF); run it without mpirun, or build it with MPI",
                      name, size));
    }
  }
}
MpiSession::~MpiSession() = default;
bool MpiSession::BuiltWithMpi() { return false; }
void MpiSession::Abort(int code) const { std::exit(code); }

std::vector<nlohmann::json> Dispatch(const MpiSession& /*session*/,
                                     const std::vector<std::int64_t>& todo, int jobs,
                                     const RunTask& task, const RunFinished& finished) {
  RunQueue queue(todo);
  return RunQueueWorkers(queue, jobs, task, finished);
}
#endif

}  // namespace moreau::sweep
