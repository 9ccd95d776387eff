// Handing out the runs of a sweep: a pool of threads in one process, or MPI ranks.
//
// Runs differ in cost by orders of magnitude, so no run is assigned ahead: whichever worker is
// free takes the next one (dynamic load balancing). Under MPI, rank 0 hands out run numbers on
// request and works on runs itself with its own threads; every other rank asks for the next run
// when it has sent back the entry of the last. Only rank 0 sees the finished entries, so only
// rank 0 writes. Each run may use OpenMP threads of its own.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include <nlohmann/json.hpp>

namespace moreau::sweep {

// Does run `index` and returns its journal entry (an object). Must not throw. Called from
// `jobs` threads at once when jobs > 1.
using RunTask = std::function<nlohmann::json(std::int64_t index)>;
// Takes a finished run's entry; called one call at a time, on rank 0 only, in the order the
// runs finish. May throw (e.g. when the journal cannot be written): the sweep stops.
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
  bool active() const { return active_; }
  int rank() const { return rank_; }
  int size() const { return size_; }

 private:
  bool active_ = false;
  int rank_ = 0;
  int size_ = 1;
};

// Runs every index of `todo` (each exactly once) on the session's ranks, `jobs` ≥ 1 threads
// each; every rank calls it with the same arguments. Returns when all runs are finished.
void Dispatch(const MpiSession& session, const std::vector<std::int64_t>& todo, int jobs,
              const RunTask& task, const RunFinished& finished);

}  // namespace moreau::sweep
