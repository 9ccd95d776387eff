// Handing out the runs of a sweep: a pool of threads in one process, or MPI ranks.
//
// Runs differ in cost by orders of magnitude, so no run is assigned ahead: whichever worker is
// free takes the next one (dynamic load balancing). Under MPI the next run is the value of a
// counter in rank 0's memory that every rank advances with one atomic MPI_Fetch_and_op (an MPI
// one-sided window): no rank serves the others, and no thread polls for messages, so every core
// works on runs. Each rank records the runs it did as they finish (`finished`, e.g. into a
// journal of its own); their entries reach rank 0 once, at the end. Each run may use OpenMP
// threads of its own.
//
// Progress: within a node (and on networks with remote atomics: InfiniBand through UCX) the
// counter advances without rank 0's help. Over plain TCP, OpenMPI emulates the atomic with a
// message that rank 0 answers when it next enters MPI, i.e. between two of its runs.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include <nlohmann/json.hpp>

namespace moreau::sweep {

// Does run `index` and returns its journal entry (an object). Must not throw. Called from
// `jobs` threads at once when jobs > 1.
using RunTask = std::function<nlohmann::json(std::int64_t index)>;
// Takes a finished run's entry; called one call at a time per rank, on the rank that did the run,
// in the order its runs finish. May throw (e.g. when the journal cannot be written): the sweep
// stops (under MPI: MpiSession's destructor aborts every rank).
using RunFinished = std::function<void(const nlohmann::json& entry)>;

// An MPI environment for the lifetime of the object, when the process was started by an MPI
// launcher (mpirun, mpiexec, srun: it sets OMPI_COMM_WORLD_SIZE, PMI_SIZE or PMIX_RANK) and
// moreau was built with MPI (CMake option MOREAU_MPI); otherwise one rank and no MPI at all.
class MpiSession {
 public:
  // Without MPI, throws InputError when the launcher says there are several ranks.
  MpiSession();
  ~MpiSession();  // MPI_Finalize, or MPI_Abort while an exception leaves the scope
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;

  static bool BuiltWithMpi();
  // Ends every rank with exit code CODE (MPI_Abort; without MPI, std::exit).
  [[noreturn]] void Abort(int code) const;
  bool active() const { return active_; }
  int rank() const { return rank_; }
  int size() const { return size_; }

 private:
  bool active_ = false;
  int rank_ = 0;
  int size_ = 1;
};

// The most runs at a time in one process (`--jobs`): each is a thread.
constexpr int kMaxJobs = 1024;
// Throws InputError("--jobs", …) unless 1 ≤ jobs ≤ kMaxJobs.
void CheckJobs(int jobs);

// Runs every index of `todo` (each at most once) on the session's ranks, `jobs` ≥ 1 threads
// each; every rank calls it (`todo` is read on rank 0 only). Returns when all runs are finished:
// on rank 0 the entries of every run of every rank (each rank's in the order they finished, rank
// by rank), on the other ranks nothing. After a stop request (common/stop.h) no run starts on
// the rank that saw it: the runs not started have no entry.
std::vector<nlohmann::json> Dispatch(const MpiSession& session,
                                     const std::vector<std::int64_t>& todo, int jobs,
                                     const RunTask& task, const RunFinished& finished);

}  // namespace moreau::sweep
