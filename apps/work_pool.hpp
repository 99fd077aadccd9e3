// Numbered tasks run in this process or spread over the ranks of an MPI job (docs/scale-out.md).
// Every rank runs the same program and calls the same methods with the same arguments; in an MPI
// job rank 0 only coordinates: it hands the tasks out one at a time, in the order given, to
// whichever rank asks next (dynamic scheduling: a slow rank simply takes fewer), and gathers each
// task's result. The results do not depend on which rank ran what, so a job gives the same
// results on any number of ranks as in one process.
#pragma once

#include <cstddef>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace tumble::app {

// A task that failed on some rank: what() names the rank and the task.
struct WorkError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class WorkPool {
 public:
  virtual ~WorkPool() = default;
  virtual int rank() const = 0;
  virtual int ranks() const = 0;
  bool is_coordinator() const { return rank() == 0; }

  // Runs task(i) for every i of `order` (the coordinator hands them out in that order: longest
  // first keeps the ranks busy to the end). On the coordinator, returns every task's result
  // indexed like `order`; elsewhere an empty vector. A task that throws stops the hand-out: the
  // coordinator throws WorkError with the rank, the task and the message, the others return.
  virtual std::vector<std::string> run(std::span<const std::size_t> order,
                                       const std::function<std::string(std::size_t)>& task) = 0;

  // The coordinator's `message` on every rank: empty when the coordinator found the inputs
  // good, else why it stops (the others then stop too, without printing it again).
  virtual std::string agree(const std::string& message) = 0;
};

// Every task of `order` in turn in this process, results in that order; a task that throws
// becomes WorkError with `who` ("" or "rank 0: "), the task and the message.
std::vector<std::string> run_tasks_here(std::span<const std::size_t> order,
                                        const std::function<std::string(std::size_t)>& task,
                                        const std::string& who);

// MPI when this process was started by an MPI launcher (mpirun, mpiexec, srun) and the build has
// MPI; one process otherwise. Throws WorkError when launched by MPI into a build without it.
std::unique_ptr<WorkPool> make_work_pool();

// Whether this build can spread work over MPI ranks.
bool mpi_available();

}  // namespace tumble::app
