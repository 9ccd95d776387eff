// Dispatch over MPI ranks (built only with the CMake option MOREAU_MPI).
#ifdef MOREAU_WITH_MPI
// The C API only (OpenMPI and MPICH would otherwise pull in their deprecated C++ bindings).
#define OMPI_SKIP_MPICXX 1
#define MPICH_SKIP_MPICXX 1
#include <mpi.h>

#include <chrono>
#include <cstdlib>
#include <exception>
#include <string>
#include <thread>

#include "moreau/sweep/dispatch.h"
#include "sweep/run_queue.h"

namespace moreau::sweep {
namespace {

constexpr int kEntryTag = 1;  // worker → rank 0: the entry of the last run ("" at first)
constexpr int kRunTag = 2;    // rank 0 → worker: the next run number, −1 when none is left
// How long a waiting rank sleeps between two looks for a message: short against a run, long
// enough that waiting costs no core the runs need.
constexpr std::chrono::microseconds kPollInterval{200};

bool LaunchedByMpi() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK"}) {
    if (std::getenv(name) != nullptr) return true;
  }
  return false;
}

// Any rank but 0: ask, run, send the entry back with the next request.
void Work(const RunTask& task) {
  std::string entry;
  while (true) {
    MPI_Send(entry.data(), static_cast<int>(entry.size()), MPI_CHAR, 0, kEntryTag, MPI_COMM_WORLD);
    std::int64_t index = -1;
    MPI_Request request = MPI_REQUEST_NULL;
    MPI_Irecv(&index, 1, MPI_INT64_T, 0, kRunTag, MPI_COMM_WORLD, &request);
    for (int done = 0; MPI_Test(&request, &done, MPI_STATUS_IGNORE) == MPI_SUCCESS && !done;) {
      std::this_thread::sleep_for(kPollInterval);  // rather than MPI_Recv's busy wait
    }
    if (index < 0) return;
    entry = task(index).dump();
  }
}

// Rank 0's main thread: answer each request with the next run (polled, so that the thread
// sleeps between messages instead of spinning on a core the runs need).
void Serve(RunQueue& queue, int workers, const RunFinished& finished) {
  while (workers > 0) {
    int ready = 0;
    MPI_Status status;
    MPI_Iprobe(MPI_ANY_SOURCE, kEntryTag, MPI_COMM_WORLD, &ready, &status);
    if (ready == 0) {
      std::this_thread::sleep_for(kPollInterval);
      continue;
    }
    int size = 0;
    MPI_Get_count(&status, MPI_CHAR, &size);
    std::string text(static_cast<std::size_t>(size), '\0');
    MPI_Recv(text.data(), size, MPI_CHAR, status.MPI_SOURCE, kEntryTag, MPI_COMM_WORLD,
             MPI_STATUS_IGNORE);
    if (!text.empty()) {
      const std::lock_guard lock(queue.finished_mutex);
      finished(nlohmann::json::parse(text));
    }
    const std::int64_t next = queue.Pop();
    MPI_Send(&next, 1, MPI_INT64_T, status.MPI_SOURCE, kRunTag, MPI_COMM_WORLD);
    if (next < 0) --workers;
  }
}

}  // namespace

MpiSession::MpiSession() {
  if (!LaunchedByMpi()) return;
  int provided = 0;
  MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided);
  active_ = true;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &size_);
}

MpiSession::~MpiSession() {
  if (!active_) return;
  if (std::uncaught_exceptions() > 0) MPI_Abort(MPI_COMM_WORLD, 1);
  MPI_Finalize();
}

bool MpiSession::BuiltWithMpi() { return true; }

void Dispatch(const MpiSession& session, const std::vector<std::int64_t>& todo, int jobs,
              const RunTask& task, const RunFinished& finished) {
  if (session.rank() != 0) {
    Work(task);
    return;
  }
  RunQueue queue(todo);
  std::exception_ptr error;
  std::jthread local([&] {
    try {
      RunQueueWorkers(queue, jobs, task, finished);
    } catch (...) {
      error = std::current_exception();
    }
  });
  Serve(queue, session.size() - 1, finished);
  local.join();
  if (error) std::rethrow_exception(error);
}

}  // namespace moreau::sweep
#endif
