// The one-process WorkPool, and the choice between it and MPI's.
#include "apps/work_pool.hpp"

#include <cstdlib>
#include <new>

namespace tumble::app {

std::unique_ptr<WorkPool> make_mpi_work_pool();  // mpi_work_pool.cpp, when built with MPI

namespace {

class LocalWorkPool final : public WorkPool {
 public:
  int rank() const override { return 0; }
  int ranks() const override { return 1; }
  std::vector<std::string> run(std::span<const std::size_t> order,
                               const std::function<std::string(std::size_t)>& task) override {
    return run_tasks_here(order, task, "");
  }
  std::string agree(const std::string& message) override { return message; }
};

// The variables MPI launchers set in the processes they start: Open MPI's mpirun, MPICH's and
// Intel's Hydra (PMI), and Slurm's srun with PMIx or PMI-2.
bool launched_by_mpi() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK", "PMI_RANK"}) {
    if (std::getenv(name) != nullptr) {
      return true;
    }
  }
  return false;
}

}  // namespace

std::vector<std::string> run_tasks_here(std::span<const std::size_t> order,
                                        const std::function<std::string(std::size_t)>& task,
                                        const std::string& who) {
  std::vector<std::string> results;
  results.reserve(order.size());
  for (const std::size_t i : order) {
    try {
      results.push_back(task(i));
    } catch (const std::bad_alloc&) {
      throw;  // reported as running out of memory, not as a fault of the task
    } catch (const std::exception& e) {
      throw WorkError(who + "task " + std::to_string(i) + ": " + e.what());
    }
  }
  return results;
}

bool mpi_available() {
#ifdef TUMBLE_HAVE_MPI
  return true;
#else
  return false;
#endif
}

std::unique_ptr<WorkPool> make_work_pool() {
  if (!launched_by_mpi()) {
    return std::make_unique<LocalWorkPool>();
  }
#ifdef TUMBLE_HAVE_MPI
  return make_mpi_work_pool();
#else
  throw WorkError(
      "started by an MPI launcher, but this build has no MPI: every rank would run the whole "
      "job. Install Open MPI (libopenmpi-dev) and configure with -DTUMBLE_WITH_MPI=ON, or run "
      "without mpirun");
#endif
}

}  // namespace tumble::app
