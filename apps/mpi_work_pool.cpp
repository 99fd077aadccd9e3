// The WorkPool of an MPI job (apps/work_pool.hpp). Rank 0 coordinates: every other rank asks it
// for a task, runs it and sends the result back with its next request, so a rank that finishes
// early is handed more (a master-worker scheme with dynamic scheduling). Messages are byte
// strings: [kind, task] as two 64-bit words, then the result or the error text.
#include <mpi.h>

#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <new>
#include <string>
#include <thread>
#include <unordered_map>

#include "apps/work_pool.hpp"

namespace tumble::app {
namespace {

constexpr int kRequestTag = 1;  // worker to coordinator: a result (or none yet) and a request
constexpr int kAssignTag = 2;   // coordinator to worker: a task index, or kStop
constexpr std::uint64_t kStop = ~std::uint64_t{0};

enum Kind : std::uint64_t { first_request = 0, result = 1, failure = 2 };

// How many processes the launcher says it started (0 when it does not say).
int launcher_size() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "SLURM_NTASKS"}) {
    if (const char* value = std::getenv(name))
      return std::atoi(value);
  }
  return 0;
}

std::string message(Kind kind, std::uint64_t task, const std::string& payload) {
  std::string bytes(2 * sizeof(std::uint64_t), '\0');
  const std::uint64_t head[2] = {kind, task};
  std::memcpy(bytes.data(), head, sizeof head);
  bytes += payload;
  return bytes;
}

class MpiWorkPool final : public WorkPool {
 public:
  MpiWorkPool() {
    int provided = 0;
    // Only the main thread calls MPI; the worlds' own threads (oneTBB) never do.
    MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided);
    MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
    MPI_Comm_size(MPI_COMM_WORLD, &ranks_);
    // A launcher of another MPI (MPICH's mpiexec starting an Open MPI build, or the reverse)
    // starts N processes that each see a world of one: every one would run the whole job into
    // the same directory. Refuse instead.
    const int launched = launcher_size();
    if (launched > 1 && ranks_ == 1) {
      MPI_Finalize();
      throw WorkError("started as one of " + std::to_string(launched) +
                      " processes, but MPI sees a world of one: the launcher is not of the MPI "
                      "this build uses (Open MPI's mpirun for an Open MPI build)");
    }
  }
  ~MpiWorkPool() override { MPI_Finalize(); }
  MpiWorkPool(const MpiWorkPool&) = delete;
  MpiWorkPool& operator=(const MpiWorkPool&) = delete;

  int rank() const override { return rank_; }
  int ranks() const override { return ranks_; }

  std::vector<std::string> run(std::span<const std::size_t> order,
                               const std::function<std::string(std::size_t)>& task) override {
    if (ranks_ == 1) {
      return run_tasks_here(order, task, "rank 0: ");
    }
    if (rank_ == 0) {
      return coordinate(order);
    }
    work(task);
    return {};
  }

  std::string agree(const std::string& text) override {
    std::uint64_t size = text.size();
    MPI_Bcast(&size, 1, MPI_UINT64_T, 0, MPI_COMM_WORLD);
    std::string agreed(size, '\0');
    if (rank_ == 0) {
      agreed = text;
    }
    MPI_Bcast(agreed.data(), static_cast<int>(size), MPI_CHAR, 0, MPI_COMM_WORLD);
    return agreed;
  }

 private:
  std::vector<std::string> coordinate(std::span<const std::size_t> order) {
    std::vector<std::string> results(order.size());
    std::unordered_map<std::size_t, std::size_t> slot;
    for (std::size_t k = 0; k < order.size(); ++k) {
      slot.emplace(order[k], k);
    }
    std::size_t next = 0;
    int working = ranks_ - 1;
    std::string error;
    std::string bytes;
    while (working > 0) {
      int arrived = 0;
      MPI_Status status;
      MPI_Iprobe(MPI_ANY_SOURCE, kRequestTag, MPI_COMM_WORLD, &arrived, &status);
      if (!arrived) {
        // A blocking receive would spin a core for the whole job; the coordinator's core is
        // better left to a worker (a pause here delays a hand-out by at most this much).
        std::this_thread::sleep_for(std::chrono::microseconds(200));
        continue;
      }
      int size = 0;
      MPI_Get_count(&status, MPI_BYTE, &size);
      bytes.resize(static_cast<std::size_t>(size));
      MPI_Recv(bytes.data(), size, MPI_BYTE, status.MPI_SOURCE, kRequestTag, MPI_COMM_WORLD,
               MPI_STATUS_IGNORE);
      std::uint64_t head[2] = {0, 0};
      std::memcpy(head, bytes.data(), sizeof head);
      std::string payload = bytes.substr(sizeof head);
      if (head[0] == result) {
        results[slot.at(head[1])] = std::move(payload);
      } else if (head[0] == failure && error.empty()) {
        error = "rank " + std::to_string(status.MPI_SOURCE) + ": task " + std::to_string(head[1]) +
                ": " + payload;
      }
      std::uint64_t assignment = kStop;
      if (error.empty() && next < order.size()) {
        assignment = order[next++];
      } else {
        --working;
      }
      MPI_Send(&assignment, 1, MPI_UINT64_T, status.MPI_SOURCE, kAssignTag, MPI_COMM_WORLD);
    }
    if (!error.empty()) {
      throw WorkError(error);
    }
    return results;
  }

  void work(const std::function<std::string(std::size_t)>& task) {
    std::string out = message(first_request, 0, "");
    for (;;) {
      MPI_Send(out.data(), static_cast<int>(out.size()), MPI_BYTE, 0, kRequestTag, MPI_COMM_WORLD);
      std::uint64_t assignment = kStop;
      MPI_Recv(&assignment, 1, MPI_UINT64_T, 0, kAssignTag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
      if (assignment == kStop) {
        return;
      }
      try {
        out = message(result, assignment, task(static_cast<std::size_t>(assignment)));
      } catch (const std::bad_alloc&) {
        out = message(failure, assignment, "out of memory");
      } catch (const std::exception& e) {
        out = message(failure, assignment, e.what());
      }
    }
  }

  int rank_ = 0;
  int ranks_ = 1;
};

}  // namespace

std::unique_ptr<WorkPool> make_mpi_work_pool() {
  return std::make_unique<MpiWorkPool>();
}

}  // namespace tumble::app
