// Dispatch over MPI ranks (built only with the CMake option MOREAU_MPI).
#ifdef MOREAU_WITH_MPI
// The C API only (OpenMPI and MPICH would otherwise pull in their deprecated C++ bindings).
#define OMPI_SKIP_MPICXX 1
#define MPICH_SKIP_MPICXX 1
#include <mpi.h>

#include <cstdlib>
#include <exception>
#include <numeric>
#include <sstream>
#include <string>

#include "moreau/common/summary_json.h"
#include "moreau/sweep/dispatch.h"
#include "sweep/run_queue.h"

namespace moreau::sweep {
namespace {

bool LaunchedByMpi() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK"}) {
    if (std::getenv(name) != nullptr) return true;
  }
  return false;
}

// The position of the next run to hand out: one int64 in rank 0's window, advanced by each
// claim. Collective to create and to free.
class SharedRunCounter {
 public:
  explicit SharedRunCounter(int rank) {
    const MPI_Aint bytes = rank == 0 ? sizeof(std::int64_t) : 0;
    MPI_Win_allocate(bytes, sizeof(std::int64_t), MPI_INFO_NULL, MPI_COMM_WORLD, &value_, &window_);
    if (rank == 0) {
      MPI_Win_lock(MPI_LOCK_EXCLUSIVE, 0, 0, window_);
      *value_ = 0;
      MPI_Win_unlock(0, window_);
    }
    MPI_Barrier(MPI_COMM_WORLD);  // nobody claims before the counter is 0
    MPI_Win_lock_all(MPI_MODE_NOCHECK, window_);
  }
  ~SharedRunCounter() {
    // While an exception leaves, the other ranks may never get here: MpiSession aborts instead.
    if (std::uncaught_exceptions() > 0) return;
    MPI_Win_unlock_all(window_);
    MPI_Win_free(&window_);
  }
  SharedRunCounter(const SharedRunCounter&) = delete;
  SharedRunCounter& operator=(const SharedRunCounter&) = delete;

  std::int64_t Claim() {
    const std::int64_t one = 1;
    std::int64_t position = 0;
    MPI_Fetch_and_op(&one, &position, MPI_INT64_T, 0, 0, MPI_SUM, window_);
    MPI_Win_flush(0, window_);
    return position;
  }

 private:
  std::int64_t* value_ = nullptr;
  MPI_Win window_ = MPI_WIN_NULL;
};

std::vector<std::int64_t> BroadcastTodo(std::vector<std::int64_t> todo) {
  auto count = static_cast<std::int64_t>(todo.size());
  MPI_Bcast(&count, 1, MPI_INT64_T, 0, MPI_COMM_WORLD);
  todo.resize(static_cast<std::size_t>(count));
  MPI_Bcast(todo.data(), static_cast<int>(count), MPI_INT64_T, 0, MPI_COMM_WORLD);
  return todo;
}

// Every rank's entries on rank 0, rank by rank, sent as lines of JSON text.
std::vector<nlohmann::json> GatherEntries(const std::vector<nlohmann::json>& mine,
                                          const MpiSession& session) {
  std::string text;
  for (const nlohmann::json& entry : mine) text += JsonText(entry, -1) + "\n";
  int length = static_cast<int>(text.size());
  const bool root = session.rank() == 0;
  std::vector<int> lengths(root ? static_cast<std::size_t>(session.size()) : 0);
  MPI_Gather(&length, 1, MPI_INT, lengths.data(), 1, MPI_INT, 0, MPI_COMM_WORLD);
  std::vector<int> offsets(lengths.size(), 0);
  if (root) std::exclusive_scan(lengths.begin(), lengths.end(), offsets.begin(), 0);
  std::string all(root ? static_cast<std::size_t>(offsets.back() + lengths.back()) : 0, '\0');
  MPI_Gatherv(text.data(), length, MPI_CHAR, all.data(), lengths.data(), offsets.data(), MPI_CHAR,
              0, MPI_COMM_WORLD);
  std::vector<nlohmann::json> entries;
  std::istringstream lines(all);
  for (std::string line; std::getline(lines, line);) entries.push_back(nlohmann::json::parse(line));
  return entries;
}

}  // namespace

MpiSession::MpiSession() {
  if (!LaunchedByMpi()) return;
  int provided = 0;
  // Worker threads claim runs one at a time (under the queue's lock): serialized calls.
  MPI_Init_thread(nullptr, nullptr, MPI_THREAD_SERIALIZED, &provided);
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

void MpiSession::Abort(int code) const {
  if (active_) MPI_Abort(MPI_COMM_WORLD, code);
  std::exit(code);
}

std::vector<nlohmann::json> Dispatch(const MpiSession& session,
                                     const std::vector<std::int64_t>& todo, int jobs,
                                     const RunTask& task, const RunFinished& finished) {
  if (!session.active()) {
    RunQueue queue(todo);
    return RunQueueWorkers(queue, jobs, task, finished);
  }
  SharedRunCounter counter(session.rank());
  RunQueue queue(BroadcastTodo(todo), [&counter] { return counter.Claim(); });
  const std::vector<nlohmann::json> mine = RunQueueWorkers(queue, jobs, task, finished);
  return GatherEntries(mine, session);
}

}  // namespace moreau::sweep
#endif
